//! End-to-end tests of graph grammars: the real binary on the shipped
//! `examples/graph` grammars.

mod common;

use common::{genform, root, s};
use std::path::PathBuf;

fn gg(name: &str) -> PathBuf {
    root().join("examples/graph").join(format!("{name}.gg.yaml"))
}

#[test]
fn koch_has_the_papers_element_count_and_is_deterministic() {
    let tmp = tempfile::tempdir().unwrap();
    let koch = gg("koch");
    let run = genform(tmp.path(), &["sample", s(&koch), "--seed", "3"]).ok();
    assert!(run.stdout().contains("192 steps, 579 vertices, 579 edges, 1158 elements"), "{}", run.stdout());
    for out in ["a.svg", "b.svg", "a.yaml", "b.yaml", "a.png"] {
        genform(tmp.path(), &["sample", s(&koch), "--seed", "3", "--out", out]).ok();
    }
    let read = |n: &str| std::fs::read(tmp.path().join(n)).unwrap();
    assert_eq!(read("a.svg"), read("b.svg"));
    assert_eq!(read("a.yaml"), read("b.yaml"));
    let svg = String::from_utf8(read("a.svg")).unwrap();
    assert!(svg.contains("cm\""), "1 unit = 1 cm: {}", &svg[..200.min(svg.len())]);
    assert_eq!(&read("a.png")[1..4], b"PNG");
    let run = genform(tmp.path(), &["sample", s(&koch), "--steps", "4"]).ok();
    assert!(run.stdout().contains("4 steps"), "{}", run.stdout());
}

#[test]
fn every_example_derives() {
    let tmp = tempfile::tempdir().unwrap();
    for name in ["koch", "square_pattern", "circle_pattern", "tree", "facade"] {
        let run = genform(tmp.path(), &["sample", s(&gg(name)), "--seed", "1", "--out", "x.svg"]).ok();
        assert!(run.stderr().contains("elements"), "{name}: {}", run.stderr());
    }
    let out = genform(tmp.path(), &["info", s(&gg("facade"))]).ok().stdout();
    assert!(out.contains("productions:"), "{out}");
}

#[test]
fn bad_grammars_name_the_position() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "host:\n  vertices: {a: {x: 0, y: 0}}\n  edges: [{from: a, to: zz}]\nproductions: []\n";
    std::fs::write(tmp.path().join("bad.gg.yaml"), text).unwrap();
    let err = genform(tmp.path(), &["sample", "bad.gg.yaml"]).fails().stderr();
    assert!(err.contains("bad.gg.yaml:3:") && err.contains("zz"), "{err}");
}

