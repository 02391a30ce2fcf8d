//! End-to-end tests of HEMLS surface grammars (`.gr8`): the real binary on
//! the shipped `examples/hemls` grammars and environment files, in a
//! temporary folder, every output read back with an independent reader
//! (`tobj`, `gltf`, `ply-rs-bw`, `stl_io`, `png`, `roxmltree`).

mod common;

use common::{Run, genform, root, s};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn gr8(name: &str) -> PathBuf {
    root().join("examples/hemls").join(format!("{name}.gr8"))
}

fn env_file(name: &str) -> PathBuf {
    root().join("examples/hemls").join(format!("{name}.toml"))
}

/// Every shipped environment file, sorted.
fn env_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("examples/hemls"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// What a grown surface should show in every format.
#[derive(Clone, Copy, Debug)]
struct Expected {
    vertices: usize,
    edges: usize,
    faces: usize,
    /// Sides of every face.
    sides: usize,
    /// Distinct edge types.
    types: usize,
    /// Triangles after triangulating the faces (GLB, STL), where every
    /// vertex is a corner; an outline with straight runs of vertices (the
    /// Koch curves) may be cut into fewer triangles.
    triangles: Option<usize>,
    /// Total area, for the triangulations: growth is a similarity, so it is
    /// the seed's area (or the curve's) times 1.5⁸.
    area: f64,
}

/// 1.5⁸: the area scale of 4 steps at scale 1.5.
const GROWN: f64 = 25.62890625;

/// Genr8's four predefined grammars after the default 4 steps.
const PREDEFINED: [(&str, Expected); 4] = [
    (
        "koch",
        Expected { vertices: 768, edges: 768, faces: 1, sides: 768, types: 1, triangles: None, area: 0.682683 * GROWN },
    ),
    (
        "quadratic_koch",
        Expected { vertices: 16384, edges: 16384, faces: 1, sides: 16384, types: 1, triangles: None, area: GROWN },
    ),
    (
        "tiles3",
        Expected {
            vertices: 153,
            edges: 408,
            faces: 256,
            sides: 3,
            types: 3,
            triangles: Some(256),
            area: 0.4330127018922193 * GROWN,
        },
    ),
    (
        "tiles4",
        Expected { vertices: 289, edges: 544, faces: 256, sides: 4, types: 2, triangles: Some(512), area: GROWN },
    ),
];

/// Checks a triangulation's count and total area.
fn check_triangles(what: &str, triangles: &[[[f32; 3]; 3]], want: Expected) {
    match want.triangles {
        Some(n) => assert_eq!(triangles.len(), n, "{what} triangles"),
        None => assert!(triangles.len() <= want.vertices - 2, "{what}: {} triangles", triangles.len()),
    }
    let area: f64 = triangles
        .iter()
        .map(|[a, b, c]| {
            let (a, b, c) =
                (glam::Vec3::from(*a).as_dvec3(), glam::Vec3::from(*b).as_dvec3(), glam::Vec3::from(*c).as_dvec3());
            0.5 * (b - a).cross(c - a).length()
        })
        .sum();
    assert!((area - want.area).abs() < 1e-5 * want.area, "{what}: area {area}, not {}", want.area);
}

/// An OBJ as `tobj` reads it: the face object and the line groups.
struct Obj {
    vertices: usize,
    /// Sides of every face.
    faces: Vec<usize>,
    /// Lines per group name (`NAME_surface0_edges_typeN`).
    lines: BTreeMap<String, usize>,
    /// Raw `l` records in the text.
    l_records: usize,
}

fn read_obj(bytes: &[u8]) -> Obj {
    let load = tobj::LoadOptions { triangulate: false, ignore_lines: false, ignore_points: true, ..Default::default() };
    let (models, _) =
        tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &load, |_| Err(tobj::LoadError::OpenFileFailed))
            .expect("tobj reads the OBJ");
    let sides = |m: &tobj::Mesh| -> Vec<usize> {
        if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3] // tobj leaves the arities out when all are triangles
        } else {
            m.face_arities.iter().map(|&a| a as usize).collect()
        }
    };
    let surfaces: Vec<&tobj::Model> = models.iter().filter(|m| !m.name.contains("_edges_")).collect();
    assert_eq!(surfaces.len(), 1, "one surface: {:?}", models.iter().map(|m| &m.name).collect::<Vec<_>>());
    let lines = models
        .iter()
        .filter(|m| m.name.contains("_edges_"))
        .map(|m| {
            let s = sides(&m.mesh);
            assert!(s.iter().all(|&a| a == 2), "{}: lines are pairs", m.name);
            (m.name.clone(), s.len())
        })
        .collect();
    let text = String::from_utf8_lossy(bytes);
    Obj {
        vertices: surfaces[0].mesh.positions.len() / 3,
        faces: sides(&surfaces[0].mesh),
        lines,
        l_records: text.lines().filter(|l| l.starts_with("l ")).count(),
    }
}

