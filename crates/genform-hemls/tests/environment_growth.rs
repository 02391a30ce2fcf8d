//! Growth in an environment, end to end: the shipped grammars
//! (`examples/hemls/*.gr8`) grown in the shipped environment files
//! (`examples/hemls/*.toml`) through the real front ends (`compile`,
//! `parse_env`, `EnvSpec::resolve`). Draping over a sphere, repellers
//! lifting the surface, gravity and the charge law through the growth
//! phase, soft / stop / enclosure boundaries holding after every step.

use genform_core::{Rng, SourceFile};
use genform_hemls::{
    Behaviour, Boundary, Charge, Environment, Growth, Hemls, Keep, Map, Settings, Shape, compile, grow, grow_with,
    parse_env, parse_str,
};
use glam::DVec3;

fn dir() -> String {
    format!("{}/../../examples/hemls", env!("CARGO_MANIFEST_DIR"))
}

/// A shipped grammar, through the real front end.
fn grammar(name: &str) -> Hemls {
    let path = format!("{}/{name}.gr8", dir());
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    match compile(&SourceFile::new(path.as_str(), text)) {
        Ok((h, _)) => h,
        Err(e) => panic!("{name}:\n{}", e.short()),
    }
}

/// An environment file's text, read and resolved (no mesh boundaries).
fn env_text(name: &str, text: &str) -> (Settings, Environment) {
    let spec = parse_env(&SourceFile::new(name, text)).unwrap_or_else(|e| panic!("{name}:\n{}", e.short()));
    spec.resolve(&mut |p| Err(format!("no mesh expected, got {p}"))).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A shipped environment file (`drape_sphere` → `examples/hemls/drape_sphere.toml`).
fn env_file(name: &str) -> (Settings, Environment) {
    let path = format!("{}/{name}.toml", dir());
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    env_text(&path, &text)
}

/// Every shipped environment file's stem, sorted.
fn env_names() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "toml").then(|| p.file_stem().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    names.sort();
    names
}

/// Grows and keeps every step's vertex positions (the seed first); every
/// step's map is validated and must be a disc (V − E + F = 1).
fn grow_steps(h: &Hemls, s: &Settings, env: &Environment) -> (Growth, Vec<Vec<DVec3>>) {
    let mut steps = Vec::new();
    let mut errors = Vec::new();
    let g = grow_with(h, s, env, &mut Rng::from_seed(3), &mut |k, m: &Map| {
        if let Err(e) = m.validate() {
            errors.push(format!("step {k}: {e}"));
        }
        if m.euler_characteristic() != 1 {
            errors.push(format!("step {k}: V - E + F = {}", m.euler_characteristic()));
        }
        steps.push(m.positions().to_vec());
    })
    .unwrap_or_else(|e| panic!("{}: {e}", h.name));
    assert!(errors.is_empty(), "{}: {errors:?}", h.name);
    assert_eq!(steps.len(), s.steps as usize + 1);
    (g, steps)
}

fn sphere_of(env: &Environment) -> (DVec3, f64) {
    env.boundaries
        .iter()
        .find_map(|b| match b.shape {
            Shape::Sphere { center, radius } => Some((center, radius)),
            _ => None,
        })
        .expect("a sphere boundary")
}

/// The identity grammar: a unit square whose edges no rule rewrites, so
/// vertex k of every step is vertex k of the seed.
fn still_square() -> Hemls {
    parse_str("still.gr8", "Edge0 + Edge0 + Edge0 + Edge0\nAngle 90\n").unwrap_or_else(|e| panic!("{}", e.short()))
}

/// Scale 1 about a fixed centre: only the environment moves anything.
fn unscaled(steps: u32) -> Settings {
    Settings { steps, scale: DVec3::ONE, fixed_center: true, ..Settings::default() }
}

/// The vertex nearest to `at` seen from above (smallest xy distance).
fn nearest_in_xy(pos: &[DVec3], at: DVec3) -> DVec3 {
    let d = |p: &DVec3| (p.truncate() - at.truncate()).length();
    *pos.iter().min_by(|a, b| d(a).total_cmp(&d(b))).unwrap()
}

/// How far `p` lies outside the sphere (negative: inside).
fn clearance(p: DVec3, center: DVec3, radius: f64) -> f64 {
    (p - center).length() - radius
}

