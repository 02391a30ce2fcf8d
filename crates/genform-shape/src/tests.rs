//! Unit tests of the whole pipeline on small grammars: golden transforms of
//! every scope operation, slot and link semantics, limits.

use super::*;
use genform_core::genome::{GenePos, Link};
use genform_core::{Generator, LimitKind, Mesh, Primitive};
use glam::{Mat3, Vec3};

/// `src` compiled (panics with the diagnostics when it does not compile).
pub(crate) fn grammar(src: &str) -> ShapeGrammar {
    let file = SourceFile::new("t.sg", src);
    match compile(&file, &NoAssets) {
        Ok((g, _)) => g,
        Err(d) => panic!("{}", d.short()),
    }
}

/// Samples with `seed` and expresses the result.
fn run(g: &ShapeGrammar, seed: u64) -> (Genome, Scene) {
    let limits = g.limits();
    let s = g.sample(&mut Rng::from_seed(seed), &limits).unwrap();
    s.genome.validate(g.graph()).unwrap();
    let mut scene = Scene::new();
    g.express(&s.genome, &limits, &mut scene).unwrap();
    (s.genome, scene)
}

fn scene(src: &str) -> Scene {
    run(&grammar(src), 1).1
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

fn centre(s: &Scene, i: usize) -> Vec3 {
    s.instances[i].transform.translation.into()
}

fn matrix(s: &Scene, i: usize) -> Mat3 {
    s.instances[i].transform.matrix3.into()
}

fn axes_len(s: &Scene, i: usize) -> Vec3 {
    let m = matrix(s, i);
    Vec3::new(m.x_axis.length(), m.y_axis.length(), m.z_axis.length())
}

#[test]
fn translate_uses_the_rotated_frame_but_not_the_size() {
    let s = scene("A { size(2, 2, 2); rotate(y, 90); translate(1, 0, 0); box; }");
    // Rotating about y by 90° turns local +x into world −z; size is not applied.
    assert!(close(centre(&s, 0), Vec3::new(0.0, 0.0, -1.0)), "{:?}", centre(&s, 0));
    assert!(close(axes_len(&s, 0), Vec3::splat(2.0)));
}

#[test]
fn rotations_compose_about_local_axes() {
    let s = scene("A { rotate(z, 90); rotate(x, 90); translate(0, 1, 0); box; }");
    // Rz(90)·Rx(90)·(0,1,0) = Rz(90)·(0,0,1) = (0,0,1).
    assert!(close(centre(&s, 0), Vec3::Z), "{:?}", centre(&s, 0));
}

#[test]
fn scale_multiplies_and_size_sets() {
    let s = scene("A { size(2, 3, 4); scale(0.5, 2, 1); box; scale(2); box; size(1, 1, 1); box; }");
    assert!(close(axes_len(&s, 0), Vec3::new(1.0, 6.0, 4.0)));
    assert!(close(axes_len(&s, 1), Vec3::new(2.0, 12.0, 8.0)));
    assert!(close(axes_len(&s, 2), Vec3::ONE));
}

#[test]
fn vector_parameters_scale_per_component() {
    let g = grammar("A { param s: vec3 uniform([1, 2, 3], [1, 2, 3]); scale(s); box; translate(s); box; }");
    let (_, s) = run(&g, 3);
    assert!(close(axes_len(&s, 0), Vec3::new(1.0, 2.0, 3.0)));
    assert!(close(centre(&s, 1), Vec3::new(1.0, 2.0, 3.0)));
}

#[test]
fn push_and_pop_restore_the_scope() {
    let s = scene("A { [ translate(1, 0, 0); size(3, 3, 3); tag(\"inner\"); box; ] box; }");
    assert!(close(centre(&s, 0), Vec3::X));
    assert!(close(centre(&s, 1), Vec3::ZERO));
    assert!(close(axes_len(&s, 1), Vec3::ONE));
    assert_eq!(s.tags[s.instances[0].tag as usize], "inner");
    assert_eq!(s.tags[s.instances[1].tag as usize], "A");
}

#[test]
fn split_lays_absolute_then_relative_pieces_along_the_axis() {
    let s = scene("A { size(10, 1, 1); split(x) { 2: box | 1r: box | 3r: { translate(0, index, count); box; } } }");
    assert_eq!(s.instances.len(), 3);
    // Absolute 2, the remaining 8 as 1:3 → 2 and 6, from −5 to +5.
    let want = [(-4.0, 2.0), (-2.0, 2.0), (2.0, 6.0)];
    for (i, (c, len)) in want.iter().enumerate() {
        assert!((centre(&s, i).x - c).abs() < 1e-5, "piece {i}: {:?}", centre(&s, i));
        assert!((axes_len(&s, i).x - len).abs() < 1e-5);
        assert!((axes_len(&s, i).y - 1.0).abs() < 1e-5);
    }
    // `index` and `count` inside the third piece.
    assert!(close(centre(&s, 2), Vec3::new(2.0, 2.0, 3.0)));
}

#[test]
fn split_follows_the_rotated_frame() {
    let s = scene("A { rotate(y, 90); size(4, 1, 1); split(x) { 1r: box | 1r: sphere } }");
    // Local x is world −z after the rotation.
    assert!(close(centre(&s, 0), Vec3::new(0.0, 0.0, 1.0)), "{:?}", centre(&s, 0));
    assert!(close(centre(&s, 1), Vec3::new(0.0, 0.0, -1.0)));
}

#[test]
fn repeat_fills_the_scope_with_rounded_tile_count() {
    let s = scene("A { size(10, 1, 1); repeat(x, 2.2) { translate(0, index, 0); box; } }");
    // round(10 / 2.2) = 5 tiles of 2.
    assert_eq!(s.instances.len(), 5);
    for i in 0..5 {
        let c = centre(&s, i);
        assert!(close(c, Vec3::new(-4.0 + 2.0 * i as f32, i as f32, 0.0)), "{i}: {c:?}");
        assert!((axes_len(&s, i).x - 2.0).abs() < 1e-5);
    }
    // At least one tile, even when the tile is larger than the scope.
    assert_eq!(scene("A { repeat(z, 100) { box; } }").instances.len(), 1);
    // Nested repeats: 2 × 3 tiles, `count` is the innermost.
    let s = scene("A { size(4, 1, 6); repeat(x, 2) { repeat(z, 2) { size(count, 1, 1); box; } } }");
    assert_eq!(s.instances.len(), 6);
    assert!(s.instances.iter().all(|i| (Mat3::from(i.transform.matrix3).x_axis.x - 3.0).abs() < 1e-5));
}

#[test]
fn mirror_reflects_and_reuses_the_same_genes() {
    let g = grammar(
        "A { slot w: W p 1; size(2, 1, 1); mirror(x) { translate(sx / 2, 0, 0); w; } }
         W { param s: uniform(0.5, 1.5); scale(s, 1, 1); translate(sx / 2, 0, 0); box; }",
    );
    let (genome, s) = run(&g, 5);
    // One W gene, expressed twice.
    assert_eq!(genome.len(), 2);
    assert_eq!(s.instances.len(), 2);
    let (a, b) = (centre(&s, 0), centre(&s, 1));
    assert!(a.x > 1.0 && close(b, Vec3::new(-a.x, a.y, a.z)), "{a:?} {b:?}");
    assert!(matrix(&s, 0).determinant() > 0.0);
    assert!(matrix(&s, 1).determinant() < 0.0);
    assert!(close(axes_len(&s, 0), axes_len(&s, 1)));
}

#[test]
fn nested_mirrors_give_four_copies() {
    let s = scene("A { mirror(x) { mirror(y) { translate(1, 2, 0); box; } } box; }");
    assert_eq!(s.instances.len(), 5);
    let mut cs: Vec<(i32, i32)> = (0..4).map(|i| (centre(&s, i).x as i32, centre(&s, i).y as i32)).collect();
    cs.sort();
    assert_eq!(cs, vec![(-1, -2), (-1, 2), (1, -2), (1, 2)]);
    // The scope is restored after the mirror.
    assert!(close(centre(&s, 4), Vec3::ZERO));
    assert!(matrix(&s, 4).determinant() > 0.0);
}

#[test]
fn primitives_map_to_scene_primitives() {
    let s = scene("A { box; cylinder; cone; sphere; frustum(0.25); taper_box(0.5); }");
    let p: Vec<Primitive> = s.instances.iter().map(|i| i.primitive).collect();
    assert_eq!(
        p,
        vec![
            Primitive::Box,
            Primitive::Frustum { top: 1.0 },
            Primitive::Frustum { top: 0.0 },
            Primitive::Sphere,
            Primitive::Frustum { top: 0.25 },
            Primitive::TaperedBox { top: 0.5 },
        ]
    );
}

#[test]
fn meshes_are_scene_assets() {
    struct One;
    impl AssetResolver for One {
        fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
            Mesh::from_obj(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        }
    }
    let file = SourceFile::new("m.sg", "mesh leaf = \"leaf.obj\"; A { mesh(leaf); size(1, 1, 1); mesh(leaf); }");
    let (g, _) = compile(&file, &One).unwrap();
    let (_, s) = run(&g, 1);
    assert_eq!(s.meshes.len(), 1);
    assert_eq!(s.instances[1].primitive, Primitive::Mesh(0));
    assert_eq!(s.meshes[0].triangles.len(), 1);
}

#[test]
fn insert_fits_an_asset_to_the_scope() {
    struct Off;
    impl AssetResolver for Off {
        fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
            // A tetrahedron off the origin: bounds (2, 1, −1) to (6, 3, 0).
            Mesh::from_obj(path, "v 2 1 -1\nv 6 1 -1\nv 2 3 -1\nv 2 1 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
        }
    }
    let src = "mesh m = \"m.obj\"; A { translate(10, 0, 0); size(1, 2, 3); insert(m); insert(m); mesh(m); }";
    let (g, _) = compile(&SourceFile::new("i.sg", src), &Off).unwrap();
    let (_, s) = run(&g, 1);
    // One fitted copy for both inserts, beside the asset as declared.
    assert_eq!(s.instances.len(), 3);
    assert_eq!(s.instances[0].primitive, s.instances[1].primitive);
    assert_ne!(s.instances[0].primitive, s.instances[2].primitive);
    let Primitive::Mesh(k) = s.instances[0].primitive else { panic!() };
    let (lo, hi) = s.meshes[k as usize]
        .positions
        .iter()
        .map(|p| s.instances[0].transform.transform_point3(*p))
        .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(p), hi.max(p)));
    // The scope's box exactly: centre (10, 0, 0), size (1, 2, 3).
    assert!(close(lo, Vec3::new(9.5, -1.0, -1.5)) && close(hi, Vec3::new(10.5, 1.0, 1.5)), "{lo} {hi}");
    // An unknown asset is an error naming it.
    let bad = compile(&SourceFile::new("i.sg", "A { insert(tree); }"), &Off).unwrap_err();
    assert!(bad.short().contains("unknown mesh `tree`"), "{}", bad.short());
}