fn check_obj(name: &str, bytes: &[u8], want: Expected) {
    let obj = read_obj(bytes);
    assert_eq!(obj.vertices, want.vertices, "{name}.obj vertices");
    assert_eq!(obj.faces.len(), want.faces, "{name}.obj faces");
    assert!(obj.faces.iter().all(|&n| n == want.sides), "{name}.obj: faces of {} sides", want.sides);
    assert_eq!(obj.l_records, want.edges, "{name}.obj `l` records");
    assert_eq!(obj.lines.len(), want.types, "{name}.obj line groups: {:?}", obj.lines);
    assert_eq!(obj.lines.values().sum::<usize>(), want.edges, "{name}.obj lines");
    for k in 0..want.types {
        assert!(obj.lines.contains_key(&format!("{name}_surface0_edges_type{k}")), "{name}: {:?}", obj.lines);
    }
}

fn check_glb(name: &str, bytes: &[u8], want: Expected) {
    let (doc, buffers, _) = gltf::import_slice(bytes).expect("gltf imports the GLB");
    let meshes: Vec<_> = doc.meshes().collect();
    assert_eq!(meshes.len(), 1, "{name}.glb");
    let prims: Vec<_> = meshes[0].primitives().collect();
    assert_eq!(prims.len(), 1 + want.types, "{name}.glb: faces, then one LINES primitive per edge type");
    assert_eq!(prims[0].mode(), gltf::mesh::Mode::Triangles);
    let reader = prims[0].reader(|b| Some(&buffers[b.index()]));
    let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    assert_eq!(pos.len(), want.vertices, "{name}.glb vertices");
    let idx: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
    let tris: Vec<[[f32; 3]; 3]> =
        idx.chunks(3).map(|t| [pos[t[0] as usize], pos[t[1] as usize], pos[t[2] as usize]]).collect();
    check_triangles(&format!("{name}.glb"), &tris, want);
    let mut lines = 0;
    for p in &prims[1..] {
        assert_eq!(p.mode(), gltf::mesh::Mode::Lines);
        assert!(p.material().name().is_some_and(|m| m.starts_with("edge")), "{name}.glb material");
        lines += p.reader(|b| Some(&buffers[b.index()])).read_indices().unwrap().into_u32().count() / 2;
    }
    assert_eq!(lines, want.edges, "{name}.glb lines");
}

fn check_ply(name: &str, bytes: &[u8], want: Expected) {
    use ply_rs_bw::ply::{DefaultElement, Property};
    let parser = ply_rs_bw::parser::Parser::<DefaultElement>::new();
    let ply = parser.read_ply(&mut std::io::Cursor::new(bytes)).expect("ply-rs reads the PLY");
    assert_eq!(ply.payload["vertex"].len(), want.vertices, "{name}.ply vertices");
    let faces = &ply.payload["face"];
    assert_eq!(faces.len(), want.faces, "{name}.ply faces");
    for f in faces {
        match &f["vertex_indices"] {
            Property::ListInt(v) => assert_eq!(v.len(), want.sides, "{name}.ply face"),
            other => panic!("{name}.ply: {other:?}"),
        }
    }
    let edges = &ply.payload["surface_edge"];
    assert_eq!(edges.len(), want.edges, "{name}.ply edges");
    let mut types: Vec<i32> = edges
        .iter()
        .map(|e| match e["type"] {
            Property::Int(t) => t,
            ref other => panic!("{name}.ply: {other:?}"),
        })
        .collect();
    types.sort_unstable();
    types.dedup();
    assert_eq!(types, (0..want.types as i32).collect::<Vec<_>>(), "{name}.ply edge types");
}

