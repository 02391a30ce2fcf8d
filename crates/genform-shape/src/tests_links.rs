//! How invocations that run in several scopes (the faces of `comp`, the
//! tiles of `repeat`, the pieces of `split`) use their slots' links: a rule
//! invoked by name re-expresses its place's one gene in every scope, so
//! every wall gets the façade; a declared slot gives each scope its next
//! link, going round its links again once all are used. Nothing is left
//! out.

use super::*;
use crate::tests::grammar;
use genform_core::Primitive;
use genform_core::genome::Link;
use glam::Vec3;
use std::collections::BTreeMap;

/// Samples with `seed`, checks the genome and expresses it.
fn run(g: &ShapeGrammar, seed: u64) -> (Genome, Scene) {
    let limits = g.limits();
    let s = g.sample(&mut Rng::from_seed(seed), &limits).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
    assert!(s.truncated.is_none(), "seed {seed}: truncated");
    s.genome.validate(g.graph()).unwrap();
    let mut scene = Scene::new();
    g.express(&s.genome, &limits, &mut scene).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
    (s.genome, scene)
}

/// Genes of the symbol `name`.
fn genes(g: &ShapeGrammar, genome: &Genome, name: &str) -> usize {
    genome.iter().filter(|x| g.graph().symbol(x.symbol()).name == name).count()
}

/// The boxes tagged `tag`, by the wall they stand on: the wall's outward
/// normal and its distance from the origin (rounded), to the widths
/// (world x size) of its boxes. A wall scope's z is its outward normal.
fn by_wall(s: &Scene, tag: &str) -> BTreeMap<(i32, i32, i32), Vec<f32>> {
    // A colour gives the tag a suffix (`glass#3e5c76`).
    let Some(id) = s.tags.iter().position(|t| t.split('#').next() == Some(tag)) else { return BTreeMap::new() };
    let mut walls: BTreeMap<(i32, i32, i32), Vec<f32>> = BTreeMap::new();
    for i in s.instances.iter().filter(|i| i.tag == id as u32 && i.primitive == Primitive::Box) {
        let m = i.transform.matrix3;
        let n = Vec3::from(m.z_axis).normalize();
        let d = n.dot(i.transform.translation.into());
        let key = ((n.x * 100.0).round() as i32, (n.z * 100.0).round() as i32, (d * 100.0).round() as i32);
        walls.entry(key).or_default().push(m.x_axis.length());
    }
    walls
}

