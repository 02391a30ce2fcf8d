//! The environment file: defaults, every key, resolving meshes through the
//! caller's loader, and the example files.

use genform_core::scene::{Primitive, Tessellation, unit_mesh};
use genform_core::{Mesh, SourceFile};
use genform_hemls::{
    Axis, Behaviour, BoundarySpec, Charge, ChargeKind, EnvSpec, Environment, Gravity, GrowthLimits, Keep, Settings,
    Shape, ShapeSpec, parse_env,
};
use glam::DVec3;

fn parse(text: &str) -> EnvSpec {
    parse_env(&SourceFile::new("test.toml", text)).unwrap_or_else(|d| panic!("{}", d.short()))
}

#[test]
fn an_empty_file_gives_genr8_defaults() {
    for text in ["", "# nothing here\n\n"] {
        let spec = parse(text);
        assert_eq!(spec, EnvSpec::default());
        assert_eq!(spec.settings, Settings::default());
        assert_eq!(spec.settings.steps, 4);
        assert_eq!(spec.settings.scale, DVec3::splat(1.5));
        assert_eq!((spec.settings.branch_angle, spec.settings.branch_length), (30.0, -1.0));
        let (settings, env) = spec.resolve(&mut |_| panic!("no meshes")).unwrap();
        assert_eq!(settings, Settings::default());
        assert!(env.is_empty());
    }
}

#[test]
fn every_key_is_parsed() {
    let spec = parse(
        r#"
steps = 3
scale = [1.2, 1.3, 0x1]
start_length = 2
start_position = [1, -2, 0.5]
fixed_center = true
fixed_perimeter = true
branch_angle = 45.5
branch_length = 1.25
join = "cone"
gravity = { axis = "y", magnitude = -0.25 }
min_distance = 0.01

[[attractor]]
position = [0, 0, 3]

[[repeller]]
position = [1, 1, -1]
strength = 0.5
exponent = 3

[[attractor]]
position = [2, 0, 0]
strength = 2
exponent = 1

[[boundary]]
sphere = { center = [0, 0, -2], radius = 1.5 }

[[boundary]]
box = { min = [-5, -5, -5], max = [5, 5, 5] }
behaviour = "stop"
keep = "inside"

[[boundary]]
plane = { point = [0, 0, -3], normal = [0, 0, 2] }
behaviour = "soft"
keep = "outside"

[[boundary]]
mesh = "meshes/rock.obj"

[limits]
max_vertices = 1000
max_edges = 2000
max_faces = 500
"#,
    );
    let s = &spec.settings;
    assert_eq!(s.steps, 3);
    assert_eq!(s.scale, DVec3::new(1.2, 1.3, 1.0));
    assert_eq!(s.start_length, 2.0);
    assert_eq!(s.start_position, DVec3::new(1.0, -2.0, 0.5));
    assert!(s.fixed_center && s.fixed_perimeter);
    assert_eq!((s.branch_angle, s.branch_length), (45.5, 1.25));
    assert_eq!(s.join, genform_hemls::JoinTest::Cone);
    assert_eq!(s.limits, GrowthLimits { max_vertices: 1000, max_edges: 2000, max_faces: 500 });
    assert_eq!(spec.gravity, Some(Gravity::new(Axis::Y, -0.25)));
    assert_eq!(spec.min_distance, 0.01);
    // Attractors first, then repellers, each in file order; defaults c = 1, e = 2.
    assert_eq!(
        spec.charges,
        vec![
            Charge::attractor(DVec3::new(0.0, 0.0, 3.0)),
            Charge::attractor(DVec3::new(2.0, 0.0, 0.0)).with_strength(2.0).with_exponent(1.0),
            Charge::repeller(DVec3::new(1.0, 1.0, -1.0)).with_strength(0.5).with_exponent(3.0),
        ]
    );
    assert_eq!(
        spec.boundaries,
        vec![
            BoundarySpec {
                shape: ShapeSpec::Sphere { center: DVec3::new(0.0, 0.0, -2.0), radius: 1.5 },
                behaviour: Behaviour::Slide,
                keep: Keep::Outside,
            },
            BoundarySpec {
                shape: ShapeSpec::Box { min: DVec3::splat(-5.0), max: DVec3::splat(5.0) },
                behaviour: Behaviour::Stop,
                keep: Keep::Inside,
            },
            BoundarySpec {
                shape: ShapeSpec::Plane { point: DVec3::new(0.0, 0.0, -3.0), normal: DVec3::new(0.0, 0.0, 2.0) },
                behaviour: Behaviour::Soft,
                keep: Keep::Outside,
            },
            BoundarySpec {
                shape: ShapeSpec::Mesh { path: "meshes/rock.obj".into(), at: "test.toml:41:8".into() },
                behaviour: Behaviour::Slide,
                keep: Keep::Outside,
            },
        ]
    );
    assert_eq!(spec.mesh_paths().collect::<Vec<_>>(), vec!["meshes/rock.obj"]);

    // Resolving loads the mesh through the caller and keeps every setting.
    let mut asked = Vec::new();
    let (settings, env) = spec
        .clone()
        .resolve(&mut |path| {
            asked.push(path.to_string());
            Ok(unit_mesh(Primitive::Box, Tessellation::default()))
        })
        .unwrap();
    assert_eq!(asked, vec!["meshes/rock.obj"]);
    assert_eq!(settings, spec.settings);
    assert_eq!(env.charges, spec.charges);
    assert_eq!(env.min_distance, 0.01);
    assert_eq!(env.boundaries.len(), 4);
    assert!(matches!(env.boundaries[2].shape, Shape::Plane { normal, .. } if normal == DVec3::Z));
    assert!(matches!(&env.boundaries[3].shape, Shape::Mesh(m) if m.is_closed()));
    assert!(env.has_soft_boundaries());
    assert!(env.is_outside_soft(DVec3::new(0.0, 0.0, -4.0)));
    // Gravity in y, plus charges: the sum the engine adds.
    let expected =
        env.charges.iter().map(|c| c.displacement(DVec3::ZERO, 0.01)).sum::<DVec3>() + DVec3::new(0.0, -0.25, 0.0);
    assert_eq!(env.displacement(DVec3::ZERO), expected);
}