#[test]
fn a_context_mesh_occludes() {
    struct City;
    impl AssetResolver for City {
        fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
            // Two separate triangles' worth of "buildings": a unit cube's
            // corners around (5, 0, 0) and a flat quad far away.
            let mut obj = String::new();
            for (x, y, z) in [(4.5, -0.5, -0.5), (5.5, -0.5, -0.5), (5.5, 0.5, 0.5), (4.5, 0.5, 0.5)] {
                obj += &format!("v {x} {y} {z}\n");
            }
            obj += "f 1 2 3\nf 1 3 4\nv 50 0 0\nv 51 0 0\nv 51 0 1\nf 5 6 7\n";
            Mesh::from_obj(path, &obj)
        }
    }
    let src = "context \"city.obj\"; A { [ translate(5, 0, 0); B; ] [ translate(-5, 0, 0); B; ] }
               B { if (!overlaps(context)) { box; } }";
    let (g, _) = compile(&SourceFile::new("c.sg", src), &City).unwrap();
    let (_, s) = run(&g, 1);
    assert_eq!(s.instances.len(), 1, "the box inside the context's building is left out");
    assert!(close(centre(&s, 0), Vec3::new(-5.0, 0.0, 0.0)));
    // Without a context, `context` names nothing.
    let e = compile(&SourceFile::new("c.sg", "A { if (overlaps(context)) { box; } }"), &City).unwrap_err();
    assert!(e.short().contains("no rule or tag is called `context`"), "{}", e.short());
    let e = compile(&SourceFile::new("c.sg", "context \"a.obj\"; context \"b.obj\"; A { box; }"), &City).unwrap_err();
    assert!(e.short().contains("`context` is given twice"), "{}", e.short());
}