fn check_stl(name: &str, bytes: &[u8], want: Expected) {
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(bytes)).expect("stl_io reads the STL");
    let corner = |i: usize| {
        let v = mesh.vertices[i];
        [v[0], v[1], v[2]]
    };
    let tris: Vec<[[f32; 3]; 3]> =
        mesh.faces.iter().map(|f| [corner(f.vertices[0]), corner(f.vertices[1]), corner(f.vertices[2])]).collect();
    check_triangles(&format!("{name}.stl"), &tris, want);
}

/// Width, height and the share of pixels that differ from the corner's.
fn read_png(bytes: &[u8]) -> (u32, u32, f64) {
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().expect("png decodes");
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    let px = info.color_type.samples();
    let background = &buf[..px];
    let drawn = buf.chunks(px).filter(|p| *p != background).count();
    (info.width, info.height, drawn as f64 / (info.width * info.height) as f64)
}

fn check_png(name: &str, bytes: &[u8]) {
    let (w, h, drawn) = read_png(bytes);
    assert!(w >= 200 && h >= 200, "{name}.png is {w}×{h}");
    assert!(drawn > 0.05, "{name}.png: only {:.1}% drawn", 100.0 * drawn);
}

/// `<line>` elements (one per edge) and subpaths of the face `<path>`s.
fn read_svg(bytes: &[u8]) -> (usize, usize) {
    let text = std::str::from_utf8(bytes).expect("SVG is UTF-8");
    let doc = roxmltree::Document::parse(text).expect("SVG is well-formed XML");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    let lines = doc.descendants().filter(|n| n.has_tag_name("line")).count();
    let subpaths = doc
        .descendants()
        .filter(|n| n.has_tag_name("path"))
        .map(|n| n.attribute("d").unwrap_or("").matches('M').count())
        .sum();
    (lines, subpaths)
}

fn check_svg(name: &str, bytes: &[u8], want: Expected) {
    let (lines, faces) = read_svg(bytes);
    assert_eq!((lines, faces), (want.edges, want.faces), "{name}.svg: lines (edges) and face subpaths");
}

#[test]
fn predefined_grammars_read_back_in_every_format() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for (name, want) in PREDEFINED {
        for ext in ["obj", "glb", "ply", "stl", "png", "svg"] {
            let out = format!("{name}.{ext}");
            let run = genform(dir, &["sample", s(&gr8(name)), "--out", &out]).ok();
            let summary = format!("{} vertices, {} edges, {} faces", want.vertices, want.edges, want.faces);
            assert!(run.stderr().contains(&summary), "{out}: {}", run.stderr());
            let bytes = read(dir, &out);
            match ext {
                "obj" => check_obj(name, &bytes, want),
                "glb" => check_glb(name, &bytes, want),
                "ply" => check_ply(name, &bytes, want),
                "stl" => check_stl(name, &bytes, want),
                "png" => check_png(name, &bytes),
                _ => check_svg(name, &bytes, want),
            }
        }
    }
}

/// A file without its `mtllib` line (OBJs name their material library by
/// their own name); other files as they are.
fn without_mtllib(bytes: Vec<u8>) -> Vec<u8> {
    match std::str::from_utf8(&bytes) {
        Ok(text) if text.starts_with("# genform\nmtllib ") => {
            text.lines().filter(|l| !l.starts_with("mtllib ")).flat_map(|l| format!("{l}\n").into_bytes()).collect()
        }
        _ => bytes,
    }
}

#[test]
fn stochastic_grammar_repeats_by_seed_and_differs_by_seed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let st = gr8("stochastic_tiles");
    for ext in ["obj", "glb"] {
        for (seed, out) in [("5", "a"), ("5", "b"), ("6", "c")] {
            genform(dir, &["sample", s(&st), "--seed", seed, "--out", &format!("{out}.{ext}")]).ok();
        }
        let (a, b, c) =
            (read(dir, &format!("a.{ext}")), read(dir, &format!("b.{ext}")), read(dir, &format!("c.{ext}")));
        // The OBJs differ only in the name of their `.mtl` (`mtllib a.mtl`).
        let (a, b, c) = (without_mtllib(a), without_mtllib(b), without_mtllib(c));
        assert_eq!(a, b, "{ext}: same seed, same bytes");
        assert_ne!(a, c, "{ext}: another seed, another surface");
    }
    // Both are discs all the same.
    for f in ["a.obj", "c.obj"] {
        let obj = read_obj(&read(dir, f));
        assert_eq!(obj.vertices as i64 - obj.l_records as i64 + obj.faces.len() as i64, 1, "{f}");
    }
}

