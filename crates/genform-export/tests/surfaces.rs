//! Surfaces with typed edges through every writer, read back by independent
//! readers: `gltf` (GLB), `tobj` (OBJ), `ply-rs-bw` (PLY), `stl_io` (STL),
//! `png` and `resvg`'s `usvg` (previews).

use genform_core::scene::{Instance, Mesh, Primitive, Scene};
use genform_core::surface::{Guide, GuideKind, Surface, SurfaceEdge};
use genform_export::{ExportError, ExportOptions, Format, edge_color, export, grown_to_y_up};
use glam::{Affine3A, Vec3};
use std::collections::BTreeMap;
use std::sync::Arc;

/// A 2×2 grid of unit quads (a disc: 9 vertices, 12 edges, 4 faces), the
/// middle raised; the outer edges of type 0, the inner ones of type 3.
fn grid(tag: u32) -> Surface {
    let mut s = Surface::new(tag);
    let id = |i: u32, j: u32| 3 * j + i;
    for j in 0..3 {
        for i in 0..3 {
            let z = if (i, j) == (1, 1) { 0.6 } else { 0.0 };
            s.positions.push(Vec3::new(i as f32, j as f32, z));
        }
    }
    for j in 0..2 {
        for i in 0..2 {
            s.push_face(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    for j in 0..3 {
        for i in 0..3 {
            if i < 2 {
                s.edges.push(SurfaceEdge { a: id(i, j), b: id(i + 1, j), kind: if j == 1 { 3 } else { 0 } });
            }
            if j < 2 {
                s.edges.push(SurfaceEdge { a: id(i, j), b: id(i, j + 1), kind: if i == 1 { 3 } else { 0 } });
            }
        }
    }
    s
}

/// A box, the grid, the grid smoothed twice (lifted by 1.5) and three
/// guides: a boundary plane, an attractor and a repeller.
fn scene() -> Scene {
    let mut s = Scene::new();
    let hull = s.tag("hull");
    s.instances.push(Instance {
        transform: Affine3A::from_translation(Vec3::new(-2.0, 1.0, 0.0)),
        primitive: Primitive::Box,
        tag: hull,
    });
    let shell = s.tag("shell");
    let g = grid(shell);
    assert_eq!(g.euler_characteristic(), 1);
    let mut smooth = g.catmull_clark(2);
    smooth.positions.iter_mut().for_each(|p| p.z += 1.5);
    s.surfaces.push(g);
    s.surfaces.push(smooth);
    let plane = Mesh {
        name: "ground".into(),
        positions: vec![
            Vec3::new(-1.0, -1.0, -0.5),
            Vec3::new(3.0, -1.0, -0.5),
            Vec3::new(3.0, 3.0, -0.5),
            Vec3::new(-1.0, 3.0, -0.5),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    let (b, a, r) = (s.tag("boundary"), s.tag("attractor"), s.tag("repeller"));
    s.guides.push(Guide { kind: GuideKind::Mesh(Arc::new(plane)), tag: b });
    s.guides.push(Guide { kind: GuideKind::Point { at: Vec3::new(1.0, 1.0, 3.0), radius: 0.2 }, tag: a });
    s.guides.push(Guide { kind: GuideKind::Point { at: Vec3::new(0.5, 1.5, -0.3), radius: 0.2 }, tag: r });
    s
}

/// Per surface, its edges as vertex pairs by type.
fn edges_by_type(s: &Surface) -> BTreeMap<u32, Vec<[u32; 2]>> {
    let mut m: BTreeMap<u32, Vec<[u32; 2]>> = BTreeMap::new();
    for e in &s.edges {
        m.entry(e.kind).or_default().push([e.a, e.b]);
    }
    m
}

fn opts() -> ExportOptions {
    let mut o = ExportOptions::default();
    o.render.width = 480;
    o.render.height = 360;
    o
}

#[test]
fn glb_imports_with_gltf_and_has_a_lines_primitive_per_edge_type() {
    let s = scene();
    let glb = export(&s, Format::Glb, &opts()).unwrap();
    let (doc, buffers, _) = gltf::import_slice(&glb).expect("gltf imports the GLB");
    let names: Vec<String> = doc.nodes().map(|n| n.name().unwrap_or("").to_string()).collect();
    assert_eq!(names, ["hull_0", "shell_surface0", "shell_surface1"], "guides are not written");
    for (k, surface) in s.surfaces.iter().enumerate() {
        let mesh = doc.meshes().find(|m| m.name() == Some(&format!("shell_surface{k}"))).unwrap();
        let groups = edges_by_type(surface);
        let prims: Vec<_> = mesh.primitives().collect();
        assert_eq!(prims.len(), 1 + groups.len());
        // The faces: triangles with one unit normal per vertex.
        let faces = &prims[0];
        assert_eq!(faces.mode(), gltf::mesh::Mode::Triangles);
        let reader = faces.reader(|b| Some(&buffers[b.index()]));
        let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        assert_eq!(pos.len(), surface.positions.len());
        assert_eq!(pos[4], surface.positions[4].to_array());
        let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
        assert_eq!(normals.len(), pos.len());
        assert!(normals.iter().all(|n| (Vec3::from(*n).length() - 1.0).abs() < 1e-5 && n[2] > 0.0));
        let tri_count = reader.read_indices().unwrap().into_u32().count() / 3;
        let expected: usize = surface.faces().map(|f| f.len() - 2).sum();
        assert_eq!(tri_count, expected);
        // Then one LINES primitive per type, in ascending order, with the
        // type's material and exactly the type's edges.
        for (prim, (kind, pairs)) in prims[1..].iter().zip(&groups) {
            assert_eq!(prim.mode(), gltf::mesh::Mode::Lines);
            let want = if *kind == SurfaceEdge::UNTYPED { "edge_untyped".into() } else { format!("edge{kind}") };
            assert_eq!(prim.material().name(), Some(want.as_str()));
            let rgba = prim.material().pbr_metallic_roughness().base_color_factor();
            let srgb = edge_color(*kind).map(|c| f32::from(c) / 255.0);
            assert!((rgba[0] - srgb[0].powf(2.2)).abs() < 0.03, "{rgba:?} vs {srgb:?}");
            let reader = prim.reader(|b| Some(&buffers[b.index()]));
            assert_eq!(reader.read_positions().unwrap().count(), surface.positions.len());
            let idx: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
            let got: Vec<[u32; 2]> = idx.chunks(2).map(|c| [c[0], c[1]]).collect();
            assert_eq!(&got, pairs);
        }
    }
    // The smoothed surface has typed halves and untyped inner edges.
    let smooth = doc.meshes().find(|m| m.name() == Some("shell_surface1")).unwrap();
    let mats: Vec<String> = smooth.primitives().map(|p| p.material().name().unwrap_or("").to_string()).collect();
    assert_eq!(mats, ["shell (double-sided)", "edge0", "edge3", "edge_untyped"]);
}

#[test]
fn obj_reads_back_with_tobj_as_polygons_and_line_groups() {
    let s = scene();
    let obj = export(&s, Format::Obj, &opts()).unwrap();
    let load = tobj::LoadOptions { triangulate: false, ignore_lines: false, ignore_points: true, ..Default::default() };
    let (models, _) =
        tobj::load_obj_buf(&mut std::io::Cursor::new(&obj), &load, |_| Err(tobj::LoadError::OpenFileFailed))
            .expect("tobj reads the OBJ");
    let by_name: BTreeMap<&str, &tobj::Mesh> = models.iter().map(|m| (m.name.as_str(), &m.mesh)).collect();
    let names: Vec<&str> = models.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "hull_0",
            "shell_surface0",
            "shell_surface0_edges_type0",
            "shell_surface0_edges_type3",
            "shell_surface1",
            "shell_surface1_edges_type0",
            "shell_surface1_edges_type3",
            "shell_surface1_edges_untyped",
        ]
    );
    for (k, surface) in s.surfaces.iter().enumerate() {
        let faces = by_name[format!("shell_surface{k}").as_str()];
        let arities: Vec<usize> = surface.faces().map(<[u32]>::len).collect();
        assert_eq!(faces.face_arities.iter().map(|&a| a as usize).collect::<Vec<_>>(), arities, "quads kept whole");
        assert_eq!(faces.positions.len() / 3, surface.positions.len());
        for (kind, pairs) in edges_by_type(surface) {
            let group = if kind == SurfaceEdge::UNTYPED { "untyped".to_string() } else { format!("type{kind}") };
            let lines = by_name[format!("shell_surface{k}_edges_{group}").as_str()];
            assert_eq!(lines.face_arities.len(), pairs.len());
            assert!(lines.face_arities.iter().all(|&a| a == 2));
            // The first line joins the first edge's two positions.
            let p = |i: u32| {
                let i = lines.indices[i as usize] as usize;
                Vec3::new(lines.positions[3 * i], lines.positions[3 * i + 1], lines.positions[3 * i + 2])
            };
            // Surfaces are written +y up: a grown (x, y, z) is (x, z, −y).
            let [a, b] = pairs[0];
            assert!((p(0) - grown_to_y_up(surface.positions[a as usize])).length() < 1e-5);
            assert!((p(1) - grown_to_y_up(surface.positions[b as usize])).length() < 1e-5);
        }
    }
}

#[test]
fn ply_reads_back_with_ply_rs_faces_and_typed_edges() {
    use ply_rs_bw::ply::Property;
    let s = scene();
    let bytes = export(&s, Format::Ply, &opts()).unwrap();
    let parser = ply_rs_bw::parser::Parser::<ply_rs_bw::ply::DefaultElement>::new();
    let ply = parser.read_ply(&mut std::io::Cursor::new(&bytes)).expect("ply-rs reads the PLY");
    let verts = &ply.payload["vertex"];
    let faces = &ply.payload["face"];
    let edges = &ply.payload["surface_edge"];
    let box_tris = 12;
    let (sv, sf, se) = s
        .surfaces
        .iter()
        .fold((0, 0, 0), |(v, f, e), x| (v + x.positions.len(), f + x.face_count(), e + x.edges.len()));
    assert_eq!(verts.len(), 3 * box_tris + sv);
    assert_eq!(faces.len(), box_tris + sf);
    assert_eq!(edges.len(), se);
    let list = |f: &ply_rs_bw::ply::DefaultElement| match &f["vertex_indices"] {
        Property::ListInt(v) => v.clone(),
        other => panic!("{other:?}"),
    };
    // Triangles of the box, then the surfaces' quads pointing at their own
    // (shared) vertices.
    assert!(faces[..box_tris].iter().all(|f| list(f).len() == 3));
    assert!(faces[box_tris..].iter().all(|f| list(f).len() == 4));
    let first = list(&faces[box_tris]);
    let base = 3 * box_tris as i32;
    assert_eq!(first, [base, base + 1, base + 4, base + 3]);
    let int = |e: &ply_rs_bw::ply::DefaultElement, k: &str| match e[k] {
        Property::Int(i) => i,
        ref other => panic!("{other:?}"),
    };
    let all: Vec<&SurfaceEdge> = s.surfaces.iter().flat_map(|x| &x.edges).collect();
    let mut offset = base;
    let mut seen = 0;
    for x in &s.surfaces {
        for e in &x.edges {
            let got = &edges[seen];
            assert_eq!((int(got, "vertex1"), int(got, "vertex2")), (offset + e.a as i32, offset + e.b as i32));
            let kind = if e.kind == SurfaceEdge::UNTYPED { -1 } else { e.kind as i32 };
            assert_eq!(int(got, "type"), kind);
            seen += 1;
        }
        offset += x.positions.len() as i32;
    }
    assert_eq!(seen, all.len());
    assert!(edges.iter().any(|e| int(e, "type") == -1) && edges.iter().any(|e| int(e, "type") == 3));
}

#[test]
fn stl_reads_back_with_stl_io_as_triangles() {
    let s = scene();
    let bytes = export(&s, Format::Stl, &opts()).unwrap();
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(&bytes)).expect("stl_io reads the STL");
    let surface_tris: usize = s.surfaces.iter().flat_map(|x| x.faces()).map(|f| f.len() - 2).sum();
    assert_eq!(mesh.faces.len(), 12 + surface_tris);
    // The grid's faces are up (grown +z, written as +y) wherever they are not tilted by the bump.
    assert!(mesh.faces.iter().filter(|f| f.normal[1] > 0.5).count() >= surface_tris);
}

#[test]
fn same_scene_same_bytes_in_every_format() {
    let s = scene();
    for f in [Format::Obj, Format::Glb, Format::Ply, Format::Stl, Format::Svg, Format::Png] {
        assert_eq!(export(&s, f, &opts()).unwrap(), export(&s.clone(), f, &opts()).unwrap(), "{f}");
    }
}

fn decode(png_bytes: &[u8]) -> (Vec<u8>, u32, u32) {
    let mut reader = png::Decoder::new(std::io::Cursor::new(png_bytes)).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (buf, info.width, info.height)
}

/// Pixels within a small distance of `c`.
fn near(rgb: &[u8], c: [u8; 3], tol: i32) -> usize {
    rgb.chunks(3).filter(|p| (0..3).all(|i| (i32::from(p[i]) - i32::from(c[i])).abs() <= tol)).count()
}

#[test]
fn png_shows_faces_edge_colours_and_guides() {
    let s = scene();
    let bytes = export(&s, Format::Png, &opts()).unwrap();
    if let Ok(dir) = std::env::var("GENFORM_PREVIEW_DIR") {
        std::fs::write(std::path::Path::new(&dir).join("surfaces.png"), &bytes).unwrap();
    }
    let (rgb, w, h) = decode(&bytes);
    assert_eq!((w, h), (480, 360));
    let bg = opts().render.background;
    assert!(near(&rgb, bg, 0) < (w * h) as usize * 9 / 10, "mostly background");
    for kind in [0, 3] {
        let n = near(&rgb, edge_color(kind), 12);
        assert!(n > 40, "type {kind}: {n} pixels of {:?}", edge_color(kind));
    }
    // Both charges show as discs of their colour (mixed toward what is
    // behind them), blue and red.
    let blue = rgb.chunks(3).filter(|p| p[2] as i32 > p[0] as i32 + 60 && p[2] as i32 > p[1] as i32 + 30).count();
    let red = rgb.chunks(3).filter(|p| p[0] as i32 > p[1] as i32 + 80 && p[0] as i32 > p[2] as i32 + 80).count();
    assert!(blue > 30 && red > 30, "blue {blue}, red {red}");
    // Without its surfaces only the box is left: the edges made those colours.
    let mut plain = s.clone();
    plain.surfaces.clear();
    let (rgb2, _, _) = decode(&export(&plain, Format::Png, &opts()).unwrap());
    assert!(near(&rgb2, edge_color(3), 12) < 5);
}

#[test]
fn png_frames_the_model_and_near_guides_not_far_ones() {
    let mut s = scene();
    let bg = opts().render.background;
    let drawn = |rgb: &[u8]| rgb.chunks(3).filter(|p| *p != bg).count();
    let near_only = decode(&export(&s, Format::Png, &opts()).unwrap()).0;
    assert!(drawn(&near_only) > 480 * 360 / 10);
    // A far-away charge would shrink the model to a dot if it were
    // framed: it changes nothing.
    s.guides.push(Guide {
        kind: GuideKind::Point { at: Vec3::new(500.0, 0.0, 0.0), radius: 1.0 },
        tag: s.tags.iter().position(|t| t == "attractor").unwrap() as u32,
    });
    let with_far = decode(&export(&s, Format::Png, &opts()).unwrap()).0;
    assert!(with_far == near_only, "the far charge moved the frame");
}

#[test]
fn svg_has_one_line_per_edge_in_its_type_colour_and_faint_guides() {
    let s = scene();
    let svg = String::from_utf8(export(&s, Format::Svg, &opts()).unwrap()).unwrap();
    let tree = resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default()).expect("usvg parses it");
    assert!(tree.size().width() > 0.0);
    let lines: Vec<&str> = svg.lines().filter(|l| l.starts_with("<line ")).collect();
    let total: usize = s.surfaces.iter().map(|x| x.edges.len()).sum();
    assert_eq!(lines.len(), total);
    let hex = |c: [u8; 3]| format!("stroke=\"#{:02x}{:02x}{:02x}\"", c[0], c[1], c[2]);
    let mut by_kind: BTreeMap<u32, usize> = BTreeMap::new();
    for e in s.surfaces.iter().flat_map(|x| &x.edges) {
        *by_kind.entry(e.kind).or_default() += 1;
    }
    for (kind, n) in by_kind {
        let stroke = hex(edge_color(kind));
        assert_eq!(lines.iter().filter(|l| l.contains(&stroke)).count(), n, "type {kind}");
    }
    // The first grid edge (0,0)→(1,0), y flipped.
    assert!(lines.iter().any(|l| l.starts_with("<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"0\"")), "{svg}");
    // One face path per surface, two charge circles, one faint boundary.
    assert_eq!(svg.matches("<circle ").count(), 2);
    assert_eq!(svg.matches("fill-opacity=\"0.2\"").count(), 1);
    let faces = svg.lines().filter(|l| l.starts_with("<path fill=\"#") && !l.contains("opacity")).count();
    assert_eq!(faces, 1 + 2, "the box and two surfaces");
}

#[test]
fn malformed_surfaces_are_refused_with_a_reason() {
    let mut s = scene();
    s.surfaces[0].edges.push(SurfaceEdge { a: 2, b: 99, kind: 0 });
    for f in [Format::Obj, Format::Glb, Format::Ply, Format::Stl, Format::Svg, Format::Png] {
        let e = export(&s, f, &opts()).unwrap_err();
        assert!(matches!(e, ExportError::BadSurface { surface: 0, .. }), "{e}");
        assert!(e.to_string().contains("edge 12"), "{e}");
    }
    let mut s = scene();
    s.surfaces[1].face_vertices[3] = 1000;
    let e = export(&s, Format::Glb, &opts()).unwrap_err();
    assert!(e.to_string().contains("surface 1") && e.to_string().contains("vertex 1000"), "{e}");
    // The preview writers called directly leave a malformed surface out.
    let png = genform_export::render_png(&s, &opts().render);
    assert!(!png.is_empty());
    let svg = genform_export::write_svg(&s, &Default::default());
    assert_eq!(svg.matches("<line ").count(), s.surfaces[0].edges.len(), "only the well-formed grid's edges");
    let mut s = scene();
    s.surfaces[0].positions[0].x = f32::NAN;
    assert!(matches!(export(&s, Format::Obj, &opts()), Err(ExportError::NonFinite(_))));
    // Edges alone are something to write for the formats that hold lines.
    let mut wire = Scene::new();
    let mut w = grid(0);
    w.face_offsets = vec![0];
    w.face_vertices.clear();
    wire.surfaces.push(w);
    for f in [Format::Obj, Format::Glb, Format::Ply, Format::Svg] {
        assert!(export(&wire, f, &opts()).is_ok(), "{f}");
    }
    assert_eq!(export(&wire, Format::Stl, &opts()), Err(ExportError::EmptyScene(Format::Stl)));
    gltf::import_slice(export(&wire, Format::Glb, &opts()).unwrap()).expect("wire-only GLB imports");
}