#[test]
fn inherited_arguments_and_conditions() {
    let s = scene(
        "S { A(2, 0); A(3, 1); }
         A(w, up) { if (up > 0) { translate(0, 5, 0); } else { translate(0, -5, 0); } size(w, 1, 1); box; }",
    );
    assert_eq!(s.instances.len(), 2);
    assert!(close(axes_len(&s, 0), Vec3::new(2.0, 1.0, 1.0)));
    assert!(close(centre(&s, 0), Vec3::new(0.0, -5.0, 0.0)));
    assert!(close(centre(&s, 1), Vec3::new(0.0, 5.0, 0.0)));
}

#[test]
fn children_start_from_the_invoking_scope() {
    let s = scene("S { translate(1, 0, 0); size(2, 2, 2); C; } C { translate(0, sy, 0); box; }");
    assert!(close(centre(&s, 0), Vec3::new(1.0, 2.0, 0.0)));
    assert_eq!(s.tags[s.instances[0].tag as usize], "C");
}

#[test]
fn template_chains_end_at_the_range() {
    let g = grammar("S { C<0>; } C<i: 0..3> { translate(0, 0, i); box; C<i + 1>; }");
    assert_eq!(g.graph().symbols.len(), 4);
    assert_eq!(g.graph().symbols[3].name, "C<2>");
    // C<2> invokes C<3>, outside the range: the chain ends.
    assert!(g.graph().symbols[3].slots.is_empty());
    let (genome, s) = run(&g, 1);
    assert_eq!(genome.len(), 4);
    assert_eq!(s.instances.len(), 3);
    assert!(close(centre(&s, 2), Vec3::new(0.0, 0.0, 3.0)));
}

