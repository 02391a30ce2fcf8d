//! Occlusion queries (`inside()`, `overlaps()`, `touches()`) through the
//! whole pipeline: what a query sees is what the derivation placed before
//! it, outside the asking gene's own branch, filtered by tag.

use genform_core::{Generator, Mesh, Rng, Scene, SourceFile};
use genform_shape::{AssetResolver, ShapeGrammar};

struct NoAssets;

impl AssetResolver for NoAssets {
    fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
        Err(format!("no asset {path}"))
    }
}

fn compile(src: &str) -> Result<ShapeGrammar, String> {
    genform_shape::compile(&SourceFile::new("t.sg", src), &NoAssets).map(|(g, _)| g).map_err(|d| d.short())
}

/// The scene of `src` (seed 1) and how many instances carry tag `tag`.
fn count(src: &str, tag: &str) -> usize {
    let g = compile(src).unwrap_or_else(|e| panic!("{e}"));
    let limits = g.limits();
    let s = g.sample(&mut Rng::from_seed(1), &limits).unwrap();
    let mut scene = Scene::new();
    g.express(&s.genome, &limits, &mut scene).unwrap();
    let id = scene.tags.iter().position(|t| t == tag);
    scene.instances.iter().filter(|i| Some(i.tag as usize) == id).count()
}

/// A 4×2×2 block at the origin (placed by a sibling of the asking gene),
/// then ten unit probes along x from −4.5 to 4.5, each emitting a `hit`
/// box when `query` holds.
fn probes(query: &str) -> String {
    format!(
        "axiom A;\nA {{ Block; Probes; }}\nBlock {{ size(4, 2, 2); tag(\"block\"); box; }}\n\
         Probes {{ size(10, 1, 1); repeat(x, 1) {{ if ({query}) {{ tag(\"hit\"); box; }} }} }}\n"
    )
}

#[test]
fn queries_see_what_was_placed_before_by_other_genes() {
    // Probes centred at −4.5 … 4.5: four lie within x ∈ [−2, 2]; the two
    // at ±2.5 touch its ends (faces at ±2 … ±3 share the plane x = ±2).
    assert_eq!(count(&probes("inside()"), "hit"), 4);
    assert_eq!(count(&probes("overlaps()"), "hit"), 4);
    assert_eq!(count(&probes("touches()"), "hit"), 6);
    assert_eq!(count(&probes("!overlaps()"), "hit"), 6);
    assert_eq!(count(&probes("inside(block)"), "hit"), 4, "by tag");
    assert_eq!(count(&probes("inside(hit)"), "hit"), 0, "no `hit` box lies around another");
}

#[test]
fn the_asking_branch_is_no_occluder_of_itself() {
    // Placed by the asking gene or by an ancestor (as a mass is for the
    // façades of its faces), the block occludes nothing, as in CGA.
    let own = "axiom A;\nA { [ size(4, 2, 2); box; ] size(10, 1, 1); repeat(x, 1) { if (inside()) { tag(\"hit\"); box; } } }\n";
    assert_eq!(count(own, "hit"), 0);
    let parent = "axiom A;\nA { [ size(4, 2, 2); box; ] P; }\nP { size(10, 1, 1); repeat(x, 1) { if (inside()) { tag(\"hit\"); box; } } }\n";
    assert_eq!(count(parent, "hit"), 0);
    let sibling = "axiom A;\nA { Q; P; }\nQ { size(4, 2, 2); box; }\nP { size(10, 1, 1); repeat(x, 1) { if (inside()) { tag(\"hit\"); box; } } }\n";
    assert_eq!(count(sibling, "hit"), 4);
}

#[test]
fn an_unknown_tag_is_an_error_at_its_position() {
    let err = compile("axiom A;\nA { if (inside(Wnig)) { box; } }\nWing { box; }\n").unwrap_err();
    assert!(err.contains("2:9") && err.contains("no rule or tag is called `Wnig`"), "{err}");
    assert!(err.contains("inside(Wing)"), "a did-you-mean: {err}");
    let err = compile("axiom A;\nA { if (outside()) { box; } }\n").unwrap_err();
    assert!(err.contains("unknown function `outside`"), "{err}");
}