#[test]
fn tiles_drape_over_the_sphere_without_entering_it() {
    let (mut s, env) = env_file("drape_sphere");
    let file_steps = s.steps;
    s.steps = 6;
    let (center, radius) = sphere_of(&env);
    let (g, steps) = grow_steps(&grammar("tiles4"), &s, &env);
    assert_eq!(g.map.face_count(), 4usize.pow(6), "the sphere must not keep the tiles from joining");
    for (k, pos) in steps.iter().enumerate() {
        for (i, p) in pos.iter().enumerate() {
            let c = clearance(*p, center, radius);
            assert!(c >= -1e-6, "step {k}: vertex {i} at {p} is {} inside the sphere", -c);
        }
    }
    // Over the file's own steps the middle of the sheet rests on the top of
    // the sphere (gravity pulls harder than the scale lifts it); later the
    // uniform scale about the centroid also magnifies the dome's height and
    // lifts it off, so steps 5 and 6 are only held to the no-entry rule.
    for (k, pos) in steps.iter().enumerate().skip(1).take(file_steps as usize) {
        let mid = nearest_in_xy(pos, center);
        let c = clearance(mid, center, radius);
        assert!(mid.truncate().length() < 1e-9 && c < 1e-3, "step {k}: middle vertex {mid}, {c} above the sphere");
    }
    let at_file = &steps[file_steps as usize];
    let resting = at_file.iter().filter(|p| clearance(**p, center, radius) < 0.05).count();
    assert!(resting >= 25, "{resting} vertices on the sphere after {file_steps} steps");
    // The rim hangs far below the sphere's top, past its equator.
    let pos = g.map.positions();
    let low = pos.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    assert!(low < center.z - 0.5 * radius, "lowest vertex at z = {low}; the sphere's equator is at {}", center.z);
    let beside = pos.iter().filter(|p| p.z < center.z && p.truncate().length() > radius).count();
    assert!(beside > pos.len() / 4, "{beside} of {} vertices hang beside the sphere", pos.len());
}

#[test]
fn sheet_that_does_not_scale_in_z_stays_draped_for_six_steps() {
    // scale = [1.5, 1.5, 1]: the sheet grows sideways only, so the dome is
    // not magnified and the middle rests on the sphere at every step.
    let (mut s, env) = env_file("drape_sphere");
    s.steps = 6;
    s.scale.z = 1.0;
    let (center, radius) = sphere_of(&env);
    let (_, steps) = grow_steps(&grammar("tiles4"), &s, &env);
    for (k, pos) in steps.iter().enumerate().skip(1) {
        let mid = nearest_in_xy(pos, center);
        let c = clearance(mid, center, radius);
        assert!((-1e-6..1e-3).contains(&c), "step {k}: middle vertex {mid}, {c} above the sphere");
        // Everything above the sphere's disc lies close on it.
        for p in pos.iter().filter(|p| p.truncate().length() < radius) {
            let c = clearance(*p, center, radius);
            assert!((-1e-6..0.25).contains(&c), "step {k}: {p} is {c} from the sphere");
        }
    }
}

#[test]
fn repellers_lift_the_sheet_above_them_step_by_step() {
    let (s, env) = env_file("repellers");
    let h = grammar("tiles4");
    let (_, steps) = grow_steps(&h, &s, &env);
    let mut final_z = Vec::new();
    for c in &env.charges {
        let z: Vec<f64> = steps.iter().map(|pos| nearest_in_xy(pos, c.position).z).collect();
        for k in 1..z.len() {
            assert!(z[k] >= z[k - 1], "above {}: z went down from {} to {} at step {k}", c.position, z[k - 1], z[k]);
        }
        assert!(z[z.len() - 1] > 1.0, "above {}: only {z:?}", c.position);
        final_z.push(z[z.len() - 1]);
    }
    // Vertices far from both repellers rise, but less: a dome over them.
    let pos = steps.last().unwrap();
    let far: Vec<f64> = pos
        .iter()
        .filter(|p| env.charges.iter().all(|c| (p.truncate() - c.position.truncate()).length() > 4.0))
        .map(|p| p.z)
        .collect();
    assert!(far.len() >= 20, "{} far vertices", far.len());
    let far_mean = far.iter().sum::<f64>() / far.len() as f64;
    let highest_far = far.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let lowest_near = final_z.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(far.iter().all(|&z| z > 0.0), "the whole sheet rises");
    assert!(
        highest_far < lowest_near && far_mean < 0.5 * lowest_near,
        "far vertices at z ≤ {highest_far} (mean {far_mean}), above the repellers {final_z:?}"
    );
    // Without the repellers the same growth stays in the seed plane.
    let (_, flat) = grow_steps(&h, &s, &Environment::default());
    assert!(flat.last().unwrap().iter().all(|p| p.z == 0.0));
}