#[test]
fn scale_may_be_one_number_and_integers_are_numbers() {
    let spec = parse("scale = 2\nstart_length = 3\nbranch_angle = 0\nsteps = 0\n");
    assert_eq!(spec.settings.scale, DVec3::splat(2.0));
    assert_eq!(spec.settings.start_length, 3.0);
    assert_eq!(spec.settings.steps, 0);
    let shrink = parse("scale = 0.5\nsteps = 64\n");
    assert_eq!(shrink.settings.scale, DVec3::splat(0.5));
    assert_eq!(shrink.settings.steps, 64);
}

#[test]
fn errors_are_all_reported_with_locations_and_hints() {
    let file = SourceFile::new("bad.toml", "stpes = 4\n\n[[repellor]]\nposition = [0, 0, 0]\n");
    let d = parse_env(&file).unwrap_err();
    let short = d.short();
    assert_eq!(d.error_count(), 2, "{short}");
    assert!(short.contains("bad.toml:1:1: error: unknown key `stpes`"), "{short}");
    assert!(short.contains("hint: did you mean `steps`?"), "{short}");
    assert!(short.contains("bad.toml:3:3: error: unknown key `repellor`"), "{short}");
    assert!(short.contains("did you mean `repeller`?"), "{short}");
}

#[test]
fn join_names_one_of_the_four_readings() {
    for t in genform_hemls::JoinTest::ALL {
        assert_eq!(parse(&format!("join = \"{}\"\n", t.name())).settings.join, t);
    }
    let d = parse_env(&SourceFile::new("j.toml", "join = \"cones\"\n")).unwrap_err();
    assert!(
        d.short()
            .contains("j.toml:1:8: error: `join` must be \"facing\", \"cone\", \"paper\" or \"scalar\", not \"cones\""),
        "{}",
        d.short()
    );
}

#[test]
fn mesh_loading_errors_name_the_boundary_and_path() {
    let spec =
        parse("[[boundary]]\nsphere = { center = [0, 0, 0], radius = 1 }\n\n[[boundary]]\nmesh = \"gone.obj\"\n");
    let err = spec.clone().resolve(&mut |_| Err("no such file".into())).unwrap_err();
    assert_eq!(err, "test.toml:5:8: boundary 2 (mesh `gone.obj`): no such file");
    let mut flat = |_: &str| {
        Ok(Mesh {
            name: "flat".into(),
            positions: vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::X * 2.0],
            triangles: vec![[0, 1, 2]],
        })
    };
    let err = spec.resolve(&mut flat).unwrap_err();
    assert!(err.starts_with("test.toml:5:8: boundary 2 (mesh `gone.obj`): ") && err.contains("no triangle"), "{err}");
}

#[test]
fn the_example_environments_parse_and_resolve() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/hemls");
    for (name, check) in [
        (
            "drape_sphere.toml",
            (|e: &Environment| e.gravity.is_some_and(|g| g.magnitude < 0.0) && e.has_hard_boundaries())
                as fn(&Environment) -> bool,
        ),
        ("repellers.toml", |e| e.charges.iter().all(|c| c.kind == ChargeKind::Repeller && c.position.z < 0.0)),
        ("boxes_attractors.toml", |e| {
            e.boundaries.iter().any(|b| b.keep == Keep::Inside && matches!(b.shape, Shape::Box { .. }))
                && e.charges.iter().any(|c| c.kind == ChargeKind::Attractor)
        }),
    ] {
        let path = dir.join(name);
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let spec = parse_env(&SourceFile::new(name, text)).unwrap_or_else(|d| panic!("{}", d.short()));
        let (settings, env) = spec.resolve(&mut |p| Err(format!("unexpected mesh {p}"))).unwrap();
        assert_eq!(settings.steps, 4, "{name}");
        assert!(check(&env), "{name}: {env:?}");
        // The seed starts on the allowed side of every boundary.
        let seed = settings.start_position;
        assert_eq!(env.settle(seed), seed, "{name}");
    }
}
