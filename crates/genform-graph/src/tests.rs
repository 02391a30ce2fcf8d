//! Semantics tests on small grammars: matching, rewriting, the step loop,
//! placement, determinism and the YAML round trip.

use crate::{Graph, GraphGrammar, Value, compile};
use genform_core::{Rng, SourceFile};

pub(crate) fn grammar(src: &str) -> GraphGrammar {
    match compile(&SourceFile::new("test.gg.yaml", src)) {
        Ok((g, _)) => g,
        Err(d) => panic!("{}", d.short()),
    }
}

fn example(name: &str) -> String {
    let path = format!("{}/../../examples/graph/{name}.gg.yaml", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// A grammar over `host` with one production `p` (mother `mother`, which
/// it keeps unchanged).
fn pattern(host: &str, mother: &str) -> GraphGrammar {
    grammar(&format!("host:\n{host}\nproductions:\n  - name: p\n    mother:\n{mother}\n    daughter: {{}}\n"))
}

fn count(g: &GraphGrammar, graph: &Graph) -> usize {
    g.matches(graph, "p").unwrap().unwrap().len()
}

const TRIANGLE: &str = "  vertices: {a: {}, b: {x: 1}, c: {y: 1}}\n  edges: [[a, b], [b, c], [c, a]]";
const DIRECTED_TRIANGLE: &str = "  vertices: {a: {}, b: {x: 1}, c: {y: 1}}\n  edges: [{from: a, to: b, directed: true}, \
                                 {from: b, to: c, directed: true}, {from: c, to: a, directed: true}]";

#[test]
fn a_two_edge_path_matches_a_triangle_six_times() {
    let g = pattern(TRIANGLE, "      vertices: {A: {}, B: {}, C: {}}\n      edges: [[A, B], [B, C]]");
    let all = g.matches(g.host(), "p").unwrap().unwrap();
    assert_eq!(all.len(), 6);
    // Every match is injective and all are different.
    for m in &all {
        let mut v = m.vertices.clone();
        v.sort_unstable();
        v.dedup();
        assert_eq!(v.len(), 3);
        assert_ne!(m.edges[0], m.edges[1]);
    }
    let mut distinct = all.clone();
    distinct.sort_by(|a, b| (&a.vertices, &a.edges).cmp(&(&b.vertices, &b.edges)));
    distinct.dedup();
    assert_eq!(distinct.len(), 6);
    // Automorphisms count separately: the triangle matches itself 6 times.
    let tri = pattern(TRIANGLE, "      vertices: {A: {}, B: {}, C: {}}\n      edges: [[A, B], [B, C], [C, A]]");
    assert_eq!(count(&tri, tri.host()), 6);
}

#[test]
fn undirected_edges_match_both_ways_directed_only_forwards() {
    let one_undirected = "      vertices: {A: {}, B: {}}\n      edges: [[A, B]]";
    let one_directed = "      vertices: {A: {}, B: {}}\n      edges: [{from: A, to: B, directed: true}]";
    let g = pattern(TRIANGLE, one_undirected);
    assert_eq!(count(&g, g.host()), 6);
    let g = pattern(TRIANGLE, one_directed);
    assert_eq!(count(&g, g.host()), 0, "a directed pattern edge needs a directed host edge");
    let g = pattern(DIRECTED_TRIANGLE, one_directed);
    assert_eq!(count(&g, g.host()), 3);
    let g = pattern(DIRECTED_TRIANGLE, one_undirected);
    assert_eq!(count(&g, g.host()), 6, "an undirected pattern edge matches a directed one either way");
    // A directed 2-path in a directed 3-cycle: 3.
    let g = pattern(
        DIRECTED_TRIANGLE,
        "      vertices: {A: {}, B: {}, C: {}}\n      edges: [{from: A, to: B, directed: true}, {from: B, to: C, directed: true}]",
    );
    assert_eq!(count(&g, g.host()), 3);
}

#[test]
fn multi_edges_loops_and_disconnected_patterns() {
    let host = "  vertices: {a: {}, b: {}, c: {}}\n  edges: [{from: a, to: b}, {from: a, to: b}, {from: c, to: c}]";
    // Two parallel pattern edges onto two parallel host edges: 2 orientations × 2 assignments.
    let g = pattern(
        host,
        "      vertices: {A: {}, B: {}}\n      edges: [{name: e, from: A, to: B}, {name: f, from: A, to: B}]",
    );
    assert_eq!(count(&g, g.host()), 4);
    // A loop matches only the loop, once.
    let g = pattern(host, "      vertices: {A: {}}\n      edges: [[A, A]]");
    assert_eq!(count(&g, g.host()), 1);
    // Two isolated vertices: ordered pairs of distinct vertices.
    let g = pattern(host, "      vertices: {A: {}, B: {}}");
    assert_eq!(count(&g, g.host()), 6);
    // An edge plus a separate vertex: the 4 parallel-edge matches, each
    // with c as the third vertex (the loop cannot be A–B: not injective).
    let g = pattern(host, "      vertices: {A: {}, B: {}, C: {}}\n      edges: [[A, B]]");
    assert_eq!(count(&g, g.host()), 4);
}

#[test]
fn labels_attributes_and_conditions_filter_matches() {
    let host = "  vertices: {a: {label: red, size: 1}, b: {label: red, size: 3}, c: {label: blue, size: 3}}";
    let g = pattern(host, "      vertices: {A: {label: red}}");
    assert_eq!(count(&g, g.host()), 2);
    let g = pattern(host, "      vertices: {A: {size: 3}}");
    assert_eq!(count(&g, g.host()), 2);
    let g = pattern(host, "      vertices: {A: {label: red, when: \"A.size > 2\"}}");
    assert_eq!(count(&g, g.host()), 1);
    let g = pattern(host, "      vertices: {A: {label: green}}");
    assert_eq!(count(&g, g.host()), 0);
}

#[test]
fn wildcards_match_anything_and_stay() {
    let g = grammar(
        "host:
  vertices: {a: {label: x}, b: {label: other, mark: 1}}
  edges: [[a, b]]
productions:
  - name: p
    mother:
      vertices: {A: {label: x}, W: {wildcard: true}}
      edges: [[A, W]]
    daughter:
      vertices: {N: {label: new, x: 1, y: 1}}
      edges: [[N, W]]
",
    );
    let d = g.derive(&mut Rng::from_seed(1), Some(1), 100).unwrap();
    let labels: Vec<&str> = d.graph.vertices().map(|v| v.label()).collect();
    // A and its edge are gone; the wildcard's vertex is untouched and joined to N.
    assert_eq!(labels, ["other", "new"]);
    let b = d.graph.vertices().next().unwrap();
    assert_eq!((b.degree(), b.attr("mark")), (1, Some(&Value::Num(1.0))));
}

#[test]
fn a_single_element_pattern_picks_uniformly() {
    let g = grammar(
        "steps: 1
host:
  vertices: {a: {}, b: {}, c: {}, d: {}, e: {}, f: {}}
  edges: [{from: a, to: b, label: x}, {from: b, to: c, label: x}, {from: c, to: d, label: x},
          {from: d, to: e, label: x}, {from: e, to: f, label: x}]
productions:
  - name: p
    mother: {vertices: {A: {}, B: {}}, edges: [{name: e, from: A, to: B, label: x}]}
    daughter: {vertices: {A: {}, B: {}}, edges: [{name: e, from: A, to: B, label: y}]}
",
    );
    let n = 5000;
    let mut counts = [0usize; 5];
    for seed in 0..n {
        let d = g.derive(&mut Rng::from_seed(seed), None, 100).unwrap();
        let i = d.graph.edges().position(|e| e.label() == "y").unwrap();
        counts[i] += 1;
    }
    let expect = n as f64 / 5.0;
    let sigma = (n as f64 * 0.2 * 0.8).sqrt();
    assert!(counts.iter().all(|&c| (c as f64 - expect).abs() < 4.0 * sigma), "{counts:?}");
}

#[test]
fn deleting_a_vertex_removes_its_edges() {
    let g = grammar(
        "host:
  vertices: {hub: {label: hub}, a: {}, b: {}, c: {}}
  edges: [[hub, a], [hub, b], [c, hub], [a, b], [hub, hub]]
productions:
  - name: cut
    mother: {vertices: {H: {label: hub}}}
    daughter: {}
",
    );
    let d = g.derive(&mut Rng::from_seed(1), None, 100).unwrap();
    assert_eq!(d.steps, 1);
    d.graph.check();
    assert_eq!((d.graph.vertex_count(), d.graph.edge_count()), (3, 1));
    let e = d.graph.edges().next().unwrap();
    let ends = [e.from(), e.to()].map(|v| d.graph.vertex(v).unwrap().pos());
    assert!(ends.iter().all(|p| *p == [0.0, 0.0]));
}

#[test]
fn priorities_and_caps_order_the_steps() {
    let src = "steps: 6
priority_limits: {0: 3}
host:
  vertices: {r: {label: root}}
productions:
  - name: first
    priority: 0
    mother: {vertices: {R: {label: root}}}
    daughter: {vertices: {R: {}, N: {label: a, x: \"R.x\", y: 0}}}
  - name: second
    priority: 1
    mother: {vertices: {R: {label: root}}}
    daughter: {vertices: {R: {}, N: {label: b, x: \"R.x\", y: 0}}}
";
    let g = grammar(src);
    let d = g.derive(&mut Rng::from_seed(3), None, 100).unwrap();
    assert_eq!(d.stats.applications, [3, 3]);
    assert_eq!(d.steps, 6);
    // The first group ran first: its vertices are the oldest.
    let labels: Vec<&str> = d.graph.vertices().skip(1).map(|v| v.label()).collect();
    assert_eq!(labels, ["a", "a", "a", "b", "b", "b"]);
    // A caller's step limit overrides the grammar's.
    assert_eq!(g.derive(&mut Rng::from_seed(3), Some(2), 100).unwrap().stats.applications, [2, 0]);
    // Without more work the derivation ends when nothing matches.
    let g = grammar(&src.replace("steps: 6\n", "").replace("priority: 1\n", "priority: 1\n    when: \"false\"\n"));
    let d = g.derive(&mut Rng::from_seed(3), None, 100).unwrap();
    assert_eq!((d.steps, d.stats.stop), (3, crate::Stop::NoMatch));
}

#[test]
fn productions_of_one_priority_are_tried_in_random_order() {
    let src = "steps: 1
host:
  vertices: {r: {label: root}}
productions:
  - {name: a, mother: {vertices: {R: {label: root}}}, daughter: {vertices: {R: {label: a}}}}
  - {name: b, mother: {vertices: {R: {label: root}}}, daughter: {vertices: {R: {label: b}}}}
";
    let g = grammar(src);
    let firsts: usize =
        (0..400).map(|s| g.derive(&mut Rng::from_seed(s), None, 10).unwrap().stats.applications[0]).sum();
    assert!((150..250).contains(&firsts), "{firsts} of 400");
}

#[test]
fn one_weighted_option_is_drawn_once_per_application() {
    let g = grammar(
        "steps: 4000
host:
  vertices: {r: {label: root}}
productions:
  - name: grow
    mother: {vertices: {R: {label: root}}}
    daughters:
      - weight: 1
        variables: {k: 1}
        vertices: {R: {last: \"{k}\"}, N: {label: a, kind: \"{k}\", x: 0, y: 0}}
      - weight: 3
        variables: {k: 2}
        vertices: {R: {last: \"{k}\"}, N: {label: b, kind: \"{k}\", x: 0, y: 0}}
",
    );
    let d = g.derive(&mut Rng::from_seed(9), None, 10_000).unwrap();
    let mut b = 0;
    for v in d.graph.vertices().skip(1) {
        let kind = v.attr("kind").and_then(Value::as_num).unwrap();
        // Structure (the label) and attributes come from the same option.
        assert_eq!(kind, if v.label() == "a" { 1.0 } else { 2.0 });
        b += usize::from(v.label() == "b");
    }
    let n = 4000.0;
    let sigma = (n * 0.75 * 0.25f64).sqrt();
    assert!((b as f64 - 0.75 * n).abs() < 4.0 * sigma, "{b} of 4000 took weight 3/4");
}

fn koch_generations(src: &str, steps: usize, seed: u64) -> Vec<u32> {
    let g = grammar(src);
    let d = g.derive(&mut Rng::from_seed(seed), Some(steps), 10_000).unwrap();
    let mut gens: Vec<u32> = d.graph.edges().map(|e| e.generation()).collect();
    gens.sort_unstable();
    gens
}

#[test]
fn oldest_matching_finishes_each_generation_first() {
    let src = example("koch");
    // 3 + 12 steps rewrite generations 0 and 1 completely: 48 edges of
    // generation 2, whatever the seed.
    for seed in 0..5 {
        assert_eq!(koch_generations(&src, 15, seed), vec![2; 48], "seed {seed}");
    }
    // Random matching mixes generations.
    let random = src.replace("match: oldest", "match: random");
    let mixed = (0..5).filter(|&s| koch_generations(&random, 15, s) != vec![2; 48]).count();
    assert!(mixed >= 4, "{mixed}");
    // New elements get the match's largest generation + 1.
    assert_eq!(koch_generations(&src, 1, 0), [0, 0, 1, 1, 1, 1]);
}

#[test]
fn spatial_matching_keeps_the_mothers_order() {
    let host =
        "  vertices: {a: {x: 0, y: 0}, b: {x: 2, y: 0}, c: {x: 5, y: 0}, d: {x: 5, y: 3}}\n  edges: [[a, b], [d, c]]";
    let across = "      vertices: {A: {at: [0, 0]}, B: {at: [1, 0]}}\n      edges: [[A, B]]";
    let g = pattern(host, across);
    assert_eq!(count(&g, g.host()), 4, "without spatial matching: 2 edges × 2 orientations");
    let spatial = |mother: &str| {
        grammar(&format!(
            "host:\n{host}\nproductions:\n  - name: p\n    spatial: true\n    mother:\n{mother}\n    daughter: {{}}\n"
        ))
    };
    let g = spatial(across);
    let m = g.matches(g.host(), "p").unwrap().unwrap();
    assert_eq!(m.len(), 1);
    assert_eq!(
        m[0].vertices.iter().map(|&v| g.host().vertex(v).unwrap().pos()).collect::<Vec<_>>(),
        [[0.0, 0.0], [2.0, 0.0]]
    );
    let g = spatial("      vertices: {A: {at: [0, 0]}, B: {at: [0, 1]}}\n      edges: [[A, B]]");
    let m = g.matches(g.host(), "p").unwrap().unwrap();
    assert_eq!(m.len(), 1);
    assert_eq!(g.host().vertex(m[0].vertices[1]).unwrap().pos(), [5.0, 3.0]);
}

fn placed(mother_edge: &str, host_edge: &str, daughter_at: &str) -> [f64; 2] {
    let g = grammar(&format!(
        "host:
  vertices: {{a: {{x: 2, y: 2}}, b: {{x: 2, y: 4}}}}
  edges: [{host_edge}]
productions:
  - name: p
    mother:
      vertices: {{A: {{at: [0, 0]}}, B: {{at: [1, 0]}}}}
      edges: [{mother_edge}]
    daughter:
      vertices: {{A: {{}}, B: {{}}, P: {{at: {daughter_at}, label: new}}}}
"
    ));
    let d = g.derive(&mut Rng::from_seed(1), Some(1), 100).unwrap();
    let p = d.graph.vertices().find(|v| v.label() == "new").unwrap().pos();
    [(p[0] * 1e9).round() / 1e9, (p[1] * 1e9).round() / 1e9]
}

#[test]
fn automatic_placement_by_hand() {
    let directed = "{from: A, to: B, directed: true}";
    // Host a(2,2) → b(2,4): the mother turned +90° and scaled by 2.
    // P at (0.5, 0.5): bary (0.5, 0) → (2, 3); (0, 0.5) → (−0.5, 0) → (−1, 0).
    assert_eq!(placed(directed, "{from: a, to: b, directed: true}", "[0.5, 0.5]"), [1.0, 3.0]);
    // Matched the other way round (b → a): turned −90°.
    assert_eq!(placed(directed, "{from: b, to: a, directed: true}", "[0.5, 0.5]"), [3.0, 3.0]);
    // On the mother's axis, beyond B: 2 units past b.
    assert_eq!(placed(directed, "{from: a, to: b, directed: true}", "[2, 0]"), [2.0, 6.0]);
    // A mother vertex's place lands on its match.
    assert_eq!(placed(directed, "{from: a, to: b, directed: true}", "[1, 0]"), [2.0, 4.0]);
}

#[test]
fn formulas_read_the_match_before_it_changes() {
    let g = grammar(
        "host:
  vertices: {a: {x: 1, y: 2, n: 5}}
productions:
  - name: p
    mother: {vertices: {A: {when: \"A.n > 0\"}}}
    vectors: {p: A}
    variables: {twice: \"A.n * 2\"}
    daughter:
      vertices:
        A: {n: \"{A.n - 1}\", x: \"A.x + 1\", label: \"n{A.n}\"}
        B: {pos: \"p + vec(twice, A.n)\", note: \"at {p} / {A.n:.2}\", label: copy}
",
    );
    let d = g.derive(&mut Rng::from_seed(1), Some(1), 100).unwrap();
    let a = d.graph.vertices().next().unwrap();
    assert_eq!((a.pos(), a.label(), a.attr("n")), ([2.0, 2.0], "n5", Some(&Value::Num(4.0))));
    let b = d.graph.vertices().nth(1).unwrap();
    assert_eq!(b.pos(), [11.0, 7.0]);
    assert_eq!(b.attr("note").and_then(Value::as_text), Some("at 1,2 / 5.00"));
    // The relabelled vertex left the label index of `n5`'s predecessor.
    d.graph.check();
}

#[test]
fn same_seed_same_result_and_yaml_round_trip() {
    for name in ["tree", "circle_pattern", "square_pattern", "facade"] {
        let g = grammar(&example(name));
        let run = |seed| g.derive(&mut Rng::from_seed(seed), None, 100_000).unwrap().graph;
        let (a, b, c) = (run(7), run(7), run(8));
        a.check();
        let yaml = a.to_yaml();
        assert_eq!(yaml, b.to_yaml(), "{name}");
        assert_ne!(yaml, c.to_yaml(), "{name}: another seed, another result");
        let svg = |g: &Graph| genform_export::write_svg(&g.to_scene(), &genform_export::SvgOptions::default());
        assert_eq!(svg(&a), svg(&b), "{name}");
        // The result reads back as a host and writes the same text.
        let back = grammar(&yaml);
        assert_eq!(back.host().to_yaml(), yaml, "{name}");
        assert_eq!(back.host().element_count(), a.element_count());
    }
}

#[test]
fn a_reused_graph_derives_what_a_fresh_one_does() {
    let names = ["koch", "tree", "circle_pattern", "square_pattern", "facade"];
    let grammars: Vec<GraphGrammar> = names.iter().map(|n| grammar(&example(n))).collect();
    // Each grammar derives into the graph the one before it returned:
    // Koch's generation buckets into the others' graphs and back.
    let mut previous = None;
    for seed in 0..2 {
        for (name, g) in names.iter().zip(&grammars) {
            let steps = (*name == "koch").then_some(500);
            let fresh = g.derive(&mut Rng::from_seed(seed), steps, 100_000).unwrap();
            let reused = g.derive_reusing(&mut Rng::from_seed(seed), steps, 100_000, previous.take()).unwrap();
            reused.graph.check();
            assert_eq!(reused.graph.to_yaml(), fresh.graph.to_yaml(), "{name}, seed {seed}");
            assert_eq!((reused.steps, &reused.stats), (fresh.steps, &fresh.stats), "{name}");
            previous = Some(reused.graph);
        }
    }
}

#[test]
fn odd_values_survive_the_round_trip() {
    let g = grammar(
        "host:
  vertices: {a: {x: 0.1, y: -1e-9, t: \"say \\\"hi\\\"\\n\\tbye {x}\", n: 1e300}}
productions:
  - name: p
    mother: {vertices: {A: {}}}
    daughter: {vertices: {A: {z: \"{0/0}\", w: \"{-1/0}\", true: 1}}}
",
    );
    let d = g.derive(&mut Rng::from_seed(1), Some(1), 10).unwrap();
    let yaml = d.graph.to_yaml();
    let back = grammar(&yaml);
    assert_eq!(back.host().to_yaml(), yaml);
    let v = back.host().vertices().next().unwrap();
    assert_eq!(v.pos(), [0.1, -1e-9]);
    assert_eq!(v.attr("t").and_then(Value::as_text), Some("say \"hi\"\n\tbye {x}"));
    assert!(v.attr("z").and_then(Value::as_num).unwrap().is_nan());
    assert_eq!(v.attr("w").and_then(Value::as_num), Some(f64::NEG_INFINITY));
    assert_eq!(v.attr("true").and_then(Value::as_num), Some(1.0));
}

#[test]
fn limits_end_with_clear_errors() {
    let grow = "host:\n  vertices: {r: {label: r}}\nproductions:\n  - name: g\n    mother: {vertices: {R: {label: r}}}\n    daughter: {vertices: {R: {}, N: {x: 0, y: 0}}}\n";
    let g = grammar(grow);
    let e = g.derive(&mut Rng::from_seed(1), None, 50).unwrap_err();
    assert_eq!(e, crate::DeriveError::TooManyElements { limit: 50, step: 49 });
    assert!(e.to_string().contains("50 elements"));
    let d = g.derive(&mut Rng::from_seed(1), Some(10), 50).unwrap();
    assert_eq!((d.steps, d.stats.stop), (10, crate::Stop::StepLimit));
}

#[test]
fn drawing_follows_the_svg_attributes() {
    let g = grammar(
        "host:
  vertices:
    a: {x: 0, y: 0}
    b: {x: 4, y: 2, svg_tag: rect, svg_width: 2, svg_height: 1, svg_fill: red, svg_z: -1}
    c: {x: 1, y: 1, svg_tag: hidden}
    d: {x: 2, y: 0, svg_tag: rect, svg_width: 3}
    e: {x: 0, y: 3, svg_tag: image, svg_href: i.png}
  edges:
    - {from: a, to: b, svg_stroke_width: 0.5, svg_stroke_dasharray: \"1 1\"}
    - {from: a, to: c, svg_tag: path, svg_d: \"M 0 0 L 1 1\"}
    - {from: b, to: a, svg_tag: rect}
    - {from: a, to: d, svg_tag: circle}
",
    );
    use genform_core::scene::Shape2dKind;
    use glam::Vec2;
    let scene = g.host().to_scene();
    let kinds: Vec<&Shape2dKind> = scene.shapes2d.iter().map(|s| &s.kind).collect();
    assert_eq!(kinds.len(), 8, "the hidden vertex is left out");
    // svg_z −1 first, then creation order.
    assert!(matches!(kinds[0], Shape2dKind::Rect { size, .. } if *size == Vec2::new(2.0, 1.0)));
    assert!(matches!(kinds[1], Shape2dKind::Circle { radius, .. } if *radius == 0.1));
    // A vertex's missing height is 1; an edge's box is the box its ends span.
    assert_eq!(kinds[2], &Shape2dKind::Rect { min: Vec2::new(2.0, 0.0), size: Vec2::new(3.0, 1.0) });
    let image = Shape2dKind::Image { href: "i.png".into(), min: Vec2::new(0.0, 3.0), size: Vec2::ONE };
    assert_eq!(kinds[3], &image);
    assert!(matches!(kinds[4], Shape2dKind::Line { .. }));
    assert!(matches!(kinds[5], Shape2dKind::Path { d } if d == "M 0 0 L 1 1"));
    assert_eq!(kinds[6], &Shape2dKind::Rect { min: Vec2::ZERO, size: Vec2::new(4.0, 2.0) });
    assert_eq!(kinds[7], &Shape2dKind::Circle { center: Vec2::new(1.0, 0.0), radius: 1.0 });
    let line = &scene.shapes2d[4].attributes;
    assert!(line.contains(&("stroke-width".into(), "0.5".into())));
    assert!(line.contains(&("stroke-dasharray".into(), "1 1".into())));
    assert!(scene.shapes2d[0].attributes.contains(&("fill".into(), "red".into())));
    let svg = genform_export::write_svg(&scene, &genform_export::SvgOptions::default());
    assert!(svg.contains("cm\" height="), "{svg}");
    assert!(svg.contains("<path transform=\"scale(1 -1)\" d=\"M 0 0 L 1 1\""), "{svg}");
}

#[test]
fn drawing_order_is_creation_order_after_many_deletions() {
    // Each step deletes the `tmp` vertex and makes a new one: 2,000 births
    // for four live elements, past what the drawing places by birth
    // directly (it sorts instead), and the same order either way.
    let src = |steps: usize| {
        format!(
            "steps: {steps}
host:
  vertices: {{x: {{label: keep}}, t: {{label: tmp}}, y: {{label: keep, x: 1}}}}
  edges: [[x, y]]
productions:
  - name: churn
    mother:
      vertices: {{T: {{label: tmp}}}}
    daughter:
      vertices: {{N: {{label: tmp, x: 2, y: 2}}}}
"
        )
    };
    for steps in [3, 2_000] {
        let g = grammar(&src(steps));
        let graph = g.derive(&mut Rng::from_seed(1), None, 100).unwrap().graph;
        let scene = graph.to_scene();
        let tags: Vec<&str> = scene.shapes2d.iter().map(|s| scene.tags[s.tag as usize].as_str()).collect();
        assert_eq!(tags, ["keep", "keep", "edge", "tmp"], "{steps} steps");
    }
}

mod props {
    use super::*;
    use proptest::prelude::*;

    fn label() -> impl Strategy<Value = String> {
        prop_oneof![Just(String::new()), Just(", label: a".to_string()), Just(", label: b".to_string())]
    }

    fn host() -> impl Strategy<Value = String> {
        (1usize..5, proptest::collection::vec((0usize..5, 0usize..5, any::<bool>(), label()), 0..6)).prop_map(
            |(n, edges)| {
                let vs: Vec<String> = (0..n).map(|i| format!("v{i}: {{x: {i}, y: {}}}", i % 2)).collect();
                let es: Vec<String> = edges
                    .iter()
                    .map(|(a, b, d, l)| format!("{{from: v{}, to: v{}, directed: {d}{l}}}", a % n, b % n))
                    .collect();
                format!("  vertices: {{{}}}\n  edges: [{}]", vs.join(", "), es.join(", "))
            },
        )
    }

    fn production() -> impl Strategy<Value = String> {
        let conditions = prop_oneof![
            Just(""),
            Just(", when: \"A.x < B.x\""),
            Just(", when: \"A.degree > 1\""),
            Just(", when: \"norm(B - A) >= 1\"")
        ];
        let pos = prop_oneof![
            Just("pos: \"A + (B - A) / 2\""),
            Just("at: [0.5, 1]"),
            Just("pos: \"rotate(B - A, 60) + A\""),
            Just("x: \"A.x + uniform(0, 1)\", y: 0")
        ];
        (
            1usize..4,
            proptest::collection::vec((0usize..3, 0usize..3, any::<bool>(), label()), 0..3),
            conditions,
            proptest::collection::vec(any::<bool>(), 3),
            pos,
            any::<bool>(),
            any::<bool>(),
            label(),
        )
            .prop_map(|(n, edges, when, keep, pos, spatial, oldest, new_label)| {
                let names = ["A", "B", "C"];
                let mv: Vec<String> =
                    (0..n).map(|i| format!("{}: {{at: [{i}, {}]{}}}", names[i], i % 2, if i == 0 { "" } else { when })).collect();
                let me: Vec<String> = edges
                    .iter()
                    .enumerate()
                    .map(|(k, (a, b, d, l))| {
                        format!("{{name: e{k}, from: {}, to: {}, directed: {d}{l}}}", names[a % n], names[b % n])
                    })
                    .collect();
                let kept: Vec<&str> = (0..n).filter(|&i| keep[i]).map(|i| names[i]).collect();
                let mut dv: Vec<String> = kept.iter().map(|k| format!("{k}: {{}}")).collect();
                let has_b = n > 1;
                if has_b {
                    dv.push(format!("N: {{{pos}{new_label}}}"));
                }
                let mut de: Vec<String> = Vec::new();
                if let (true, Some(k)) = (has_b, kept.first()) {
                    de.push(format!("{{from: {k}, to: N, directed: true}}"));
                }
                format!(
                    "  - name: p\n    spatial: {spatial}\n    match: {}\n    mother:\n      vertices: {{{}}}\n      edges: [{}]\n    daughter:\n      vertices: {{{}}}\n      edges: [{}]\n",
                    if oldest { "oldest" } else { "random" },
                    mv.join(", "),
                    me.join(", "),
                    dv.join(", "),
                    de.join(", ")
                )
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        #[test]
        fn random_small_grammars_never_panic(h in host(), p in production(), seed in 0u64..1000) {
            let src = format!("host:\n{h}\nproductions:\n{p}");
            if let Ok((g, _)) = compile(&SourceFile::new("p.gg.yaml", src.as_str())) {
                match g.derive(&mut genform_core::Rng::from_seed(seed), Some(25), 400) {
                    Ok(d) => {
                        d.graph.check();
                        let _ = d.graph.to_scene();
                        let back = grammar(&d.graph.to_yaml());
                        prop_assert_eq!(back.host().element_count(), d.graph.element_count());
                    }
                    Err(e) => prop_assert!(matches!(e, crate::DeriveError::TooManyElements { .. }), "{e}"),
                }
            }
        }

        #[test]
        fn any_text_compiles_or_fails_cleanly(s in "\\PC{0,200}") {
            let _ = compile(&SourceFile::new("x.gg.yaml", s.as_str()));
        }

        #[test]
        fn mangled_examples_compile_or_fail_cleanly(cut in 0usize..2000, insert in "[ :{}\\[\\],\"#A-z0-9-]{0,4}") {
            let src = example("square_pattern");
            let cut = cut.min(src.len());
            let cut = (0..=cut).rev().find(|&i| src.is_char_boundary(i)).unwrap_or(0);
            let text = format!("{}{}{}", &src[..cut], insert, &src[cut..]);
            if let Ok((g, _)) = compile(&SourceFile::new("m.gg.yaml", text.as_str())) {
                let _ = g.derive(&mut genform_core::Rng::from_seed(1), Some(40), 2000);
            }
        }
    }
}

#[test]
fn a_non_finite_daughter_position_is_an_error_naming_production_and_step() {
    let src = |a: u32| {
        format!(
            "host:\n  vertices: {{r: {{label: r, a: {a}}}}}\nproductions:\n  - name: split\n    mother: {{vertices: {{R: {{label: r}}}}}}\n    daughter: {{vertices: {{R: {{label: s}}, N: {{label: s, x: \"1 / (R.a - 1)\", y: 0}}}}}}\n"
        )
    };
    let e = grammar(&src(1)).derive(&mut Rng::from_seed(1), Some(5), 100).unwrap_err();
    // The position is the `x:` formula's, in the file.
    let text = src(1);
    let col = text.lines().nth(5).unwrap().find("1 / (R.a").unwrap() + 1;
    assert_eq!(
        e,
        crate::DeriveError::NonFinitePosition {
            production: "split".into(),
            at: format!("test.gg.yaml:6:{col}"),
            value: "inf".into(),
            step: 0
        }
    );
    assert!(e.to_string().contains("production `split`") && e.to_string().contains("step 0"), "{e}");
    // With a = 2 the vertex lands at x = 1.
    let d = grammar(&src(2)).derive(&mut Rng::from_seed(1), Some(5), 100).unwrap();
    assert_eq!(d.graph.element_count(), 2);
}

/// A graph whose last vertex was deleted is written with empty maps, and
/// reads back; one without edges keeps its vertices.
#[test]
fn empty_graphs_are_written_with_empty_lists() {
    let g = grammar(
        "host:
  vertices: {a: {x: 0, y: 0}}
productions:
  - name: gone
    mother: {vertices: {A: {}}}
    daughter: {}
",
    );
    let d = g.derive(&mut Rng::from_seed(1), Some(1), 10).unwrap();
    let yaml = d.graph.to_yaml();
    assert!(yaml.ends_with("host:\n  vertices: {}\n  edges: []\n"), "{yaml}");
    assert_eq!(grammar(&yaml).host().to_yaml(), yaml);
    let host = g.host().to_yaml();
    assert!(host.contains("vertices:\n    v0: {x: 0, y: 0}") && host.ends_with("edges: []\n"), "{host}");
}
