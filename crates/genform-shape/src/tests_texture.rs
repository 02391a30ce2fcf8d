//! `texture("file.png", w, h)`: the tag it makes, the scene's texture
//! table, and errors at the file's position.

use super::*;
use genform_core::Mesh;

/// Textures that exist: any path ending in `.png` reads as a tiny PNG
/// header; anything else is missing.
struct Pngs;

impl AssetResolver for Pngs {
    fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
        Err(format!("no mesh {path}"))
    }

    fn load_texture(&self, path: &str) -> Result<Vec<u8>, String> {
        if !path.ends_with(".png") {
            return Err("no such file".into());
        }
        let mut b = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
        b.extend_from_slice(&[0, 0, 0, 8, 0, 0, 0, 4, 8, 2, 0, 0, 0]);
        Ok(b)
    }
}

fn express(src: &str) -> Scene {
    let file = SourceFile::new("t.sg", src);
    let (g, _) = compile(&file, &Pngs).unwrap_or_else(|e| panic!("{}", e.short()));
    let limits = g.limits();
    let s = g.sample(&mut Rng::from_seed(1), &limits).unwrap();
    let mut scene = Scene::new();
    g.express(&s.genome, &limits, &mut scene).unwrap();
    scene
}

fn errors(src: &str) -> String {
    match compile(&SourceFile::new("t.sg", src), &Pngs) {
        Ok(_) => panic!("expected errors"),
        Err(e) => e.short(),
    }
}

#[test]
fn a_texture_belongs_to_the_tag_and_keeps_its_colour() {
    let s = express(
        "A { tag(\"wall\"); texture(\"img/brick.png\", 2, 1); box; [ color(\"#aa0000\"); sphere; ] \
         [ tag(\"wall\"); box; ] B; }\n\
         B { texture(\"img/brick.png\", 2, 1); color(\"#00aa00\"); box; texture(\"x/brick.png\"); cylinder; }",
    );
    let names: Vec<&str> = s.instances.iter().map(|i| s.tags[i.tag as usize].as_str()).collect();
    assert_eq!(names, ["wall@brick", "wall@brick#aa0000", "wall", "B@brick#00aa00", "B@brick2#00aa00"]);
    // One image per (file, size); the same file at another size is another texture.
    assert_eq!(s.textures.len(), 2);
    assert_eq!((s.textures[0].name.as_str(), s.textures[0].size, s.textures[0].pixels), ("brick", [2.0, 1.0], [8, 4]));
    assert_eq!((s.textures[1].name.as_str(), s.textures[1].size), ("brick2", [1.0, 1.0]));
    let texture = |k: usize| s.texture_of(s.instances[k].tag).map(|t| t.name.as_str());
    assert_eq!(
        (0..5).map(texture).collect::<Vec<_>>(),
        [Some("brick"), Some("brick"), None, Some("brick"), Some("brick2")]
    );
}

#[test]
fn grammars_without_textures_keep_their_tags() {
    let s = express("A { tag(\"wall\"); box; color(\"#aa0000\"); box; }");
    assert_eq!(s.tags, ["wall", "wall#aa0000"]);
    assert!(s.textures.is_empty() && s.tag_textures.is_empty());
}

#[test]
fn occlusion_queries_see_a_textured_tag_as_its_plain_tag() {
    // `B` asks whether a `wall` overlaps it: the textured wall `W` placed does.
    let s = express(
        "A { W; B; }\n\
         W { tag(\"wall\"); texture(\"b.png\"); box; }\n\
         B { if (overlaps(wall)) { tag(\"hit\"); sphere; } }",
    );
    assert!(s.tags.iter().any(|t| t == "hit"), "{:?}", s.tags);
}

#[test]
fn texture_mistakes_are_errors_at_their_position() {
    let e = errors("A { texture(\"missing.jpg\"); box; }");
    assert!(e.contains("1:13") && e.contains("cannot load the texture \"missing.jpg\""), "{e}");
    assert!(e.contains("relative to the grammar file"), "{e}");
    let e = errors("A { texture(\"b.png\", 0, 1); box; }");
    assert!(e.contains("1:22") && e.contains("must be above 0"), "{e}");
    let e = errors("A { param w: uniform(1, 2); texture(\"b.png\", w, 1); box; }");
    assert!(e.contains("known when the grammar is compiled"), "{e}");
    let e = errors("A { texture(2); box; }");
    assert!(e.contains("quoted PNG file"), "{e}");
    let e = errors("A { texture(\"b.png\", 2); box; }");
    assert!(e.contains("no size or a width and a height"), "{e}");
    // Without a resolver that reads files, a texture is an error too.
    let e = match compile(&SourceFile::new("t.sg", "A { texture(\"b.png\"); box; }"), &NoAssets) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.short(),
    };
    assert!(e.contains("no texture files are available here"), "{e}");
}

#[test]
fn a_roofs_gables_may_name_a_textured_tag() {
    let s = express(
        "A { lot(6, 8); extrude(5); comp(f) { side: { tag(\"wall\"); texture(\"b.png\"); shape; } | top: R } }\n\
         R { roof_gable(35, 0, gables = \"wall@b\"); }",
    );
    // Four walls (polygons), the gables (one mesh), all `wall@b` and textured.
    let walls = s.polygons.iter().filter(|p| s.tags[p.tag as usize] == "wall@b").count();
    let gables = s.instances.iter().filter(|i| s.tags[i.tag as usize] == "wall@b").count();
    assert_eq!((walls, gables), (4, 1), "{:?}", s.tags);
    let tag = s.tags.iter().position(|t| t == "wall@b").unwrap() as u32;
    assert_eq!(s.texture_of(tag).map(|t| t.name.as_str()), Some("b"));
}
