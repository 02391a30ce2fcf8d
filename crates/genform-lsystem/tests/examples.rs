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
            let top = scene.polylines.iter().flat_map(|l| &l.points).map(|p| p.y as f64).fold(f64::MIN, f64::max);
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
