//! The shipped examples (`examples/lsystem/*.ls`) against the golden
//! figures of ABOP (`shared/reference/lsystems.md`): string lengths,
//! module counts and the drawing's top, read from the files themselves so
//! the examples and the figures cannot drift apart.

use genform_core::{Rng, Scene, SourceFile};
use genform_lsystem::{LSystem, LsGenerator};
use std::sync::Arc;

fn load(name: &str) -> LSystem {
    let path = format!("{}/../../examples/lsystem/{name}.ls", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    match genform_lsystem::compile(&SourceFile::new(format!("{name}.ls"), text)) {
        Ok((s, warnings)) => {
            assert!(warnings.items.is_empty(), "{name}: {}", warnings.short());
            s
        }
        Err(e) => panic!("{name}:\n{}", e.short()),
    }
}

/// What a figure must show at its derivation length.
struct Golden {
    name: &'static str,
    length: usize,
    counts: &'static [(&'static str, usize)],
    /// Highest y of the drawing (plants grow up), if given.
    ymax: Option<f64>,
}

const GOLDEN: &[Golden] = &[
    Golden { name: "koch_snowflake", length: 1792, counts: &[("F", 768)], ymax: Some(70.148) },
    Golden { name: "quadratic_koch_island", length: 3803, counts: &[("F", 2048)], ymax: Some(21.0) },
    Golden { name: "abop_1_24a", length: 7811, counts: &[("F", 3125), ("[", 1562)], ymax: Some(243.0) },
    Golden { name: "abop_1_24b", length: 9373, counts: &[("F", 3125), ("[", 2343)], ymax: Some(63.0) },
    Golden { name: "abop_1_24c", length: 11116, counts: &[("F", 4096), ("[", 1170)], ymax: Some(55.8983) },
    Golden {
        name: "abop_1_24d",
        length: 13956,
        counts: &[("F", 4118), ("X", 2187), ("[", 2186)],
        ymax: Some(248.9342),
    },
    Golden { name: "abop_1_24e", length: 12863, counts: &[("F", 4118), ("X", 2187), ("[", 2186)], ymax: Some(254.0) },
    Golden { name: "abop_1_24f", length: 6263, counts: &[("F", 1488), ("X", 1024), ("[", 1023)], ymax: Some(80.1663) },
    Golden { name: "hogeweg", length: 6910, counts: &[("F", 2501), ("[", 636)], ymax: None },
    Golden { name: "koch_parametric", length: 2388, counts: &[("F", 1024)], ymax: None },
    // By hand: the block made at step j has age a = 8 - j and 2a + 10
    // modules (a F under its leaf, a I in its bud branch), plus the apex.
    Golden { name: "branch_context", length: 137, counts: &[("F", 28), ("[", 16)], ymax: None },
];

#[test]
fn examples_match_the_golden_figures() {
    for g in GOLDEN {
        let s = load(g.name);
        let m = s.derive(s.settings.derivation, &mut Rng::from_seed(0)).unwrap();
        assert_eq!(m.len(), g.length, "{}", g.name);
        for (module, n) in g.counts {
            assert_eq!(m.count(&s.alphabet, module), *n, "{}: #{module}", g.name);
        }
        if let Some(ymax) = g.ymax {
            let mut scene = Scene::new();
            s.interpret(&m, &mut Rng::from_seed(0), usize::MAX, &mut scene).unwrap();
            let top = scene.polylines.points().iter().map(|p| p.y as f64).fold(f64::MIN, f64::max);
            assert!((top - ymax).abs() < 2e-3, "{}: ymax {top} vs {ymax}", g.name);
        }
    }
}