#[test]
fn slot_links_are_used_in_invocation_order() {
    let g = grammar(
        "S { slot k: B p 1 x 3; k; k; k; k; A; A; } B { param s: uniform(1, 2); size(s, s, s); box; } A { sphere; }",
    );
    let spec = &g.graph().symbols[0];
    assert_eq!(spec.slots[0].max_count, 3);
    // An implicit slot has one link per place it is invoked.
    assert_eq!(spec.slots[1].max_count, 2);
    let (genome, s) = run(&g, 1);
    assert_eq!(genome.len(), 6);
    // The fourth `k` finds the three links used and goes back to the
    // first: nothing is left out, and its box is the first box again.
    let prims: Vec<Primitive> = s.instances.iter().map(|i| i.primitive).collect();
    assert_eq!(prims, [[Primitive::Box; 4].as_slice(), &[Primitive::Sphere; 2]].concat());
    let sizes: Vec<Vec3> = (0..4).map(|i| axes_len(&s, i)).collect();
    assert!(close(sizes[3], sizes[0]), "{sizes:?}");
    assert!(!close(sizes[1], sizes[0]) && !close(sizes[2], sizes[1]), "{sizes:?}");
}

#[test]
fn empty_links_emit_nothing() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/shape/spaceship.sg")).unwrap();
    let g = grammar(&text);
    let graph = g.graph();
    let limits = Limits::default();
    // Only the start symbol: no body.
    let genome = Genome::with_root(graph, graph.root, &[]);
    let mut s = Scene::new();
    g.express(&genome, &limits, &mut s).unwrap();
    assert!(s.is_empty());
    // S with one body and nothing else: one box.
    let mut genome = Genome::with_root(graph, graph.root, &[]);
    let body = graph.symbol_id("Body").unwrap();
    genome.grow(GenePos(0), 0, body, &[1.0, 1.0, 1.0], graph.symbol(body).link_len());
    let mut s = Scene::new();
    g.express(&genome, &limits, &mut s).unwrap();
    assert_eq!(s.instances.len(), 1);
}

