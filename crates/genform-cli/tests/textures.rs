//! Textured buildings end to end: the shipped `textured_house.sg` sampled
//! by the real binary into a GLB (read back by the independent `gltf`
//! crate: embedded images, a repeating sampler, `TEXCOORD_0` on the
//! textured primitives) and an OBJ (texture coordinates, `map_Kd`, the
//! images beside it); a texture that cannot be read is an error at its
//! position, and no image written beside an OBJ replaces a file the
//! grammar read.

mod common;

use common::{example, fails, ok, s};
use std::path::Path;

/// The shipped textures, as the grammar names them.
fn shipped(name: &str) -> Vec<u8> {
    std::fs::read(example("assets").join(name)).unwrap()
}

#[test]
fn the_textured_house_is_a_glb_with_its_images_and_texture_coordinates() {
    let tmp = tempfile::tempdir().unwrap();
    let house = example("textured_house.sg");
    ok(tmp.path(), &["sample", s(&house), "--seed", "3", "--out", "house.glb"]);
    ok(tmp.path(), &["sample", s(&house), "--seed", "3", "--out", "again.glb"]);
    let glb = std::fs::read(tmp.path().join("house.glb")).unwrap();
    assert_eq!(glb, std::fs::read(tmp.path().join("again.glb")).unwrap(), "same seed, same bytes");

    let (doc, buffers, images) = gltf::import_slice(&glb).expect("the gltf crate reads it, images decoded");
    let embedded: Vec<(String, Vec<u8>)> = doc
        .images()
        .map(|im| match im.source() {
            gltf::image::Source::View { view, mime_type } => {
                assert_eq!(mime_type, "image/png");
                let bytes = buffers[view.buffer().index()][view.offset()..view.offset() + view.length()].to_vec();
                (im.name().unwrap_or_default().to_string(), bytes)
            }
            gltf::image::Source::Uri { .. } => panic!("images are embedded, not referenced"),
        })
        .collect();
    assert_eq!(
        embedded,
        vec![("brick".to_string(), shipped("brick.png")), ("roof_tiles".to_string(), shipped("roof_tiles.png"))]
    );
    assert_eq!((images[0].width, images[0].height), (128, 128));
    for t in doc.textures() {
        assert_eq!(t.sampler().wrap_s(), gltf::texture::WrappingMode::Repeat);
        assert_eq!(t.sampler().wrap_t(), gltf::texture::WrappingMode::Repeat);
    }

    // Walls and roof textured, with coordinates; the glass plain.
    let mut seen = Vec::new();
    for mesh in doc.meshes() {
        for prim in mesh.primitives() {
            let material = prim.material();
            let name = material.name().unwrap_or_default().trim_end_matches(" (double-sided)").to_string();
            let texture = material.pbr_metallic_roughness().base_color_texture().map(|t| t.texture().index());
            let reader = prim.reader(|b| Some(&buffers[b.index()]));
            let uv: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|c| c.into_f32().collect());
            match name.as_str() {
                "wall@brick" => assert_eq!(texture, Some(0)),
                "roof@roof_tiles" => assert_eq!(texture, Some(1)),
                other => assert!(texture.is_none() && uv.is_none(), "{other}"),
            }
            if let Some(uv) = uv {
                let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
                assert_eq!(uv.len(), pos.len());
                assert!(uv.iter().flatten().all(|c| c.is_finite()));
                // World-anchored: coordinates span as many copies as the faces span metres.
                let span = |k: usize| {
                    let (lo, hi) = uv.iter().fold((f32::MAX, f32::MIN), |(lo, hi), c| (lo.min(c[k]), hi.max(c[k])));
                    hi - lo
                };
                assert!(span(0) > 4.0 && span(1) > 4.0, "{name}: {} × {} copies", span(0), span(1));
            }
            seen.push(name);
        }
    }
    for want in ["wall@brick", "roof@roof_tiles", "glass#3e5c76"] {
        assert!(seen.iter().any(|n| n == want), "{want} in {seen:?}");
    }
}

