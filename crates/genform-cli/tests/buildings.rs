//! End-to-end tests of the building operations of `.sg` grammars: the
//! shipped row house samples with no flags into a model file, and the
//! building-envelope scene evolves (small) reproducibly and improves.

mod common;

use common::{fitness_columns, genform, json, ok, root, s, small_scene};

#[test]
fn the_row_house_samples_with_no_flags_into_a_glb_and_an_obj() {
    let tmp = tempfile::tempdir().unwrap();
    let house = root().join("examples/shape/row_house.sg");
    ok(tmp.path(), &["sample", s(&house), "--out", "house.glb"]);
    let glb = std::fs::read(tmp.path().join("house.glb")).unwrap();
    assert!(glb.starts_with(b"glTF") && glb.len() > 1000, "{} bytes", glb.len());
    // Same seed, same bytes.
    ok(tmp.path(), &["sample", s(&house), "--out", "again.glb"]);
    assert_eq!(glb, std::fs::read(tmp.path().join("again.glb")).unwrap());
    ok(tmp.path(), &["sample", s(&house), "--out", "house.obj"]);
    let obj = std::fs::read_to_string(tmp.path().join("house.obj")).unwrap();
    let faces = obj.lines().filter(|l| l.starts_with("f ")).count();
    // Walls, window tiles, a roof: far more than one box.
    assert!(faces > 100, "{faces} faces");
}

#[test]
fn the_l_house_and_the_office_block_sample_with_no_flags_reproducibly() {
    let tmp = tempfile::tempdir().unwrap();
    for name in ["l_house", "office_block"] {
        let g = root().join(format!("examples/shape/{name}.sg"));
        ok(tmp.path(), &["sample", s(&g), "--out", "a.glb"]);
        ok(tmp.path(), &["sample", s(&g), "--out", "b.glb"]);
        let a = std::fs::read(tmp.path().join("a.glb")).unwrap();
        assert!(a.starts_with(b"glTF") && a.len() > 1000, "{name}: {} bytes", a.len());
        assert_eq!(a, std::fs::read(tmp.path().join("b.glb")).unwrap(), "{name}: same seed, same bytes");
    }
}

#[test]
fn the_building_scenes_evolve_reproducibly() {
    // The voxel envelope and the façade silhouette.
    for (name, least) in [("building_envelope.toml", 0.0), ("building_facade.toml", 0.9)] {
        let tmp = tempfile::tempdir().unwrap();
        let scene = small_scene(
            tmp.path(),
            name,
            &[("population = 60", "population = 16\nelitism = 3"), ("generations = 30", "generations = 4")],
        );
        let sc = s(&scene);
        ok(tmp.path(), &["evolve", sc, "--seed", "5", "--threads", "1", "--out", "one", "-q"]);
        ok(tmp.path(), &["evolve", sc, "--seed", "5", "--threads", "2", "--out", "two", "-q"]);
        let read = |d: &str, f: &str| std::fs::read_to_string(tmp.path().join(d).join(f)).unwrap();
        assert_eq!(fitness_columns(&read("one", "stats.csv")), fitness_columns(&read("two", "stats.csv")), "{name}");
        assert_eq!(read("one", "best-genome.json"), read("two", "best-genome.json"), "{name}");
        let run = json(&tmp.path().join("one/run.json"));
        assert!(run["best_fitness"].as_f64().unwrap() > least, "{name}: {run}");
        assert!(std::fs::metadata(tmp.path().join("one/best.glb")).unwrap().len() > 0);
    }
}

#[test]
fn the_l_wings_leave_out_the_windows_the_other_wing_covers() {
    let tmp = tempfile::tempdir().unwrap();
    let wings = root().join("examples/shape/l_wings.sg");
    let primitives = |run: &common::Run| -> usize {
        let err = run.stderr();
        let at = err.find(" primitives").unwrap_or_else(|| panic!("{err}"));
        err[..at].rsplit(' ').next().unwrap().parse().unwrap()
    };
    let with = ok(tmp.path(), &["sample", s(&wings), "--seed", "3", "--out", "wings.glb"]);
    // The same grammar with every tile glazed.
    let text = std::fs::read_to_string(&wings).unwrap();
    let glazed = text.replace("is_side ? !overlaps(MainWing) : !overlaps(SideWing)", "1");
    assert_ne!(glazed, text, "the query is in the example");
    std::fs::write(tmp.path().join("glazed.sg"), glazed).unwrap();
    let without = ok(tmp.path(), &["sample", "glazed.sg", "--seed", "3", "--out", "glazed.glb"]);
    let (a, b) = (primitives(&with), primitives(&without));
    // Where the wings meet, whole columns of tiles reach into the other wing.
    assert!(a + 4 <= b, "{a} with the query, {b} without");
    let glb = std::fs::read(tmp.path().join("wings.glb")).unwrap();
    ok(tmp.path(), &["sample", s(&wings), "--seed", "3", "--out", "again.glb"]);
    assert_eq!(glb, std::fs::read(tmp.path().join("again.glb")).unwrap());
}