#[test]
fn every_example_compiles_and_draws() {
    let dir = format!("{}/../../examples/lsystem", env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "ls").then(|| p.file_stem().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    names.sort();
    assert!(names.len() >= 16, "{names:?}");
    for name in names {
        let s = load(&name);
        let m = s.derive(s.settings.derivation, &mut Rng::from_seed(1)).unwrap();
        let mut scene = Scene::new();
        let end = s.interpret(&m, &mut Rng::from_seed(1), 1_000_000, &mut scene).unwrap();
        assert!(end.segments > 0, "{name} draws nothing");
        // Context-free examples are generators too.
        if !s.is_context_sensitive() && s.settings.growth < 1.0 {
            LsGenerator::new(Arc::new(s)).unwrap();
        }
    }
}

/// The parameters of every module named `name`, in string order.
fn params_of(s: &LSystem, m: &genform_lsystem::ModuleString, name: &str) -> Vec<Vec<f64>> {
    m.modules(&s.alphabet)
        .filter(|(sym, _)| s.alphabet.symbols[*sym as usize].name == name)
        .map(|(_, p)| p.to_vec())
        .collect()
}

#[test]
fn hooks_plant_shrinks_its_internodes_by_the_end_each_factor() {
    // By hand: step k (1-based) rewrites 3^(k-1) apices X, each adding two
    // F of length 10·0.6^(k-1) (EndEach has run k-1 times).
    let s = load("hooks_plant");
    let m = s.derive(s.settings.derivation, &mut Rng::from_seed(0)).unwrap();
    let lengths: Vec<f64> = params_of(&s, &m, "F").into_iter().map(|p| p[0]).collect();
    assert_eq!(lengths.len(), 2 * (1 + 3 + 9 + 27 + 81 + 243));
    for j in 0..6 {
        let want = 10.0 * 0.6f64.powi(j);
        let n = lengths.iter().filter(|&&l| (l - want).abs() < 1e-9 * want).count();
        assert_eq!(n, 2 * 3usize.pow(j as u32), "F({want})");
    }
    assert_eq!(m.count(&s.alphabet, "X"), 729);
    assert!((m.state[1] - 10.0 * 0.6f64.powi(6)).abs() < 1e-12, "len after six EndEach");
}

#[test]
fn produce_plant_matches_its_counts_by_hand() {
    // Apices of age t: 1, 3, 3, 9, 9, 27, 27 (even ages fork in three); each
    // emits one F(1.2·0.85^t); the 27 of age 6 flower.
    let s = load("produce_plant");
    let m = s.derive(s.settings.derivation, &mut Rng::from_seed(0)).unwrap();
    let lengths: Vec<f64> = params_of(&s, &m, "F").into_iter().map(|p| p[0]).collect();
    assert_eq!(lengths.len(), 79);
    assert_eq!(m.count(&s.alphabet, "K"), 27);
    assert_eq!(m.count(&s.alphabet, "A"), 0);
    for (t, n) in [1, 3, 3, 9, 9, 27, 27].into_iter().enumerate() {
        let want = 1.2 * 0.85f64.powi(t as i32);
        assert_eq!(lengths.iter().filter(|&&l| (l - want).abs() < 1e-12).count(), n, "age {t}");
    }
}

#[test]
fn topiary_stops_exactly_the_apices_outside_its_disc() {
    // Every ?P holds the turtle position where it stands (checked against
    // the turtle: the query after a flower K is where the drawing put the
    // flower); an apex A is only rewritten to K when its query was outside
    // the disc, so flowers are outside and growing apices are inside.
    let s = load("topiary");
    let m = s.derive(s.settings.derivation, &mut Rng::from_seed(0)).unwrap();
    let modules: Vec<(String, Vec<f64>)> =
        m.modules(&s.alphabet).map(|(sym, p)| (s.alphabet.symbols[sym as usize].name.clone(), p.to_vec())).collect();
    let outside = |p: &[f64]| p[0] * p[0] + (p[1] - 7.0).powi(2) > 36.0;
    let (mut flowers, mut apices) = (0, 0);
    for w in modules.windows(2) {
        if w[1].0 != "?P" {
            continue;
        }
        match w[0].0.as_str() {
            "K" => {
                flowers += 1;
                // Stopped at the step after it crossed: at most one
                // internode (0.9) beyond the circle.
                let d = (w[1].1[0].powi(2) + (w[1].1[1] - 7.0).powi(2)).sqrt();
                assert!(outside(&w[1].1) && d < 6.0 + 0.9 + 1e-9, "{:?}", w[1].1);
            }
            "A" => {
                // Its parent was inside, so it is at most one internode out.
                apices += 1;
                let d = (w[1].1[0].powi(2) + (w[1].1[1] - 7.0).powi(2)).sqrt();
                assert!(d < 6.0 + 0.9 + 1e-9, "{:?}", w[1].1);
            }
            _ => {}
        }
    }
    assert!(flowers > 20 && apices > 0, "{flowers} flowers, {apices} apices");
    // The flowers are where the turtle draws them.
    let mut scene = Scene::new();
    s.interpret(&m, &mut Rng::from_seed(0), usize::MAX, &mut scene).unwrap();
    let centres: Vec<[f64; 2]> =
        scene.instances.iter().map(|i| [i.transform.translation.x as f64, i.transform.translation.y as f64]).collect();
    assert_eq!(centres.len(), flowers);
    for w in modules.windows(2).filter(|w| w[0].0 == "K") {
        let p = &w[1].1;
        assert!(centres.iter().any(|c| (c[0] - p[0]).abs() < 1e-4 && (c[1] - p[1]).abs() < 1e-4), "{p:?}");
    }
}

#[test]
fn leafy_plant_places_one_leaf_mesh_per_surface_module() {
    // By hand: A adds one leaf per step (6); the B born at step j steps
    // 6 − j more times with two leaves each: 2·(5 + 4 + 3 + 2 + 1 + 0) = 30.
    let s = load("leafy_plant");
    let m = s.derive(s.settings.derivation, &mut Rng::from_seed(0)).unwrap();
    assert_eq!(m.count(&s.alphabet, "~l"), 36);
    let mut scene = Scene::new();
    s.interpret(&m, &mut Rng::from_seed(0), usize::MAX, &mut scene).unwrap();
    let leaves = scene.instances.iter().filter(|i| matches!(i.primitive, genform_core::scene::Primitive::Mesh(_)));
    assert_eq!(leaves.count(), 36);
    assert_eq!(scene.meshes.len(), 1, "one shared leaf mesh");
}