#[test]
fn gravity_moves_every_vertex_the_same_amount_each_step() {
    let text = "steps = 5\nscale = 1\nfixed_center = true\ngravity = { axis = \"z\", magnitude = -0.1 }\n";
    let (s, env) = env_text("gravity.toml", text);
    assert_eq!((s.steps, s.scale, s.fixed_center), (5, DVec3::ONE, true));
    let (_, steps) = grow_steps(&still_square(), &s, &env);
    let seed = &steps[0];
    assert_eq!(seed.len(), 4);
    for (k, pos) in steps.iter().enumerate() {
        assert_eq!(pos.len(), 4);
        for (p, p0) in pos.iter().zip(seed) {
            assert_eq!((p.x, p.y), (p0.x, p0.y), "step {k}: x and y never change");
            assert!((p.z - (p0.z - 0.1 * k as f64)).abs() < 1e-12, "step {k}: z = {}", p.z);
        }
    }
}

#[test]
fn one_attractor_moves_a_vertex_by_the_inverse_square_law() {
    let (_, seed) = grow_steps(&still_square(), &unscaled(0), &Environment::default());
    let seed = seed[0].clone();
    let q = seed[0] + DVec3::new(0.0, 0.0, 2.0);
    let text = format!(
        "steps = 1\nscale = 1\nfixed_center = true\n[[attractor]]\nposition = [{}, {}, {}]\nstrength = 1\nexponent = 2\n",
        q.x, q.y, q.z
    );
    let (s, env) = env_text("attractor.toml", &text);
    let (_, steps) = grow_steps(&still_square(), &s, &env);
    let moved = steps[1][0] - seed[0];
    assert!((moved - DVec3::new(0.0, 0.0, 0.25)).length() < 1e-12, "moved {moved}");
    // Every other vertex: c / d² towards the attractor.
    for (p1, p0) in steps[1].iter().zip(&seed) {
        let to = q - *p0;
        let d = to.length();
        let want = to / d * (1.0 / (d * d));
        assert!((*p1 - *p0 - want).length() < 1e-12, "{p0} moved {} instead of {want}", *p1 - *p0);
    }
}

/// A busy environment's text, plus `extra` (a boundary table).
fn busy_env(extra: &str) -> String {
    format!(
        "steps = 4\ngravity = {{ axis = \"z\", magnitude = -0.2 }}\n[[repeller]]\nposition = [0.3, 0.2, -1]\n\
         [[attractor]]\nposition = [2, -1, 1]\nstrength = 0.5\n{extra}"
    )
}

#[test]
fn soft_boundaries_count_vertices_and_move_nothing() {
    let h = grammar("tiles4");
    let (s, free) = env_text("free.toml", &busy_env(""));
    let (g_free, steps_free) = grow_steps(&h, &s, &free);
    assert_eq!(g_free.outside_soft, 0);
    let cases = [
        ("sphere = { center = [0, 0, 0], radius = 2 }\n", Keep::Outside),
        ("box = { min = [-2, -2, -1], max = [2, 3, 2] }\nkeep = \"inside\"\n", Keep::Inside),
    ];
    for (shape, keep) in cases {
        let text = busy_env(&format!("[[boundary]]\n{shape}behaviour = \"soft\"\n"));
        let (s2, env) = env_text("soft.toml", &text);
        assert_eq!(s2, s);
        assert_eq!((env.boundaries[0].behaviour, env.boundaries[0].keep), (Behaviour::Soft, keep));
        let (g, steps) = grow_steps(&h, &s, &env);
        assert_eq!(steps, steps_free, "{shape}: a soft boundary moved something");
        let pos = g.map.positions();
        let wrong = pos
            .iter()
            .filter(|p| match env.boundaries[0].shape {
                Shape::Sphere { center, radius } => (**p - center).length() < radius,
                Shape::Box { min, max } => !(p.cmpge(min).all() && p.cmple(max).all()),
                _ => unreachable!(),
            })
            .count();
        assert!(wrong > 0 && wrong < pos.len(), "{shape}: {wrong} of {} on the wrong side", pos.len());
        assert_eq!(g.outside_soft as usize, wrong, "{shape}");
        assert_eq!(g.surface(0).outside_soft, g.outside_soft);
    }
}