#[test]
fn the_city_block_derives_once_per_footprint_with_its_own_seed() {
    let tmp = tempfile::tempdir().unwrap();
    let block = root().join("examples/shape/city_block.sg");
    // No flags: the grammar's own footprint file (8 lots).
    let run = ok(tmp.path(), &["sample", s(&block), "--seed", "4", "--out", "block.glb"]);
    assert!(run.stderr().contains("8 footprints (seeds 4–11)"), "{}", run.show());
    let glb = std::fs::read(tmp.path().join("block.glb")).unwrap();
    ok(tmp.path(), &["sample", s(&block), "--seed", "4", "--out", "again.glb"]);
    assert_eq!(glb, std::fs::read(tmp.path().join("again.glb")).unwrap(), "same seed, same bytes");
    // Another file: two lots, the second an L; each lot is its own derivation.
    let lots = r#"{"type": "FeatureCollection", "features": [
        {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [10, 0], [10, 8], [0, 8], [0, 0]]]}},
        {"type": "Feature", "geometry": {"type": "Polygon",
         "coordinates": [[[20, 0], [30, 0], [30, 4], [24, 4], [24, 12], [20, 12], [20, 0]]]}}]}"#;
    std::fs::write(tmp.path().join("two.geojson"), lots).unwrap();
    let two = ok(tmp.path(), &["sample", s(&block), "--footprints", "two.geojson", "--out", "two.obj"]);
    assert!(two.stderr().contains("2 footprints (seeds 0–1)"), "{}", two.show());
    let obj = std::fs::read_to_string(tmp.path().join("two.obj")).unwrap();
    let xs: Vec<f64> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|v| v.split(' ').next().unwrap().parse().unwrap())
        .collect();
    let (lo, hi) = xs.iter().fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(lo > -0.5 && lo < 0.5 && hi > 29.5 && hi < 30.5, "the lots stand where the file puts them: x {lo}..{hi}");
    // The same two lots as the up-facing faces of an OBJ file (x, z).
    let obj_lots = "v 0 0 0\nv 10 0 0\nv 10 0 -8\nv 0 0 -8\nv 20 0 0\nv 30 0 0\nv 30 0 -4\nv 24 0 -4\nv 24 0 -12\nv 20 0 -12\n\
                    f 1 2 3 4\nf 5 6 7 8 9 10\nf 4 3 2 1\n";
    std::fs::write(tmp.path().join("lots.obj"), obj_lots).unwrap();
    let from_obj = ok(tmp.path(), &["sample", s(&block), "--footprints", "lots.obj", "--out", "from_obj.obj"]);
    assert!(from_obj.stderr().contains("2 footprints (seeds 0–1)"), "{}", from_obj.show());
    let same = std::fs::read_to_string(tmp.path().join("from_obj.obj")).unwrap().replace("from_obj.mtl", "two.mtl");
    assert!(obj == same, "the OBJ's lots give the model the GeoJSON's give");
    // Errors name the file and the lot.
    std::fs::write(
        tmp.path().join("bad.geojson"),
        r#"{"type": "Polygon", "coordinates": [[[0, 0], [4, 4], [4, 0], [0, 4]]]}"#,
    )
    .unwrap();
    let bad = genform(tmp.path(), &["sample", s(&block), "--footprints", "bad.geojson"]).fails();
    assert!(bad.stderr().contains("footprint 1 crosses itself"), "{}", bad.show());
    let genome = genform(tmp.path(), &["sample", s(&block), "--genome-out", "g.json"]).fails();
    assert!(genome.stderr().contains("each of the 8 footprints has its own"), "{}", genome.show());
}