#[test]
fn has_reads_the_first_link_and_sampling_decides_it_once() {
    let g = grammar("A { slot b: B p 0.5; if (!has(b)) { sphere; } b; b; } B { box; }");
    for seed in 0..50 {
        let (genome, s) = run(&g, seed);
        // Exactly one of the two: the leaf-like sphere, or the child's box
        // (twice: the second `b` re-expresses the slot's one link).
        let child = genome.gene(GenePos(0)).link(0);
        let want: &[Primitive] =
            if matches!(child, Link::Child(_)) { &[Primitive::Box; 2] } else { &[Primitive::Sphere] };
        let got: Vec<Primitive> = s.instances.iter().map(|i| i.primitive).collect();
        assert_eq!(got, want, "seed {seed}");
    }
}

#[test]
fn sampling_and_expression_are_deterministic() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/shape/spaceship.sg")).unwrap();
    let g = grammar(&text);
    for seed in 0..20 {
        let (a, sa) = run(&g, seed);
        let (b, sb) = run(&g, seed);
        assert_eq!(a, b);
        assert_eq!(sa.instances, sb.instances);
    }
}

#[test]
fn growth_stops_at_the_gene_and_depth_limits() {
    let g = grammar("A { slot a: A p 1; box; translate(0, 1, 0); a; }");
    let limits = Limits { max_genes: 10, max_depth: 100, max_primitives: 1000 };
    let s = g.sample(&mut Rng::from_seed(1), &limits).unwrap();
    assert_eq!(s.truncated, Some(LimitKind::Genes));
    assert_eq!(s.genome.len(), 10);
    let limits = Limits { max_genes: 1000, max_depth: 4, max_primitives: 1000 };
    let s = g.sample(&mut Rng::from_seed(1), &limits).unwrap();
    assert_eq!(s.truncated, Some(LimitKind::Depth));
    assert_eq!(s.genome.len(), 5);
    // Expression of a genome deeper than the limit is an error.
    let deep = g.sample(&mut Rng::from_seed(1), &Limits { max_depth: 20, ..limits }).unwrap().genome;
    let err = g.express(&deep, &limits, &mut Scene::new()).unwrap_err();
    assert_eq!(err, ExpressError::Limit { kind: LimitKind::Depth, limit: 4 });
}

#[test]
fn primitive_limit_stops_expression_and_truncates_sampling() {
    let g = grammar("A { repeat(x, 0.001) { box; } }");
    let limits = Limits { max_genes: 10, max_depth: 10, max_primitives: 50 };
    let s = g.sample(&mut Rng::from_seed(1), &limits).unwrap();
    assert_eq!(s.truncated, Some(LimitKind::Primitives));
    let err = g.express(&s.genome, &limits, &mut Scene::new()).unwrap_err();
    assert_eq!(err, ExpressError::Limit { kind: LimitKind::Primitives, limit: 50 });
}

#[test]
fn runaway_work_without_geometry_stops() {
    // Each level re-runs its child twice: 2^depth executions, no primitives.
    let g = grammar("A { slot a: A p 1; mirror(x) { a; } repeat(x, 1e-300) { } }");
    let limits = Limits { max_genes: 100, max_depth: 60, max_primitives: 100 };
    let t = std::time::Instant::now();
    let s = g.sample(&mut Rng::from_seed(1), &limits).unwrap();
    assert!(s.truncated.is_some());
    let err = g.express(&s.genome, &limits, &mut Scene::new());
    assert!(err.is_err());
    assert!(t.elapsed().as_secs() < 10);
}