#[test]
fn the_textured_house_is_an_obj_with_texture_coordinates_and_its_images_beside() {
    let tmp = tempfile::tempdir().unwrap();
    let house = example("textured_house.sg");
    let run = ok(tmp.path(), &["sample", s(&house), "--seed", "3", "--out", "house.obj"]);
    let mtl = std::fs::read_to_string(tmp.path().join("house.mtl")).unwrap();
    assert!(mtl.contains("newmtl wall@brick\nKd 1 1 1\n"), "{mtl}");
    assert!(mtl.contains("map_Kd house.brick.png\n") && mtl.contains("map_Kd house.roof_tiles.png\n"), "{mtl}");
    assert_eq!(std::fs::read(tmp.path().join("house.brick.png")).unwrap(), shipped("brick.png"));
    assert_eq!(std::fs::read(tmp.path().join("house.roof_tiles.png")).unwrap(), shipped("roof_tiles.png"));
    assert!(run.stderr().contains("(4 files)"), "{}", run.show());
    let obj = std::fs::read_to_string(tmp.path().join("house.obj")).unwrap();
    let vt = obj.lines().filter(|l| l.starts_with("vt ")).count();
    let textured_faces = obj.lines().filter(|l| l.starts_with("f ") && l.contains('/')).count();
    assert!(vt > 100 && textured_faces > 30, "{vt} vt, {textured_faces} textured faces");
    // Every `f v/vt` names texture coordinates that exist.
    for l in obj.lines().filter(|l| l.starts_with("f ") && l.contains('/')) {
        for corner in l[2..].split(' ') {
            let t: usize = corner.split_once('/').unwrap().1.parse().unwrap();
            assert!((1..=vt).contains(&t), "{l}");
        }
    }
}

/// A grammar in `dir` whose walls show the texture `file` (copied from
/// the shipped brick unless `copy` is false).
fn grammar_with(dir: &Path, file: &str, copy: bool) -> std::path::PathBuf {
    if copy {
        std::fs::write(dir.join(file), shipped("brick.png")).unwrap();
    }
    let g = dir.join("t.sg");
    std::fs::write(&g, format!("A {{\n  lot(4, 4); extrude(3);\n  texture(\"{file}\", 1, 1);\n  shape;\n}}\n"))
        .unwrap();
    g
}

#[test]
fn a_texture_that_cannot_be_read_is_an_error_at_its_position() {
    let tmp = tempfile::tempdir().unwrap();
    let g = grammar_with(tmp.path(), "nowhere.png", false);
    let err = fails(tmp.path(), &["sample", s(&g), "--out", "x.glb"]);
    assert!(err.contains("t.sg:3:11") && err.contains("cannot load the texture \"nowhere.png\""), "{err}");
    assert!(err.contains("relative to the grammar file"), "{err}");
    // A file that is no PNG.
    std::fs::write(tmp.path().join("fake.png"), "not an image").unwrap();
    let g = grammar_with(tmp.path(), "fake.png", false);
    let err = fails(tmp.path(), &["sample", s(&g), "--out", "x.glb"]);
    assert!(err.contains("not a PNG image"), "{err}");
    assert!(!tmp.path().join("x.glb").exists());
}

#[test]
fn no_image_written_beside_an_obj_replaces_the_grammars_texture() {
    let tmp = tempfile::tempdir().unwrap();
    // The texture `h.png` of a model `x.obj` goes to `x.h.png`: a grammar
    // reading a file of that name must not lose it.
    std::fs::write(tmp.path().join("h.png"), shipped("brick.png")).unwrap();
    std::fs::write(tmp.path().join("x.h.png"), shipped("roof_tiles.png")).unwrap();
    let g = tmp.path().join("t.sg");
    std::fs::write(
        &g,
        "A {\n  lot(4, 4); extrude(3);\n  comp(f) { side: { texture(\"h.png\"); shape; } | top: { texture(\"x.h.png\"); shape; } }\n}\n",
    )
    .unwrap();
    let err = fails(tmp.path(), &["sample", s(&g), "--out", "x.obj"]);
    assert!(err.contains("x.h.png"), "{err}");
    assert_eq!(std::fs::read(tmp.path().join("x.h.png")).unwrap(), shipped("roof_tiles.png"), "the input is intact");
    assert!(!tmp.path().join("x.obj").exists(), "no OBJ naming an image that is not its own");
}