#[test]
fn a_facade_invoked_for_every_wall_decorates_every_wall_and_replays() {
    let tmp = tempfile::tempdir().unwrap();
    let block = root().join("examples/shape/facade_every_wall.sg");
    let primitives = |run: &common::Run| -> usize {
        let err = run.stderr();
        let at = err.find(" primitives").unwrap_or_else(|| panic!("{err}"));
        err[..at].rsplit(' ').next().unwrap().parse().unwrap()
    };
    let all = ok(tmp.path(), &["sample", s(&block), "--seed", "2", "--out", "a/m.obj", "--genome-out", "g.json"]);
    // A saved genome replays byte for byte: the shared genes are read back
    // the way sampling grew them.
    ok(tmp.path(), &["derive", s(&block), "--genome", "g.json", "--out", "b/m.obj"]);
    for file in ["m.obj", "m.mtl"] {
        let a = std::fs::read(tmp.path().join("a").join(file)).unwrap();
        assert_eq!(a, std::fs::read(tmp.path().join("b").join(file)).unwrap(), "derive must reproduce {file}");
    }
    // The same grammar with the façade on the front wall only: the six
    // walls of the L carry several times its windows.
    let text = std::fs::read_to_string(&block).unwrap();
    let front = text.replace("side: Facade(floor_h)", "front: Facade(floor_h)");
    assert_ne!(front, text, "the façade arm is in the example");
    std::fs::write(tmp.path().join("front.sg"), front).unwrap();
    let one = ok(tmp.path(), &["sample", "front.sg", "--seed", "2", "--out", "front.glb"]);
    let (a, b) = (primitives(&all), primitives(&one));
    assert!(a > 2 * b, "{a} primitives on every wall, {b} on the front only");
}

#[test]
fn an_inset_that_leaves_nothing_is_a_warning_naming_its_place_once_per_district() {
    // Three 4 × 2 lots, each inset by 1.5: nothing is left inside any of
    // them. The sample still succeeds, and says so once with the count.
    let tmp = tempfile::tempdir().unwrap();
    let lots = r#"{"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 2], [0, 2], [0, 0]]]}},
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[10, 0], [14, 0], [14, 2], [10, 2], [10, 0]]]}},
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[20, 0], [24, 0], [24, 2], [20, 2], [20, 0]]]}}]}"#;
    std::fs::write(tmp.path().join("lots.geojson"), lots).unwrap();
    let grammar = "grammar \"inset\";\naxiom Lot;\nfootprints \"lots.geojson\";\nLot {\n    offset(-1.5) { inside: { extrude(3); shape; } | border: { shape; } }\n}\n";
    std::fs::write(tmp.path().join("inset.sg"), grammar).unwrap();
    let run = ok(tmp.path(), &["sample", "inset.sg", "--out", "m.obj"]);
    let warning = run.stderr().lines().find(|l| l.contains("leaves nothing inside")).map(str::to_string);
    let warning = warning.unwrap_or_else(|| panic!("no warning\n{}", run.show()));
    assert!(
        warning.starts_with("warning: ") && warning.contains("inset.sg:5:5") && warning.ends_with("(3 times)"),
        "{warning}"
    );
    assert_eq!(run.stderr().matches("leaves nothing inside").count(), 1, "{}", run.show());
}

#[test]
fn the_roof_faces_example_glazes_only_the_street_slope_and_walls_its_gables() {
    let tmp = tempfile::tempdir().unwrap();
    let g = root().join("examples/shape/roof_faces.sg");
    for seed in ["0", "1", "2"] {
        ok(tmp.path(), &["sample", s(&g), "--seed", seed, "--out", "house.obj"]);
        // Read back by an independent reader: every triangle with its
        // material and normal.
        let load = tobj::LoadOptions { triangulate: true, ..Default::default() };
        let (models, materials) = tobj::load_obj(tmp.path().join("house.obj"), &load).expect("tobj reads the OBJ");
        let materials = materials.expect("the .mtl");
        let mut glass = 0;
        let mut gable_up = 0.0f32;
        for m in &models {
            let name = m.mesh.material_id.map(|i| materials[i].name.as_str()).unwrap_or("");
            let p = &m.mesh.positions;
            for t in m.mesh.indices.chunks(3) {
                let v = |k: usize| glam::Vec3::from_slice(&p[3 * t[k] as usize..3 * t[k] as usize + 3]);
                let n = (v(1) - v(0)).cross(v(2) - v(0)).normalize();
                // Nothing looks down: the roof's underside is left out.
                assert!(n.y > -0.5, "seed {seed}: {name} faces down");
                if name.starts_with("glass") {
                    // On the slope that faces the street (+z), tilted.
                    assert!(n.z > 0.4 && n.y > 0.4, "seed {seed}: glass facing {n}");
                    glass += 1;
                }
                if name.starts_with("wall") && n.x.abs() > 0.99 {
                    // The gables: in the side walls' planes, up to the ridge.
                    gable_up = [v(0).y, v(1).y, v(2).y].into_iter().fold(gable_up, f32::max);
                }
            }
        }
        assert!(glass >= 4, "seed {seed}: {glass} glass triangles (two windows or more)");
        assert!(gable_up > 7.0, "seed {seed}: the gable walls reach {gable_up} m, above the eaves");
    }
}