#[test]
fn non_finite_geometry_is_an_eval_error() {
    let g = grammar("A { param a: uniform(0, 1); size(1 / (a - a), 1, 1); box; }");
    let err = g.sample(&mut Rng::from_seed(1), &Limits::default()).unwrap_err();
    let ExpressError::Eval(msg) = err else { panic!("{err:?}") };
    assert!(msg.contains("t.sg:1:") && msg.contains("rule `A`") && msg.contains("size"), "{msg}");
}

#[test]
fn invalid_genomes_are_rejected() {
    let g = grammar("A { slot b: B p 1; b; } B { param s: uniform(1, 2); box; }");
    let graph = g.graph();
    let mut genome = Genome::with_root(graph, 0, &[]);
    genome.grow(GenePos(0), 0, 1, &[5.0], 0);
    assert!(matches!(g.express(&genome, &Limits::default(), &mut Scene::new()), Err(ExpressError::Genome(_))));
}

#[test]
fn alternatives_are_hidden_choice_parameters() {
    let g = grammar("A { param h: uniform(1, 2); alt { 3: { box; } 1: { sphere; } } }");
    let spec = &g.graph().symbols[0];
    assert_eq!(spec.params.len(), 2);
    assert_eq!(
        spec.params[1].components,
        vec![genform_core::Distribution::Choice { values: vec![0.0, 1.0], weights: vec![3.0, 1.0] }]
    );
    // Expression follows the gene's choice.
    let mut genome = Genome::with_root(g.graph(), 0, &[1.5, 1.0]);
    let mut s = Scene::new();
    g.express(&genome, &Limits::default(), &mut s).unwrap();
    assert_eq!(s.instances[0].primitive, Primitive::Sphere);
    genome.set_param(GenePos(0), 1, 0.0);
    s.clear();
    g.express(&genome, &Limits::default(), &mut s).unwrap();
    assert_eq!(s.instances[0].primitive, Primitive::Box);
}

#[test]
fn graph_reflects_params_slots_and_geometry() {
    let g = grammar(
        "S { slot b: B p 0.25 x 4; b; }
         B { param size: vec3 uniform(0.5, 1); param n: int(1, 3); param k: choice(1: 2, 5: 1);
             param z: normal(0, 1) in [-2, 2]; box; }",
    );
    let graph = g.graph();
    assert_eq!(graph.root, 0);
    assert!(!graph.symbols[0].emits_geometry);
    assert!(graph.symbols[1].emits_geometry);
    assert_eq!(graph.symbols[0].slots[0].prob, 0.25);
    assert_eq!(graph.symbols[1].param_len(), 6);
    assert_eq!(graph.symbols[1].params[0].name, "size");
    assert_eq!(g.name(), "t");
    assert_eq!(g.limits(), Limits::default());
}

#[test]
fn header_items_set_name_axiom_and_limits() {
    let g = grammar(
        "grammar \"towers\"; axiom B; limits genes = 12, depth = 3, primitives = 40; const h = 2;
         A { box; } B { size(1, h, 1); box; }",
    );
    assert_eq!(g.name(), "towers");
    assert_eq!(g.graph().root, 1);
    assert_eq!(g.limits(), Limits { max_genes: 12, max_depth: 3, max_primitives: 40 });
    let (_, s) = run(&g, 1);
    assert!(close(axes_len(&s, 0), Vec3::new(1.0, 2.0, 1.0)));
}

#[test]
fn unreachable_rules_warn() {
    let file = SourceFile::new("w.sg", "A { box; }\nB { box; }\n");
    let (_, w) = compile(&file, &NoAssets).unwrap();
    assert_eq!(w.items.len(), 1);
    assert!(w.short().contains("w.sg:2:1: warning: rule `B` is unreachable"), "{}", w.short());
}
