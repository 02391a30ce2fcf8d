//! End-to-end tests of real footprints: a district of Prague (Bubeneč,
//! 407 cadastral plots shipped with momepy, see
//! `crates/genform-app/tests/data/bubenec/README.md`) read as RFC 7946
//! longitude/latitude, as UTM metres and as EPSG:3857 builds centred on a
//! local origin and at the same size; lots the grammar cannot stand on
//! are skipped with a warning; the grammar reads each lot's properties;
//! the original GeoPackage builds its `buildings` and `plots` layers.

mod common;

use common::{genform, ok, root, s};
use std::path::Path;

/// The `v` lines of the OBJ file at `path` as `[x, y, z]`.
fn vertices(path: &Path) -> Vec<[f64; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|v| {
            let c: Vec<f64> = v.split_whitespace().take(3).map(|x| x.parse().unwrap()).collect();
            [c[0], c[1], c[2]]
        })
        .collect()
}

fn size(vs: &[[f64; 3]]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (i, o) in out.iter_mut().enumerate() {
        let (lo, hi) = vs.iter().fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v[i]), b.max(v[i])));
        *o = hi - lo;
    }
    out
}

#[test]
fn a_real_district_builds_centred_and_the_same_size_in_degrees_and_in_metres() {
    let tmp = tempfile::tempdir().unwrap();
    let block = root().join("examples/shape/city_block.sg");
    let data = root().join("crates/genform-app/tests/data/bubenec");
    let mut sizes = Vec::new();
    for (file, origin) in [
        ("plots_lonlat.geojson", "°N"),
        ("plots_utm33n.geojson", "of urn:ogc:def:crs:EPSG::32633"),
        ("plots_3857.geojson", "(read from EPSG:3857)"),
    ] {
        let out = format!("{file}.obj");
        let run = ok(tmp.path(), &["sample", s(&block), "--footprints", s(&data.join(file)), "--out", &out]);
        let err = run.stderr();
        let skipped = err.matches("the lot is skipped").count();
        assert!(err.contains(&format!("{} footprints (seeds 0–", 407 - skipped)), "{}", run.show());
        assert!(skipped <= 4, "few lots skipped: {}", run.show());
        assert!(err.contains("origin at") && err.contains(origin), "{}", run.show());
        // The origin travels with the model: an OBJ comment, GLB `asset.extras`.
        let obj = std::fs::read_to_string(tmp.path().join(&out)).unwrap();
        let comment = obj.lines().nth(1).unwrap_or_default();
        assert!(comment.starts_with("# origin: ") && comment.contains(origin), "{file}: {comment}");
        let vs = vertices(&tmp.path().join(&out));
        let far = vs.iter().map(|v| v[0].abs().max(v[2].abs())).fold(0.0, f64::max);
        assert!(far < 2000.0, "{file}: centred on a local origin, yet a vertex lies {far} m away");
        sizes.push((file, size(&vs)));
    }
    // The GLB's JSON chunk (after the 12-byte header and its own 8) holds
    // the origin in the asset's extras.
    ok(tmp.path(), &["sample", s(&block), "--footprints", s(&data.join("plots_lonlat.geojson")), "--out", "d.glb"]);
    let glb = std::fs::read(tmp.path().join("d.glb")).unwrap();
    let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let json: serde_json::Value = serde_json::from_slice(&glb[20..20 + len]).unwrap();
    let origin = json["asset"]["extras"]["origin"].as_str().unwrap_or_default();
    assert!(origin.contains("°N") && origin.contains("WGS 84"), "{}", json["asset"]);
    assert!(gltf::Gltf::from_slice(&glb).is_ok(), "still a glTF a reader opens");
    let (_, lonlat) = sizes[0];
    assert!(lonlat[0] > 300.0 && lonlat[2] > 300.0, "a district hundreds of metres across: {lonlat:?}");
    for (file, sz) in &sizes[1..] {
        for i in [0, 2] {
            let ratio = sz[i] / lonlat[i];
            assert!((ratio - 1.0).abs() < 0.01, "{file}: axis {i} is {ratio} times the lon/lat model's");
        }
    }
}

#[test]
fn a_bad_lot_is_skipped_with_a_warning_and_a_file_without_a_good_one_fails() {
    let tmp = tempfile::tempdir().unwrap();
    let block = root().join("examples/shape/city_block.sg");
    let lots = r#"{"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "good"}, "geometry": {"type": "Polygon",
         "coordinates": [[[0, 0], [10, 0], [10, 8], [0, 8], [0, 0]]]}},
        {"type": "Feature", "id": "way/42", "properties": {}, "geometry": {"type": "Polygon",
         "coordinates": [[[20, 0], [24, 4], [24, 0], [20, 4], [20, 0]]]}},
        {"type": "Feature", "properties": {"name": "short"}, "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 1]]]}}]}"#;
    std::fs::write(tmp.path().join("lots.geojson"), lots).unwrap();
    let run = ok(tmp.path(), &["sample", s(&block), "--footprints", "lots.geojson", "--out", "m.obj"]);
    let err = run.stderr();
    assert!(err.contains("1 footprints (seeds 0–0)"), "{}", run.show());
    assert!(err.contains("feature 2 (\"way/42\") crosses itself"), "{}", run.show());
    assert!(err.contains("feature 3 (\"short\"): an outer ring of 2 corners"), "{}", run.show());
    let bad = r#"{"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
         "coordinates": [[[20, 0], [24, 4], [24, 0], [20, 4], [20, 0]]]}}"#;
    std::fs::write(tmp.path().join("bad.geojson"), bad).unwrap();
    let fail = genform(tmp.path(), &["sample", s(&block), "--footprints", "bad.geojson"]).fails();
    assert!(
        fail.stderr().contains("no usable footprint") && fail.stderr().contains("crosses itself"),
        "{}",
        fail.show()
    );
}