#[test]
fn every_step_writes_a_mesh_per_step_or_one_picture_of_small_multiples() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let t4 = gr8("tiles4");
    let run = genform(dir, &["sample", s(&t4), "--every-step", "--out", "grid.obj"]).ok();
    // Each step's OBJ with its material library.
    assert!(run.stderr().contains("grid-step0.obj … grid-step4.mtl (10 files)"), "{}", run.stderr());
    assert!(!dir.join("grid.obj").exists(), "only the step files");
    for k in 0..=4u32 {
        let obj = read_obj(&read(dir, &format!("grid-step{k}.obj")));
        let side = 2usize.pow(k) + 1;
        assert_eq!((obj.vertices, obj.faces.len()), (side * side, 4usize.pow(k)), "step {k}");
        assert_eq!(obj.vertices as i64 - obj.l_records as i64 + obj.faces.len() as i64, 1, "step {k}");
    }
    assert!(!dir.join("grid-step5.obj").exists());
    genform(dir, &["sample", s(&t4), "--out", "grid.obj"]).ok();
    let (last, one) = (without_mtllib(read(dir, "grid-step4.obj")), without_mtllib(read(dir, "grid.obj")));
    assert_eq!(last, one, "the last step is the surface");

    // Pictures: small multiples, one labelled panel per step in a 3 × 2 grid.
    genform(dir, &["sample", s(&t4), "--every-step", "--out", "all.png"]).ok();
    let names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(!names.iter().any(|n| n.starts_with("all-step")), "one picture: {names:?}");
    check_png("all", &read(dir, "all.png"));
    let (w, h, _) = read_png(&read(dir, "all.png"));
    assert_eq!((w, h), (3 * 400 + 4 * 4, 2 * (300 + 18) + 3 * 4), "3 × 2 panels of 400 × 300 with a caption line");
    // Every panel is seen through one camera: the step-0 square is drawn
    // smaller than the last step's grid of the same size ×16 in faces.
    let (w, rgb) = png_rgb(&read(dir, "all.png"));
    let drawn = |x0: usize, y0: usize| {
        (y0..y0 + 300)
            .flat_map(|y| (x0..x0 + 400).map(move |x| (x, y)))
            .filter(|&(x, y)| rgb[(y * w + x) * 3..][..3] != [236, 238, 241])
            .count()
    };
    let (first, last) = (drawn(4, 4), drawn(4 + 404, 4 + 318 + 4));
    assert!(first > 0 && last > 4 * first, "step 0 draws {first} pixels, step 4 {last}");
    // The SVG: every step's edges and faces, each in its own framed cell with its label.
    genform(dir, &["sample", s(&t4), "--every-step", "--out", "all.svg"]).ok();
    let (lines, faces) = read_svg(&read(dir, "all.svg"));
    assert_eq!((lines, faces), (744, 1 + 4 + 16 + 64 + 256), "4 + 12 + 40 + 144 + 544 edges");
    let text = String::from_utf8(read(dir, "all.svg")).unwrap();
    for (k, f) in [(0, "1 face"), (1, "4 faces"), (2, "16 faces"), (3, "64 faces"), (4, "256 faces")] {
        assert!(text.contains(&format!(">step {k}: {f}</text>")), "label of step {k}");
    }
    let doc = roxmltree::Document::parse(&text).unwrap();
    let frames: Vec<[f32; 2]> = doc
        .descendants()
        .filter(|n| n.has_tag_name("rect") && n.attribute("stroke") == Some("#bbbbbb"))
        .map(|n| ["x", "y"].map(|a| n.attribute(a).unwrap().parse().unwrap()))
        .collect();
    assert_eq!(frames.len(), 5, "a frame per step");
    assert!(frames.windows(2).all(|p| p[0] != p[1]), "no two steps drawn in one place");
}

/// An RGB PNG's width and pixels.
fn png_rgb(bytes: &[u8]) -> (usize, Vec<u8>) {
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().expect("png decodes");
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    buf.truncate(info.buffer_size());
    (info.width as usize, buf)
}