#[test]
fn stop_boundaries_freeze_vertices_where_slide_lets_them_move_on() {
    // A square falling onto the plane z = -0.5 while it grows about the
    // origin: step 1 ends at z = -0.4, step 2 hits the plane.
    let h = still_square();
    let make = |behaviour: &str| {
        let text = format!(
            "steps = 4\nscale = 1.5\nfixed_center = true\ngravity = {{ axis = \"z\", magnitude = -0.4 }}\n\
             [[boundary]]\nplane = {{ point = [0, 0, -0.5], normal = [0, 0, 1] }}\nbehaviour = \"{behaviour}\"\n"
        );
        env_text("plane.toml", &text)
    };
    let (s, stop) = make("stop");
    let (_, steps) = grow_steps(&h, &s, &stop);
    // Step 2 moves z from -0.4 to 1.5 · (-0.4) - 0.4 = -1 and x from 0.75
    // to 1.125: the plane is a sixth of the way.
    let hit = 0.75 + 0.375 / 6.0;
    for (k, pos) in steps.iter().enumerate() {
        for p in pos {
            assert!(p.z >= -0.5, "step {k}: {p} below the stop plane");
            if k >= 2 {
                assert!((p.x.abs() - hit).abs() < 1e-5 && (p.z + 0.5).abs() < 1e-5, "step {k}: stopped at {p}");
            }
        }
    }
    assert_eq!(steps[2], steps[4], "a stopped vertex stays stopped");
    let (s, slide) = make("slide");
    let (_, steps) = grow_steps(&h, &s, &slide);
    for (k, pos) in steps.iter().enumerate().skip(2) {
        for p in pos {
            assert!(p.z >= -0.5 && p.z < -0.5 + 1e-5, "step {k}: {p}");
            assert!((p.x.abs() - 0.5 * 1.5f64.powi(k as i32)).abs() < 1e-5, "step {k}: slid to {p}");
        }
    }
}

#[test]
fn tiles_stopped_by_a_sphere_never_enter_it() {
    let text = "steps = 5\nstart_position = [0, 0, 1]\ngravity = { axis = \"z\", magnitude = -0.6 }\n\
                [[boundary]]\nsphere = { center = [0.4, -0.3, -1.5], radius = 2 }\nbehaviour = \"stop\"\n";
    let (s, env) = env_text("stop_sphere.toml", text);
    let (center, radius) = sphere_of(&env);
    let (_, steps) = grow_steps(&grammar("tiles4"), &s, &env);
    let mut held = 0;
    for (k, pos) in steps.iter().enumerate() {
        for p in pos {
            let c = clearance(*p, center, radius);
            assert!(c >= -1e-6, "step {k}: {p} is {} inside", -c);
            held += usize::from(c < 1e-3);
        }
    }
    assert!(held > 10, "only {held} vertices ever reached the sphere");
}

#[test]
fn box_enclosure_holds_the_sheet_and_attractors_lift_its_corners() {
    let (s, env) = env_file("boxes_attractors");
    let Shape::Box { min, max } = env.boundaries[0].shape else { panic!("a box") };
    assert_eq!(env.boundaries[0].keep, Keep::Inside);
    let (_, steps) = grow_steps(&grammar("tiles4"), &s, &env);
    for (k, pos) in steps.iter().enumerate() {
        for p in pos {
            assert!(p.cmpge(min).all() && p.cmple(max).all(), "step {k}: {p} outside the box {min}..{max}");
        }
    }
    let pos = steps.last().unwrap();
    let walls = pos.iter().filter(|p| (max.x - p.x.abs()) < 1e-3 || (max.y - p.y.abs()) < 1e-3).count();
    assert!(walls >= 20, "only {walls} vertices press against the walls");
    let middle = nearest_in_xy(pos, DVec3::ZERO).z;
    for c in &env.charges {
        let under = nearest_in_xy(pos, c.position);
        assert!(under.z > middle + 0.1, "under the attractor at {}: {under}, middle z = {middle}", c.position);
    }
}

#[test]
fn every_example_environment_grows_a_finite_disc() {
    let names = env_names();
    assert!(names.len() >= 3, "{names:?}");
    for name in names {
        let (mut s, env) = env_file(&name);
        s.steps = 4;
        let (g, steps) = grow_steps(&grammar("tiles4"), &s, &env);
        for (k, pos) in steps.iter().enumerate() {
            assert!(pos.iter().all(|p| p.is_finite()), "{name} step {k}");
        }
        assert!(g.map.face_count() > 64, "{name}: {} faces", g.map.face_count());
    }
}

#[test]
fn boundary_built_in_code_matches_the_file() {
    // The env file and the builder API give the same growth.
    let (s, from_file) = env_text(
        "b.toml",
        "steps = 3\n[[attractor]]\nposition = [0, 0, 2]\n[[boundary]]\nsphere = { center = [0, 0, 1], radius = 0.5 }\n",
    );
    let built = Environment::new()
        .with_charge(Charge::attractor(DVec3::new(0.0, 0.0, 2.0)))
        .with_boundary(Boundary::sphere(DVec3::new(0.0, 0.0, 1.0), 0.5));
    let h = grammar("tiles3");
    let a = grow(&h, &s, &from_file, &mut Rng::from_seed(1)).unwrap();
    let b = grow(&h, &s, &built, &mut Rng::from_seed(1)).unwrap();
    assert_eq!(a.map.positions(), b.map.positions());
}