/// A façade of tiles 2 wide, each with a window whose width is a gene of
/// `Window` (a share of the tile).
const FACADE: &str = "
    Facade { repeat(x, 2) { Window; } }
    Window { param w: uniform(0.2, 0.8); tag(\"glass\"); translate(0, 0, 0.05); size(sx * w, sy / 2, 0.1); box; }";

#[test]
fn a_rule_invoked_for_every_wall_of_a_box_decorates_all_four() {
    // A plain box scope, 8 × 3 × 4: tiles of 2, so 4 on the long walls, 2
    // on the short ones.
    let g = grammar(&format!("Block {{ size(8, 3, 4); comp(f) {{ side: Facade }} }} {FACADE}"));
    for seed in 0..20 {
        let (genome, s) = run(&g, seed);
        let walls = by_wall(&s, "glass");
        assert_eq!(walls.len(), 4, "seed {seed}: {walls:?}");
        let mut counts: Vec<usize> = walls.values().map(Vec::len).collect();
        counts.sort();
        assert_eq!(counts, [2, 2, 4, 4], "seed {seed}");
        // One façade gene, one window gene: every window alike.
        assert_eq!((genes(&g, &genome, "Facade"), genes(&g, &genome, "Window")), (1, 1));
        let widths: Vec<f32> = walls.values().flatten().copied().collect();
        assert!(widths.iter().all(|w| (w - widths[0]).abs() < 1e-5), "seed {seed}: {widths:?}");
    }
    // The same on an extruded lot.
    let g = grammar(&format!("Block {{ lot(8, 4); extrude(3); comp(f) {{ side: Facade | top: shape }} }} {FACADE}"));
    let (_, s) = run(&g, 1);
    assert_eq!(by_wall(&s, "glass").values().map(Vec::len).sum::<usize>(), 12);
}

#[test]
fn an_l_block_written_the_cga_way_decorates_every_wall() {
    // An L lot of six walls, extruded; then an L cut from a lot by `shapeL`.
    for block in [
        "lot(0, 0, 10, 0, 10, 4, 4, 4, 4, 10, 0, 10); extrude(3); comp(f) { side: Facade | top: shape }",
        "lot(16, 12); shapeL(5, 6) { shape: { extrude(3); comp(f) { side: Facade | top: shape } } | remainder: shape }",
    ] {
        let g = grammar(&format!("Block {{ {block} }} {FACADE}"));
        for seed in 0..10 {
            let (genome, s) = run(&g, seed);
            let walls = by_wall(&s, "glass");
            assert_eq!(walls.len(), 6, "{block} seed {seed}: {walls:?}");
            assert_eq!(genes(&g, &genome, "Facade"), 1);
        }
    }
}

#[test]
fn the_shipped_example_puts_one_facade_on_every_wall() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/shape/facade_every_wall.sg");
    let (g, warnings) =
        compile(&SourceFile::new("facade_every_wall.sg", std::fs::read_to_string(path).unwrap()), &NoAssets).unwrap();
    assert!(warnings.items.is_empty(), "{}", warnings.short());
    for seed in 0..30 {
        let (genome, s) = run(&g, seed);
        let walls = by_wall(&s, "glass");
        assert_eq!(walls.len(), 6, "seed {seed}: {walls:?}");
        // At least two floors: at least two windows on every wall.
        assert!(walls.values().all(|w| w.len() >= 2), "seed {seed}: {walls:?}");
        assert_eq!((genes(&g, &genome, "Facade"), genes(&g, &genome, "Window")), (1, 1), "seed {seed}");
        // Expression is deterministic and a saved genome replays exactly.
        let json = genome.to_json(g.graph());
        let again = Genome::from_json(&json, g.graph()).unwrap();
        let mut replay = Scene::new();
        g.express(&again, &g.limits(), &mut replay).unwrap();
        assert_eq!(replay.instances, s.instances, "seed {seed}");
        assert_eq!(replay.polygons, s.polygons, "seed {seed}");
    }
}

#[test]
fn each_arm_re_expresses_its_own_gene() {
    // Two places invoke `Facade`: the front's gene and the other walls'
    // shared one. The second place no longer takes a wall or two and
    // leaves the rest bare.
    let g = grammar(
        "Block { size(8, 3, 4); comp(f) { front: Facade(1) | side: Facade(0) } }
         Facade(shop) { repeat(x, 2) { Window(shop); } }
         Window(shop) { param w: uniform(0.2, 0.8); if (shop) { tag(\"shop\"); } else { tag(\"glass\"); }
                        translate(0, 0, 0.05); size(sx * w, sy / 2, 0.1); box; }",
    );
    for seed in 0..10 {
        let (genome, s) = run(&g, seed);
        let (shop, glass) = (by_wall(&s, "shop"), by_wall(&s, "glass"));
        assert_eq!((shop.len(), glass.len()), (1, 3), "seed {seed}: {shop:?} {glass:?}");
        assert_eq!((genes(&g, &genome, "Facade"), genes(&g, &genome, "Window")), (2, 2));
        // The side walls share one window gene, the front has its own.
        let side: Vec<f32> = glass.values().flatten().copied().collect();
        assert!(side.iter().all(|w| (w - side[0]).abs() < 1e-5), "seed {seed}: {side:?}");
        let front = shop.values().next().unwrap()[0];
        assert!((front - side[0]).abs() > 1e-6, "seed {seed}: distinct genes, distinct widths");
    }
}

#[test]
fn a_slot_with_a_link_per_wall_keeps_a_gene_per_wall() {
    // `x 8` on four walls: one gene per wall, as before; links 4..8 stay
    // empty. The window width is the façade's gene here.
    let facade = "Facade { param w: uniform(0.2, 0.8); repeat(x, 2) { Window(w); } }
        Window(w) { tag(\"glass\"); translate(0, 0, 0.05); size(sx * w, sy / 2, 0.1); box; }";
    let g = grammar(&format!("Block {{ slot fac: Facade x 8; size(8, 3, 4); comp(f) {{ side: fac }} }} {facade}"));
    for seed in 0..10 {
        let (genome, s) = run(&g, seed);
        assert_eq!(genes(&g, &genome, "Facade"), 4, "seed {seed}");
        let root = genome.gene(genform_core::genome::GenePos(0));
        let children: Vec<bool> = root.links().map(|l| matches!(l, Link::Child(_))).collect();
        assert_eq!(children, [true, true, true, true, false, false, false, false]);
        let walls = by_wall(&s, "glass");
        assert_eq!(walls.len(), 4);
        // Each wall's windows alike, the walls' widths all different.
        let mut widths: Vec<f32> = walls.values().map(|w| w[0]).collect();
        assert!(walls.values().all(|w| w.iter().all(|x| (x - w[0]).abs() < 1e-5)));
        widths.sort_by(f32::total_cmp);
        assert!(widths.windows(2).all(|p| p[1] - p[0] > 1e-6), "seed {seed}: {widths:?}");
    }
    // `x 2` on four walls: the third and fourth walls take links 0 and 1
    // again, so two widths, each on two walls, and no bare wall.
    let g = grammar(&format!("Block {{ slot fac: Facade x 2; size(8, 3, 4); comp(f) {{ side: fac }} }} {facade}"));
    for seed in 0..10 {
        let (genome, s) = run(&g, seed);
        assert_eq!(genes(&g, &genome, "Facade"), 2, "seed {seed}");
        let walls = by_wall(&s, "glass");
        assert_eq!(walls.len(), 4, "seed {seed}: {walls:?}");
        let mut widths: Vec<i64> = walls.values().map(|w| (w[0] * 1e4).round() as i64).collect();
        widths.sort();
        widths.dedup();
        assert_eq!(widths.len(), 2, "seed {seed}: {walls:?}");
    }
}

#[test]
fn tiles_and_pieces_re_express_their_places_gene() {
    // Every tile of a repeat and every piece of a split: one gene each place.
    let g = grammar(
        "A { size(10, 1, 1); repeat(x, 1) { B; } repeat(x, 2) { split(y) { 1r: C | 1r: { C; C; } } } }
         B { param s: uniform(0.1, 0.9); size(s, s, s); box; }
         C { param s: uniform(0.1, 0.9); size(s, s, s); sphere; }",
    );
    let (genome, s) = run(&g, 3);
    assert_eq!((genes(&g, &genome, "B"), genes(&g, &genome, "C")), (1, 3));
    let boxes = s.instances.iter().filter(|i| i.primitive == Primitive::Box).count();
    // 10 tiles of B; 5 tiles of three C each.
    assert_eq!((boxes, s.instances.len() - boxes), (10, 15));
}

#[test]
fn sampling_and_expression_agree_when_genes_are_shared() {
    // A shared gene re-run in a scope where it reaches new children (a
    // condition on the scope's size): sampling grows them there, and
    // expression reads them back.
    let g = grammar(
        "A { lot(0, 0, 12, 0, 12, 3, 3, 3, 3, 12, 0, 12); extrude(4); comp(f) { side: F } }
         F { slot big: Big p 0.7; slot small: Small p 0.7; if (sx > 5) { big; } else { small; } }
         Big { param h: uniform(0.5, 1); size(sx, h, 0.1); box; }
         Small { sphere; }",
    );
    for seed in 0..40 {
        let limits = g.limits();
        let s1 = g.sample(&mut Rng::from_seed(seed), &limits).unwrap();
        let s2 = g.sample(&mut Rng::from_seed(seed), &limits).unwrap();
        assert_eq!(s1.genome.to_json(g.graph()), s2.genome.to_json(g.graph()), "seed {seed}: deterministic");
        let (genome, s) = run(&g, seed);
        // Walls of 12, 3, 9, 9, 3 and 12: four take `big`, two `small`,
        // each the one link the shared `F` gene holds for it.
        let f = genome.iter().find(|x| g.graph().symbol(x.symbol()).name == "F").unwrap();
        let has = |l| matches!(f.link(l), Link::Child(_));
        let boxes = s.instances.iter().filter(|i| i.primitive == Primitive::Box).count();
        let spheres = s.instances.iter().filter(|i| i.primitive == Primitive::Sphere).count();
        assert_eq!(boxes, if has(0) { 4 } else { 0 }, "seed {seed}");
        assert_eq!(spheres, if has(1) { 2 } else { 0 }, "seed {seed}");
    }
}