#[test]
fn smoothing_twice_gives_sixteen_times_the_quads() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let run = genform(dir, &["sample", s(&gr8("tiles4")), "--smooth", "2", "--out", "smooth.obj"]).ok();
    assert!(run.stderr().contains("256 faces (smoothed 2×)"), "{}", run.stderr());
    let obj = read_obj(&read(dir, "smooth.obj"));
    assert_eq!(obj.faces.len(), 16 * 256);
    assert!(obj.faces.iter().all(|&n| n == 4));
    assert_eq!(obj.vertices, 65 * 65);
    assert_eq!(obj.vertices as i64 - obj.l_records as i64 + obj.faces.len() as i64, 1);
    // Typed halves of the old edges and untyped new inner edges.
    assert!(obj.lines.contains_key("tiles4_surface0_edges_type0"), "{:?}", obj.lines);
    assert!(obj.lines.contains_key("tiles4_surface0_edges_untyped"), "{:?}", obj.lines);
}

#[test]
fn every_example_environment_grows_through_the_cli() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let files = env_files();
    assert!(files.len() >= 3, "{files:?}");
    for env in files {
        let stem = env.file_stem().unwrap().to_string_lossy().into_owned();
        for ext in ["obj", "png"] {
            let out = format!("{stem}.{ext}");
            genform(dir, &["sample", s(&gr8("tiles4")), "--env", s(&env), "--out", &out]).ok();
        }
        let obj = read_obj(&read(dir, &format!("{stem}.obj")));
        assert!(obj.faces.len() > 64, "{stem}: {} faces", obj.faces.len());
        assert_eq!(obj.vertices as i64 - obj.l_records as i64 + obj.faces.len() as i64, 1, "{stem}");
        check_png(&stem, &read(dir, &format!("{stem}.png")));
    }
    // The documentation's drape: six steps, over the sphere (without
    // --out, the summary alone, on stdout).
    let run = genform(dir, &["sample", s(&gr8("tiles4")), "--env", s(&env_file("drape_sphere")), "--steps", "6"]);
    let out = run.ok().stdout();
    assert!(out.contains("6 steps, 4225 vertices, 8320 edges, 4096 faces"), "{out}");
}

#[test]
fn mesh_boundaries_are_read_relative_to_the_environment_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("scene")).unwrap();
    // A closed cube [-1, 1]² × [-3, -1], wound outwards, under the sheet.
    let v = [(-1, -1, -3), (1, -1, -3), (1, 1, -3), (-1, 1, -3), (-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)];
    let f = [
        [1, 3, 2], // bottom
        [1, 4, 3],
        [5, 6, 7], // top
        [5, 7, 8],
        [1, 2, 6], // sides
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 4, 8],
        [3, 8, 7],
        [4, 1, 5],
        [4, 5, 8],
    ];
    let mut obj = String::new();
    for (x, y, z) in v {
        obj += &format!("v {x} {y} {z}\n");
    }
    for [a, b, c] in f {
        obj += &format!("f {a} {b} {c}\n");
    }
    std::fs::write(dir.join("scene/cube.obj"), obj).unwrap();
    let env = "steps = 4\ngravity = { axis = \"z\", magnitude = -0.5 }\n[[boundary]]\nmesh = \"cube.obj\"\n";
    std::fs::write(dir.join("scene/env.toml"), env).unwrap();
    genform(dir, &["sample", s(&gr8("tiles4")), "--env", "scene/env.toml", "--out", "over.obj"]).ok();
    let load = tobj::LoadOptions { triangulate: false, ignore_lines: true, ignore_points: true, ..Default::default() };
    let (models, _) = tobj::load_obj_buf(&mut std::io::Cursor::new(read(dir, "over.obj")), &load, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .unwrap();
    // The OBJ is +y up; the environment (and the cube) are in the growth frame, +z up.
    let p: Vec<[f32; 3]> = models[0].mesh.positions.chunks(3).map(|v| [v[0], -v[2], v[1]]).collect();
    let inside = p.iter().filter(|v| v[0].abs() < 0.999 && v[1].abs() < 0.999 && v[2] > -2.999 && v[2] < -1.001);
    assert_eq!(inside.count(), 0, "no vertex inside the cube");
    let resting = p.iter().filter(|v| v[0].abs() < 0.9 && v[1].abs() < 0.9 && (v[2] + 1.0).abs() < 1e-3).count();
    assert!(resting >= 9, "the sheet lies on the cube's top: {resting} vertices");
    // A mesh that is not there is named with the path it was looked for at.
    std::fs::write(dir.join("scene/env.toml"), env.replace("cube.obj", "gone.obj")).unwrap();
    let err =
        genform(dir, &["sample", s(&gr8("tiles4")), "--env", "scene/env.toml", "--out", "x.obj"]).fails().stderr();
    assert!(err.contains("gone.obj") && err.contains("boundary 1"), "{err}");
}