#[test]
fn the_grammar_reads_each_lots_height_levels_and_use() {
    let tmp = tempfile::tempdir().unwrap();
    // OSM-style properties: one lot 12.5 m tall, one of 4 levels (3 m
    // each), one garage (use 5) of neither: 2.5 m.
    let lots = r#"{"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"height": "12.5", "building": "apartments"}, "geometry": {"type": "Polygon",
         "coordinates": [[[13.4000, 52.5200], [13.4001, 52.5200], [13.4001, 52.5201], [13.4000, 52.5201], [13.4000, 52.5200]]]}},
        {"type": "Feature", "properties": {"building:levels": 4}, "geometry": {"type": "Polygon",
         "coordinates": [[[13.4003, 52.5200], [13.4004, 52.5200], [13.4004, 52.5201], [13.4003, 52.5201], [13.4003, 52.5200]]]}},
        {"type": "Feature", "properties": {"building": "garage"}, "geometry": {"type": "Polygon",
         "coordinates": [[[13.4006, 52.5200], [13.4007, 52.5200], [13.4007, 52.5201], [13.4006, 52.5201], [13.4006, 52.5200]]]}}]}"#;
    std::fs::write(tmp.path().join("lots.geojson"), lots).unwrap();
    let grammar = r#"grammar "osm";
axiom Lot;
footprints "lots.geojson";
Lot {
    extrude(lot.height > 0 ? lot.height : lot.levels > 0 ? lot.levels * 3 : lot.use == 5 ? 2.5 : 9);
    shape;
}
"#;
    std::fs::write(tmp.path().join("osm.sg"), grammar).unwrap();
    let run = ok(tmp.path(), &["sample", "osm.sg", "--out", "m.obj"]);
    assert!(run.stderr().contains("3 footprints"), "{}", run.show());
    let vs = vertices(&tmp.path().join("m.obj"));
    // Lots lie west to east, about 20 m apart: each one's top by its x.
    let mut tops = [0.0f64; 3];
    for v in &vs {
        let k = ((v[0] + 24.0) / 20.0).floor().clamp(0.0, 2.0) as usize;
        tops[k] = tops[k].max(v[1]);
    }
    assert_eq!(tops.map(|t| (t * 100.0).round() / 100.0), [12.5, 12.0, 2.5], "{}", run.show());
}

#[test]
fn hip_roofs_stand_on_every_lot_of_the_district_with_and_without_an_overhang() {
    // 407 real plots of 4–49 corners, some with slivers and notches
    // narrower than the overhang: every lot gets its roof. (Plot 190 once
    // stopped the skeleton; an overhang of 0.3 once made plot 4's outline
    // cross itself; both used to stop the whole district.)
    let tmp = tempfile::tempdir().unwrap();
    let data = root().join("crates/genform-app/tests/data/bubenec/plots_lonlat.geojson");
    for overhang in ["0", "0.3", "1.5"] {
        let grammar = format!(
            "grammar \"hips\";\naxiom Lot;\nfootprints \"{}\";\nLot {{ extrude(6); shape; comp(f) {{ top: {{ roof_hip(30, {overhang}); }} }} }}\n",
            data.display().to_string().replace('\\', "/")
        );
        std::fs::write(tmp.path().join("hips.sg"), grammar).unwrap();
        let run = ok(tmp.path(), &["sample", "hips.sg", "--out", "d.obj"]);
        assert!(run.stderr().contains("407 footprints") && run.stderr().contains("814 primitives"), "{}", run.show());
        assert!(!run.stderr().contains("skipped"), "{}", run.show());
        // Roofs rise above the 6 m walls, and no higher than half the
        // widest plot (≈ 150 m) at 30°.
        let top = vertices(&tmp.path().join("d.obj")).iter().map(|v| v[1]).fold(f64::MIN, f64::max);
        assert!(top > 6.0 && top < 6.0 + 90.0, "overhang {overhang}: roof top {top}");
    }
}

