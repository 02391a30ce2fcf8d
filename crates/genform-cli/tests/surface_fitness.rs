//! Genr8's surface criteria on surfaces the real grower makes: the flat-tile
//! values of the reference (shared/reference/genr8.md §9) end to end, from
//! the shipped `.gr8` files through growth to the scorer.

mod common;

use common::root;
use genform_core::{Rng, SourceFile};
use genform_hemls::{Environment, Settings};
use genform_score::SurfaceMeasures;

fn measures(grammar: &str, steps: u32) -> SurfaceMeasures {
    let path = root().join("examples/hemls").join(grammar);
    let file = SourceFile::new(grammar, std::fs::read_to_string(path).unwrap());
    let (h, _) = genform_hemls::compile(&file).unwrap();
    let settings = Settings { steps, ..Settings::default() };
    let g = genform_hemls::grow(&h, &settings, &Environment::default(), &mut Rng::from_seed(0)).unwrap();
    SurfaceMeasures::of_surfaces(&[g.surface(0)])
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-4 * b.abs().max(1.0)
}

#[test]
fn grown_four_sided_tiles_score_the_reference_values() {
    let s: f64 = 1.5;
    for (n, subdivisions) in [(0, 1.0), (1, 0.75), (2, 0.625), (3, 0.5625), (4, 0.53125)] {
        let m = measures("tiles4.gr8", n);
        assert!(close(m.size, 2.0 * s.powi(n as i32)), "n = {n}: size {}", m.size);
        assert!(close(m.subdivisions, subdivisions), "n = {n}: subdivisions {}", m.subdivisions);
        assert!(m.smoothness.abs() < 1e-5 && m.undulation.abs() < 1e-5, "n = {n}: flat");
        assert_eq!(m.symmetry, 1.0, "n = {n}");
        assert_eq!(m.soft_boundary, 0.0);
    }
    assert!(close(measures("tiles4.gr8", 4).size, 10.125));
}

#[test]
fn grown_three_sided_tiles_score_the_reference_values() {
    let s: f64 = 1.5;
    for (n, subdivisions) in [(0, 1.0), (1, 2.0 / 3.0), (2, 0.5), (3, 5.0 / 12.0), (4, 0.375)] {
        let m = measures("tiles3.gr8", n);
        let size = (1.0 + 3f64.sqrt() / 2.0) * s.powi(n as i32);
        assert!(close(m.size, size), "n = {n}: size {} vs {size}", m.size);
        assert!(close(m.subdivisions, subdivisions), "n = {n}: subdivisions {}", m.subdivisions);
    }
}