#[test]
fn info_prints_the_rewrite_system_and_a_disc_every_step() {
    let tmp = tempfile::tempdir().unwrap();
    let out = genform(tmp.path(), &["info", s(&gr8("tiles3"))]).ok().stdout();
    assert!(out.contains("3-sided seed, 3 rules, Angle 60, synchronous (Sync)"), "{out}");
    assert!(out.contains("Edge0 + Edge1 + Edge2\n"), "{out}");
    assert!(out.contains("Edge0 -> Edge0 [ + Edge2 ] [ + + Edge1 ] [ - Edge1 ] [ - - Edge2 ] Edge0\n"), "{out}");
    assert!(out.contains("\nSync\n"), "{out}");
    let header = out.lines().position(|l| l.starts_with("step") && l.ends_with("V-E+F")).expect("the step table");
    let rows: Vec<Vec<i64>> = out
        .lines()
        .skip(header + 1)
        .take_while(|l| !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 5, "{out}");
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), 5, "{out}");
        assert_eq!(r[0], k as i64);
        assert_eq!(r[1] - r[2] + r[3], 1, "row {k}");
        assert_eq!(r[4], 1, "row {k}: V-E+F");
        assert_eq!(r[3], 4i64.pow(k as u32), "row {k}: 4^k triangles");
    }
    assert_eq!(rows[4], [4, 153, 408, 256, 1]);
}

#[test]
fn malformed_grammar_names_file_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("bad.gr8"), "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 [ + Edge0\nedge0 -> Edge0\nAngle 60\n")
        .unwrap();
    let err = genform(dir, &["sample", "bad.gr8", "--out", "x.obj"]).fails().stderr();
    assert!(err.contains("bad.gr8:2:16") && err.contains("never closed"), "{err}");
    assert!(err.contains("bad.gr8:3:1") && err.contains("Edge0"), "every error at once: {err}");
    assert!(err.contains("2 errors in bad.gr8"), "{err}");
    assert!(!dir.join("x.obj").exists());
    let err = genform(dir, &["info", "bad.gr8"]).fails().stderr();
    assert!(err.contains("bad.gr8:2:16"), "{err}");
}

#[test]
fn bad_environment_files_name_file_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let t4 = gr8("tiles4");
    let sample = |env: &str| genform(dir, &["sample", s(&t4), "--env", env, "--out", "x.obj"]).fails().stderr();
    std::fs::write(dir.join("typo.toml"), "steps = 3\nscael = 1.2\n").unwrap();
    let err = sample("typo.toml");
    assert!(err.contains("unknown key `scael`") && err.contains("typo.toml:2:1"), "{err}");
    assert!(err.contains("did you mean `scale`"), "{err}");
    std::fs::write(dir.join("nan.toml"), "steps = 3\ngravity = { axis = \"z\", magnitude = nan }\n").unwrap();
    let err = sample("nan.toml");
    assert!(err.contains("nan.toml:2:37") && err.contains("finite"), "{err}");
    std::fs::write(dir.join("nan2.toml"), "[[attractor]]\nposition = [0, nan, 1]\nstrength = inf\n").unwrap();
    let err = sample("nan2.toml");
    assert!(err.contains("nan2.toml:2:16") && err.contains("nan2.toml:3:12"), "{err}");
    assert!(err.contains("2 errors in nan2.toml"), "{err}");
    assert!(!dir.join("x.obj").exists());
    let err = sample("missing.toml");
    assert!(err.contains("missing.toml"), "{err}");
}