/// Axis-aligned bounds of corner triples.
fn bounds(tris: &[[[f32; 3]; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for p in tris.iter().flatten() {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

#[test]
fn drawings_export_as_flat_ribbons_in_every_mesh_format() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for out in ["k.obj", "k.glb", "k.ply", "k.stl", "again/k.obj"] {
        genform(dir, &["sample", s(&gg("koch")), "--seed", "3", "--out", out]).ok();
    }
    let read = |n: &str| std::fs::read(dir.join(n)).unwrap();
    assert_eq!(read("k.obj"), read("again/k.obj"));
    // The drawing's extreme points (192 steps of a 90 cm triangle's
    // snowflake: x from −4.054 to 94.054, y from −30 to the top corner
    // 90·√3/2 = 77.942) widened by half the 0.6 stroke (round caps); flat.
    // The caps are polygons of 45° steps turned with each edge, so an
    // extreme may fall short of the round cap by up to 0.3·(1 − cos 22.5°).
    let want = ([-4.054 - 0.3, -30.0 - 0.3, 0.0], [94.054 + 0.3, 77.942 + 0.3, 0.0]);
    let tolerance = 0.01 + 0.3 * (1.0 - (std::f32::consts::PI / 8.0).cos());
    let close = |(lo, hi): ([f32; 3], [f32; 3]), what: &str| {
        for k in 0..3 {
            let ok = (lo[k] - want.0[k]).abs() < tolerance && (hi[k] - want.1[k]).abs() < tolerance;
            assert!(ok, "{what}: {lo:?} {hi:?}");
        }
    };

    let load = tobj::LoadOptions { triangulate: true, ..Default::default() };
    let (models, _) =
        tobj::load_obj_buf(&mut std::io::Cursor::new(read("k.obj")), &load, |_| Err(tobj::LoadError::OpenFileFailed))
            .expect("tobj reads the OBJ");
    // 579 edges: many polygons, so one merged object.
    assert_eq!(models.len(), 1, "{:?}", models.iter().map(|m| &m.name).collect::<Vec<_>>());
    let m = &models[0].mesh;
    let corner = |i: u32| {
        let i = 3 * i as usize;
        [m.positions[i], m.positions[i + 1], m.positions[i + 2]]
    };
    let obj: Vec<[[f32; 3]; 3]> = m.indices.chunks(3).map(|t| [corner(t[0]), corner(t[1]), corner(t[2])]).collect();
    // 579 koch edges, each a quad (2 triangles) and two round caps, half
    // octagons outside the quad (3 each).
    assert_eq!(obj.len(), 579 * (2 + 2 * 3), "OBJ triangles");
    close(bounds(&obj), "k.obj");
    for t in &obj {
        let (u, v) = ([t[1][0] - t[0][0], t[1][1] - t[0][1]], [t[2][0] - t[0][0], t[2][1] - t[0][1]]);
        assert!(u[0] * v[1] - u[1] * v[0] > 0.0, "every face looks at +z, as the SVG is seen");
    }

    let (doc, buffers, _) = gltf::import_slice(read("k.glb")).expect("gltf imports the GLB");
    let mut glb = Vec::new();
    for mesh in doc.meshes() {
        for p in mesh.primitives() {
            assert_eq!(p.mode(), gltf::mesh::Mode::Triangles, "no lines left");
            assert!(p.material().double_sided(), "a flat drawing shows from both sides");
            // Black, the drawing's stroke colour.
            assert_eq!(p.material().pbr_metallic_roughness().base_color_factor(), [0.0, 0.0, 0.0, 1.0]);
            let r = p.reader(|b| Some(&buffers[b.index()]));
            let pos: Vec<[f32; 3]> = r.read_positions().unwrap().collect();
            let idx: Vec<u32> = r.read_indices().unwrap().into_u32().collect();
            glb.extend(idx.chunks(3).map(|t| [pos[t[0] as usize], pos[t[1] as usize], pos[t[2] as usize]]));
        }
    }
    assert_eq!(glb.len(), obj.len(), "GLB triangles");
    // The GLB's nodes carry no turn for a drawing: its points are the OBJ's.
    close(bounds(&glb), "k.glb");

    let stl = stl_io::read_stl(&mut std::io::Cursor::new(read("k.stl"))).expect("stl_io reads the STL");
    assert_eq!(stl.faces.len(), obj.len(), "STL triangles");
    use ply_rs_bw::ply::DefaultElement;
    let ply = ply_rs_bw::parser::Parser::<DefaultElement>::new()
        .read_ply(&mut std::io::Cursor::new(read("k.ply")))
        .expect("ply-rs reads the PLY");
    assert_eq!(ply.payload["face"].len(), obj.len(), "PLY triangles");
}

#[test]
fn coloured_drawings_keep_their_svg_colours_in_layers() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    genform(dir, &["sample", s(&gg("facade")), "--seed", "1", "--out", "f.glb"]).ok();
    let (doc, _, _) = gltf::import_slice(std::fs::read(dir.join("f.glb")).unwrap()).expect("gltf imports the GLB");
    let names: Vec<String> = doc.materials().filter_map(|m| m.name().map(str::to_string)).collect();
    // The wall's fill (#8f8f8f) and outline (#1e1e1e) of facade.gg.yaml.
    for want in ["building#8f8f8f", "building#1e1e1e"] {
        assert!(names.iter().any(|n| n.starts_with(want)), "{want} in {names:?}");
    }
    let grey = doc.materials().find(|m| m.name().is_some_and(|n| n.starts_with("building#8f8f8f"))).unwrap();
    let c = grey.pbr_metallic_roughness().base_color_factor();
    // sRGB 0x8f = 143 is linear 0.2747.
    assert!((c[0] - 0.2747).abs() < 1e-3 && c[0] == c[1] && c[1] == c[2], "{c:?}");
}

/// sRGB 0–1 → linear, as glTF colours are.
fn linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

#[test]
fn obj_files_bring_a_material_library_in_the_glbs_colours() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let models = [
        ("ship", root().join("examples/shape/spaceship.sg")),
        ("house", root().join("examples/boxsplit/house.bsg")),
        ("facade", gg("facade")),
    ];
    for (name, grammar) in &models {
        for ext in ["obj", "glb"] {
            let out = format!("sub/{name}.{ext}");
            let run = genform(dir, &["sample", s(grammar), "--seed", "1", "--out", &out]).ok();
            if ext == "obj" {
                assert!(run.stderr().contains(&format!("sub/{name}.obj and sub/{name}.mtl")), "{}", run.stderr());
            }
        }
        let obj_path = dir.join(format!("sub/{name}.obj"));
        let text = std::fs::read_to_string(&obj_path).unwrap();
        // Named relative to the OBJ, so the pair can be moved together.
        assert!(text.lines().any(|l| l == format!("mtllib {name}.mtl")), "{name}");
        let load = tobj::LoadOptions { triangulate: true, ..Default::default() };
        let (meshes, materials) = tobj::load_obj(&obj_path, &load).expect("tobj reads the OBJ");
        let materials = materials.expect("tobj reads the MTL beside it");
        assert!(!materials.is_empty(), "{name}");
        for m in &meshes {
            assert!(m.mesh.material_id.is_some(), "{name}: {} has no usemtl", m.name);
        }
        // Every material has the colour of the GLB material of the same name.
        let (doc, _, _) = gltf::import_slice(std::fs::read(dir.join(format!("sub/{name}.glb"))).unwrap()).unwrap();
        let glb: Vec<(String, [f32; 4])> = doc
            .materials()
            .filter_map(|m| Some((m.name()?.replace('#', "_"), m.pbr_metallic_roughness().base_color_factor())))
            .collect();
        for mat in &materials {
            let kd = mat.diffuse.expect("Kd");
            let (_, want) = glb
                .iter()
                .find(|(n, _)| n.trim_end_matches(" (double-sided)") == mat.name)
                .unwrap_or_else(|| panic!("{name}: no GLB material {} in {glb:?}", mat.name));
            for k in 0..3 {
                assert!((linear(kd[k]) - want[k]).abs() < 2e-3, "{name} {}: Kd {kd:?}, GLB {want:?}", mat.name);
            }
        }
    }
}