#[test]
fn a_geopackage_layer_builds_hip_roofs_and_its_plots_are_the_geojson_plots() {
    // momepy's own GeoPackage, unchanged: layers `tessellation`,
    // `buildings` and `plots` (polygons), `streets` (lines), `dtm` (tiles).
    let tmp = tempfile::tempdir().unwrap();
    let data = root().join("crates/genform-app/tests/data/bubenec");
    let gpkg = data.join("bubenec.gpkg").display().to_string().replace('\\', "/");
    // The grammar names the layer: every one of the 144 buildings gets its roof.
    let grammar = format!(
        "grammar \"hips\";\naxiom Lot;\nfootprints \"{gpkg}#buildings\";\nLot {{ extrude(6); shape; comp(f) {{ top: {{ roof_hip(30, 0.3); }} }} }}\n"
    );
    std::fs::write(tmp.path().join("hips.sg"), grammar).unwrap();
    let run = ok(tmp.path(), &["sample", "hips.sg", "--out", "b.obj"]);
    assert!(run.stderr().contains("144 footprints") && run.stderr().contains("288 primitives"), "{}", run.show());
    assert!(!run.stderr().contains("skipped"), "{}", run.show());
    assert!(run.stderr().contains("origin at") && run.stderr().contains("(read from EPSG:3857)"), "{}", run.show());
    let top = vertices(&tmp.path().join("b.obj")).iter().map(|v| v[1]).fold(f64::MIN, f64::max);
    assert!(top > 6.0 && top < 60.0, "roof top {top}");
    // `--footprints FILE#LAYER` overrides it: the plots, as many and as
    // large as the GeoJSON made from them.
    let mut sizes = Vec::new();
    for (lots, out) in
        [(format!("{gpkg}#plots"), "p.obj"), (data.join("plots_3857.geojson").display().to_string(), "j.obj")]
    {
        let run = ok(tmp.path(), &["sample", "hips.sg", "--footprints", &lots, "--out", out]);
        assert!(run.stderr().contains("407 footprints") && run.stderr().contains("814 primitives"), "{}", run.show());
        sizes.push(size(&vertices(&tmp.path().join(out))));
    }
    for i in 0..3 {
        assert!((sizes[0][i] - sizes[1][i]).abs() < 0.05, "axis {i}: {:?}", sizes);
    }
    // No layer named, in a file of three polygon layers; a layer it lacks;
    // a layer of lines; a file that is no GeoPackage.
    let fail = genform(tmp.path(), &["sample", "hips.sg", "--footprints", &gpkg]).fails();
    assert!(
        fail.stderr().contains("holds 3 polygon layers (`tessellation`, `buildings`, `plots`): name one after a `#`"),
        "{}",
        fail.show()
    );
    let fail = genform(tmp.path(), &["sample", "hips.sg", "--footprints", &format!("{gpkg}#roads")]).fails();
    assert!(fail.stderr().contains("has no feature layer `roads`; its polygon layers are"), "{}", fail.show());
    let fail = genform(tmp.path(), &["sample", "hips.sg", "--footprints", &format!("{gpkg}#streets")]).fails();
    assert!(fail.stderr().contains("holds LINESTRING geometries, not polygons"), "{}", fail.show());
    std::fs::write(tmp.path().join("fake.gpkg"), "PK\u{3}\u{4} a zip, not a database").unwrap();
    let fail = genform(tmp.path(), &["sample", "hips.sg", "--footprints", "fake.gpkg#plots"]).fails();
    assert!(fail.stderr().contains("fake.gpkg is not a GeoPackage"), "{}", fail.show());
    assert!(!fail.stderr().contains("panicked"), "{}", fail.show());
}

#[test]
fn plots_read_with_their_streets_know_which_edge_faces_one() {
    // `#plots,streets`: the street lines of momepy's own street layer; a
    // plot facing one (within 60 m of an edge, along its normal) reads its
    // edge and distance, and its `front` is that edge.
    let tmp = tempfile::tempdir().unwrap();
    let gpkg =
        root().join("crates/genform-app/tests/data/bubenec/bubenec.gpkg").display().to_string().replace('\\', "/");
    let grammar = "grammar \"fronts\";\naxiom Lot;\n\
                   Lot { if (lot.street_edge >= 0 && lot.street > 0) { setback(2) { front: { extrude(3); shape; } } } }\n";
    std::fs::write(tmp.path().join("fronts.sg"), grammar).unwrap();
    let lots = format!("{gpkg}#plots,streets");
    let run = ok(tmp.path(), &["sample", "fronts.sg", "--footprints", &lots, "--out", "f.obj"]);
    assert!(run.stderr().contains("407 footprints"), "{}", run.show());
    // 376 of the 407 plots face a street: at least one front strip each
    // (more where several edges face the street's way).
    let n: usize = run.stderr().split(" primitives").next().unwrap().rsplit(' ').next().unwrap().parse().unwrap();
    assert!(n >= 376, "{n} front strips: {}", run.show());
    // Without the streets, no plot has one, so nothing is built.
    let bare = format!("{gpkg}#plots");
    let run = genform(tmp.path(), &["sample", "fronts.sg", "--footprints", &bare, "--out", "g.obj"]).fails();
    assert!(run.stderr().contains("the scene is empty"), "{}", run.show());
}