#[test]
fn runaway_growth_stops_quickly_at_the_element_limit() {
    let tmp = tempfile::tempdir().unwrap();
    let start = Instant::now();
    let run = genform(tmp.path(), &["sample", s(&gr8("tiles4")), "--steps", "20", "--out", "big.obj"]);
    let elapsed = start.elapsed();
    let run: Run = run.fails();
    assert!(run.out.status.code().is_some_and(|c| c != 0));
    assert!(elapsed < Duration::from_secs(10), "took {elapsed:?}");
    let err = run.stderr();
    assert!(err.contains("growth stopped at step 11") && err.contains("max_vertices"), "{err}");
    assert!(!tmp.path().join("big.obj").exists(), "nothing written");
    let err = genform(tmp.path(), &["sample", s(&gr8("tiles4")), "--steps", "65"]).fails().stderr();
    assert!(err.contains("--steps 65") && err.contains("64"), "{err}");
}

#[test]
fn out_of_range_and_foreign_options_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let t4 = gr8("tiles4");
    let err = genform(dir, &["sample", s(&t4), "--smooth", "9", "--out", "x.obj"]).fails().stderr();
    assert!(err.contains("--smooth 9") && err.contains("6"), "{err}");
    let err = genform(dir, &["sample", s(&t4), "--box", "0,0,0,1,1,1", "--out", "x.obj"]).fails().stderr();
    assert!(err.contains("--box") && err.contains(".bsg") && err.contains(".gr8"), "{err}");
    assert!(!dir.join("x.obj").exists());
    // --smooth 6 is the most there is, and works.
    genform(dir, &["sample", s(&gr8("koch")), "--steps", "1", "--smooth", "6", "--out", "k.stl"]).ok();
}

/// (min, max) of `points`.
fn extent(points: impl IntoIterator<Item = [f32; 3]>) -> ([f32; 3], [f32; 3]) {
    let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (lo, hi)
}

#[test]
fn every_3d_format_has_the_surface_lying_flat_with_y_up() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for ext in ["obj", "ply", "stl", "glb"] {
        genform(dir, &["sample", s(&gr8("tiles4")), "--out", &format!("t.{ext}")]).ok();
    }
    let obj = {
        let load = tobj::LoadOptions { ignore_lines: true, ignore_points: true, ..Default::default() };
        let (models, _) = tobj::load_obj_buf(&mut std::io::Cursor::new(read(dir, "t.obj")), &load, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .unwrap();
        extent(models.iter().flat_map(|m| m.mesh.positions.chunks(3).map(|c| [c[0], c[1], c[2]])))
    };
    let ply = {
        use ply_rs_bw::ply::{DefaultElement, Property};
        let parser = ply_rs_bw::parser::Parser::<DefaultElement>::new();
        let ply = parser.read_ply(&mut std::io::Cursor::new(read(dir, "t.ply"))).unwrap();
        let f = |e: &DefaultElement, k: &str| match e[k] {
            Property::Float(v) => v,
            _ => panic!("float coordinates"),
        };
        extent(ply.payload["vertex"].iter().map(|e| [f(e, "x"), f(e, "y"), f(e, "z")]))
    };
    let stl = {
        let mesh = stl_io::read_stl(&mut std::io::Cursor::new(read(dir, "t.stl"))).unwrap();
        extent(mesh.vertices.iter().map(|v| [v[0], v[1], v[2]]))
    };
    let glb = {
        let (doc, buffers, _) = gltf::import_slice(read(dir, "t.glb")).unwrap();
        let mut points = Vec::new();
        for node in doc.nodes() {
            let Some(mesh) = node.mesh() else { continue };
            let m = glam::Mat4::from_cols_array_2d(&node.transform().matrix());
            for prim in mesh.primitives() {
                let r = prim.reader(|b| Some(&buffers[b.index()]));
                points.extend(r.read_positions().unwrap().map(|p| m.transform_point3(glam::Vec3::from(p)).to_array()));
            }
        }
        extent(points)
    };
    // tiles4 grows a flat sheet: as wide as deep, no height, the same in every format.
    for (name, (lo, hi)) in [("obj", obj), ("ply", ply), ("stl", stl), ("glb", glb)] {
        let size = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        assert!(size[0] > 1.0 && size[2] > 1.0 && size[1] < 1e-3, "{name}: size {size:?} is not flat with y up");
        for i in 0..3 {
            assert!((lo[i] - obj.0[i]).abs() < 1e-4 && (hi[i] - obj.1[i]).abs() < 1e-4, "{name} differs from obj");
        }
    }
}
