//! `color("#rrggbb")`: the current tag with that colour, which exporters
//! and pictures show exactly (a tag named `name#rrggbb`).

use genform_core::{Generator, Rng, Scene, SourceFile};
use genform_shape::NoAssets;

fn tags(src: &str) -> Result<Vec<String>, String> {
    let (g, _) = genform_shape::compile(&SourceFile::new("t.sg", src), &NoAssets).map_err(|d| d.short())?;
    let limits = g.limits();
    let s = g.sample(&mut Rng::from_seed(1), &limits).unwrap();
    let mut scene = Scene::new();
    g.express(&s.genome, &limits, &mut scene).unwrap();
    Ok(scene.instances.iter().map(|i| scene.tags[i.tag as usize].clone()).collect())
}

#[test]
fn color_recolours_the_current_tag_until_the_next_tag_or_colour() {
    let src = "axiom A;\nA { tag(\"wall\"); color(\"#AA5533\"); box; [ color(\"#112233\"); box; B; ] box; tag(\"roof\"); box; }\n\
               B { color(\"#aa5533\"); box; }\n";
    assert_eq!(
        tags(src).unwrap(),
        ["wall#aa5533", "wall#112233", "B#aa5533", "wall#aa5533", "roof"],
        "a child starts with its own rule's tag; `[ ]` restores the colour"
    );
}

#[test]
fn a_colour_that_is_not_six_hex_digits_is_an_error_at_its_position() {
    let err = tags("axiom A;\nA { color(\"red\"); box; }\n").unwrap_err();
    assert!(err.contains("2:11") && err.contains("`color` takes one quoted colour `#rrggbb`"), "{err}");
}
