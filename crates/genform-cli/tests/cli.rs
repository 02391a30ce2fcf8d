//! End-to-end tests: run the real `genform` binary in a temporary folder and
//! print everything it said when an expectation fails.

mod common;

use common::{example, genform, root, s};

#[test]
fn spaceship_glb_is_deterministic_and_well_formed() {
    let tmp = tempfile::tempdir().unwrap();
    let ship = example("spaceship.sg");
    genform(tmp.path(), &["sample", s(&ship), "--seed", "7", "--out", "a.glb"]).ok();
    genform(tmp.path(), &["sample", s(&ship), "--seed", "7", "--out", "b.glb"]).ok();
    let a = std::fs::read(tmp.path().join("a.glb")).unwrap();
    let b = std::fs::read(tmp.path().join("b.glb")).unwrap();
    assert_eq!(a, b, "same seed must give the same bytes");
    assert_eq!(&a[0..4], b"glTF");
    assert_eq!(u32::from_le_bytes(a[4..8].try_into().unwrap()), 2);
    assert_eq!(u32::from_le_bytes(a[8..12].try_into().unwrap()) as usize, a.len());
}

#[test]
fn spaceship_obj_has_one_box_per_part() {
    let tmp = tempfile::tempdir().unwrap();
    let ship = example("spaceship.sg");
    genform(tmp.path(), &["sample", s(&ship), "--seed", "7", "--out", "ship.obj", "--genome-out", "g.json"]).ok();
    let genome: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("g.json")).unwrap()).unwrap();
    let count = |sym: &str| genome["genes"].as_array().unwrap().iter().filter(|g| g["symbol"] == sym).count();
    // Body, top and top segments emit one box each; a wing gene emits a mirrored pair.
    let expected = count("Body") + count("Top") + count("TopSegment") + 2 * (count("Wing") + count("WingSegment"));
    assert!(count("Body") >= 1);
    let obj = std::fs::read_to_string(tmp.path().join("ship.obj")).unwrap();
    let objects = obj.lines().filter(|l| l.starts_with("o ") || l.starts_with("g ")).count();
    assert_eq!(objects, expected, "one OBJ object per emitted box");
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 8 * expected);
}

#[test]
fn granularity_sets_the_glb_nodes_and_obj_objects() {
    let tmp = tempfile::tempdir().unwrap();
    let ship = example("spaceship.sg");
    let nodes = |mode: &str| {
        let out = format!("{mode}.glb");
        genform(tmp.path(), &["sample", s(&ship), "--seed", "15", "--granularity", mode, "--out", &out]).ok();
        let glb = std::fs::read(tmp.path().join(&out)).unwrap();
        let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let json: serde_json::Value = serde_json::from_slice(&glb[20..20 + len]).unwrap();
        json["nodes"].as_array().unwrap().len()
    };
    // Seed 15 grows 86 boxes of 5 tags: past the 32 of `auto`, so merged.
    assert_eq!([nodes("auto"), nodes("merged"), nodes("tag"), nodes("instanced")], [1, 1, 5, 86]);
    genform(tmp.path(), &["sample", s(&ship), "--seed", "15", "--granularity", "tag", "--out", "t.obj"]).ok();
    let obj = std::fs::read_to_string(tmp.path().join("t.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("o ")).count(), 5);
    let r = genform(tmp.path(), &["sample", s(&ship), "--granularity", "nodes", "--out", "x.glb"]).fails();
    assert!(r.stderr().contains("auto, merged, tag, instanced"), "{}", r.stderr());
}

#[test]
fn derive_replays_a_saved_genome_byte_for_byte() {
    let tmp = tempfile::tempdir().unwrap();
    for (grammar, seed) in [("spaceship.sg", "3"), ("city_grid.sg", "5"), ("tree_v2.sg", "2")] {
        let g = example(grammar);
        // Same file names in two folders: the OBJ names its `.mtl` by name.
        genform(tmp.path(), &["sample", s(&g), "--seed", seed, "--out", "a/m.obj", "--genome-out", "g.json"]).ok();
        genform(tmp.path(), &["derive", s(&g), "--genome", "g.json", "--out", "b/m.obj"]).ok();
        for file in ["m.obj", "m.mtl"] {
            let a = std::fs::read(tmp.path().join("a").join(file)).unwrap();
            let b = std::fs::read(tmp.path().join("b").join(file)).unwrap();
            assert_eq!(a, b, "{grammar}: derive must reproduce sample's {file}");
        }
    }
}

#[test]
fn every_example_samples_into_every_format() {
    let tmp = tempfile::tempdir().unwrap();
    let mut n = 0;
    for entry in std::fs::read_dir(root().join("examples/shape")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("sg") {
            continue;
        }
        n += 1;
        for ext in ["glb", "obj", "ply", "stl", "png"] {
            let out = format!("m.{ext}");
            genform(tmp.path(), &["sample", s(&path), "--seed", "11", "--out", &out]).ok();
            assert!(std::fs::metadata(tmp.path().join(&out)).unwrap().len() > 0, "{} → {out}", path.display());
        }
    }
    assert!(n >= 7, "expected the seven shipped shape grammars, found {n}");
}

#[test]
fn info_lists_symbols_parameters_and_slots() {
    let tmp = tempfile::tempdir().unwrap();
    let r = genform(tmp.path(), &["info", s(&example("spaceship.sg"))]).ok();
    let out = r.stdout();
    for want in ["start `S`", "param", "uniform(0.6, 1.5)", "slot", "→ Wing", "limits: genes"] {
        assert!(out.contains(want), "missing {want:?} in:\n{out}");
    }
}

#[test]
fn grammar_errors_name_file_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("bad.sg"), "axiom S;\nS {\n  boxx;\n  param a: uniform(2, 1);\n}\n").unwrap();
    let r = genform(tmp.path(), &["sample", "bad.sg", "--out", "x.glb"]).fails();
    let err = r.stderr();
    assert!(err.contains("bad.sg:3:3"), "{err}");
    assert!(err.contains("bad.sg:4:"), "every error is reported: {err}");
    assert!(!tmp.path().join("x.glb").exists());
}

#[test]
fn a_genome_that_does_not_fit_is_rejected_with_a_reason() {
    let tmp = tempfile::tempdir().unwrap();
    let ship = example("spaceship.sg");
    genform(tmp.path(), &["sample", s(&ship), "--seed", "1", "--genome-out", "g.json"]).ok();
    let text = std::fs::read_to_string(tmp.path().join("g.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let body = v["genes"].as_array_mut().unwrap().iter_mut().find(|g| g["symbol"] == "Body").unwrap();
    body["params"]["size"][0] = serde_json::json!(99.0);
    std::fs::write(tmp.path().join("bad.json"), serde_json::to_string(&v).unwrap()).unwrap();
    let r = genform(tmp.path(), &["derive", s(&ship), "--genome", "bad.json", "--out", "x.obj"]).fails();
    assert!(r.stderr().contains("outside uniform(0.6, 1.5)"), "{}", r.stderr());
}

#[test]
fn unknown_output_format_is_a_clear_error() {
    let tmp = tempfile::tempdir().unwrap();
    let r = genform(tmp.path(), &["sample", s(&example("spaceship.sg")), "--out", "x.dae"]).fails();
    assert!(r.stderr().contains("use one of the extensions"), "{}", r.stderr());
}

#[test]
fn runaway_growth_stops_at_the_gene_limit_with_a_message() {
    let tmp = tempfile::tempdir().unwrap();
    let r = genform(tmp.path(), &["sample", s(&example("city_filling.sg")), "--max-genes", "5", "--seed", "2"]).ok();
    assert!(r.stderr().contains("gene limit (5)"), "{}", r.stderr());
}

#[test]
fn options_of_another_formalism_are_refused_by_the_table() {
    let tmp = tempfile::tempdir().unwrap();
    let ship = example("spaceship.sg");
    let args = ["sample", s(&ship), "--box", "0,0,0,9,9,9", "--world", "w", "--out", "x.glb"];
    let err = genform(tmp.path(), &args).fails().stderr();
    assert!(
        err.contains("--box and --world apply to box-split grammars (.bsg) only, not to shape grammars (.sg)"),
        "{err}"
    );
    assert!(!tmp.path().join("x.glb").exists());
    let koch = root().join("examples/graph/koch.gg.yaml");
    let err = genform(tmp.path(), &["sample", s(&koch), "--genome-out", "g.json"]).fails().stderr();
    assert!(err.contains("--genome-out applies to shape grammars (.sg) and L-systems (.ls .lpy) only"), "{err}");
}

#[test]
fn grammars_without_a_generator_say_why_in_every_generator_verb() {
    let tmp = tempfile::tempdir().unwrap();
    let castle = root().join("examples/boxsplit/castle.bsg");
    let err = genform(tmp.path(), &["derive", s(&castle), "--genome", "g.json", "--out", "x.obj"]).fails().stderr();
    assert!(
        err.contains("is evolved with codons") && err.contains("genform derive SCENE.toml --genome g.json"),
        "{err}"
    );
    let info = genform(tmp.path(), &["info", s(&castle)]).ok().stdout();
    assert!(info.contains("genomes: codon lists (codon scenes"), "{info}");
    // (Graph and box-split grammars in scenes are codon scenes, see tests/ge.rs.)
    let koch = root().join("examples/hemls/koch.gr8");
    let scene = format!(
        "grammar = {:?}\n[volume]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nvoxels = [4, 4, 4]\n[[volume.target]]\nmesh = \"t.obj\"\n",
        s(&koch)
    );
    std::fs::write(tmp.path().join("scene.toml"), scene).unwrap();
    let err = genform(tmp.path(), &["score", "scene.toml", "--genome", "g.json"]).fails().stderr();
    assert!(err.contains("scene.toml:1:11: HEMLS surface grammars are not evolved directly"), "{err}");
}

#[test]
fn derive_rebuilds_an_evolved_best_from_its_scene_tree_or_codon() {
    let tmp = tempfile::tempdir().unwrap();
    let scenes = root().join("examples/scenes");
    for (scene, flags, genome) in [
        ("spaceship_volume.toml", ["--generations", "2"], "best-genome.json"),
        ("ge_castle_volume.toml", ["--evaluations", "200"], "best-codons.json"),
    ] {
        let scene = scenes.join(scene);
        let mut args = vec!["evolve", s(&scene), "--seed", "1", "--out", "run", "-q"];
        args.extend(flags);
        genform(tmp.path(), &args).ok();
        let genome = format!("run/{genome}");
        let args = ["derive", s(&scene), "--genome", &genome, "--out", "again/best.obj"];
        let err = genform(tmp.path(), &args).ok().stderr();
        assert!(err.contains("→ again/best.obj and again/best.mtl"), "{err}");
        for file in ["best.obj", "best.mtl"] {
            let (again, best) = (tmp.path().join("again").join(file), tmp.path().join("run").join(file));
            assert_eq!(std::fs::read(&again).unwrap(), std::fs::read(&best).unwrap(), "{} {file}", scene.display());
        }
    }
}

#[test]
fn unknown_grammar_extensions_list_every_formalism() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("house.dae"), "").unwrap();
    let err = genform(tmp.path(), &["info", "house.dae"]).fails().stderr();
    for want in [".sg (shape grammar)", ".ls .lpy (L-system)", ".bsg (box-split grammar)", ".gg.yaml (graph grammar)"] {
        assert!(err.contains(want), "missing {want:?} in {err}");
    }
}

/// An output flag pointing at an input of the same command (under any
/// spelling) is refused before anything is written; the input is intact.
#[test]
fn outputs_never_overwrite_the_commands_inputs() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(example("spaceship.sg")).unwrap();
    std::fs::create_dir(tmp.path().join("sub")).unwrap();
    std::fs::write(tmp.path().join("ship.sg"), &text).unwrap();
    std::fs::copy(root().join("examples/lsystem/koch_snowflake.ls"), tmp.path().join("koch.ls")).unwrap();
    for (grammar, flag, path) in [
        ("ship.sg", "--genome-out", "ship.sg"),
        ("ship.sg", "--genome-out", "./sub/../ship.sg"),
        ("koch.ls", "--string-out", "koch.ls"),
    ] {
        let err = genform(tmp.path(), &["sample", grammar, flag, path]).fails().stderr();
        assert!(
            err.contains(&format!("{flag} {path} is the grammar")) && err.contains("an input of this command"),
            "{flag}: {err}"
        );
    }
    genform(tmp.path(), &["sample", "ship.sg", "--seed", "3", "--genome-out", "g.json"]).ok();
    let err =
        genform(tmp.path(), &["derive", "ship.sg", "--genome", "g.json", "--out", "sub/../g.json"]).fails().stderr();
    assert!(err.contains("is the genome g.json, an input"), "{err}");
    assert_eq!(std::fs::read_to_string(tmp.path().join("ship.sg")).unwrap(), text);
    assert!(std::fs::read_to_string(tmp.path().join("g.json")).unwrap().starts_with(['{', '[']));
}

/// `--threads` is bounded: a hundred thousand threads is refused with the
/// range before any run starts.
#[test]
fn thread_counts_are_bounded() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = root().join("examples/scenes/spaceship_volume.toml");
    for n in ["100000", "0", "many"] {
        let err = genform(tmp.path(), &["evolve", s(&scene), "--generations", "1", "--threads", n]).fails().stderr();
        assert!(err.contains("--threads"), "{n}: {err}");
    }
    assert!(!tmp.path().join("evolve-out").exists());
}

/// The distinct vertex colours of a PLY file, read with ply-rs.
fn ply_colours(bytes: &[u8]) -> std::collections::BTreeSet<[u8; 3]> {
    use ply_rs_bw::ply::{DefaultElement, Property};
    let parser = ply_rs_bw::parser::Parser::<DefaultElement>::new();
    let ply = parser.read_ply(&mut std::io::Cursor::new(bytes)).expect("ply-rs reads the PLY");
    let c = |e: &DefaultElement, k: &str| match e[k] {
        Property::UChar(v) => v,
        _ => panic!("uchar colour"),
    };
    ply.payload["vertex"].iter().map(|e| [c(e, "red"), c(e, "green"), c(e, "blue")]).collect()
}

#[test]
fn ply_files_carry_the_tag_and_block_colours() {
    let tmp = tempfile::tempdir().unwrap();
    let ship = example("spaceship.sg");
    genform(tmp.path(), &["sample", s(&ship), "--seed", "15", "--out", "ship.ply"]).ok();
    let colours = ply_colours(&std::fs::read(tmp.path().join("ship.ply")).unwrap());
    assert!(colours.len() >= 3, "a colour per tag: {colours:?}");
    let castle = root().join("examples/boxsplit/castle.bsg");
    genform(tmp.path(), &["sample", s(&castle), "--box", "0,0,0,39,19,39", "--out", "castle.ply"]).ok();
    let colours = ply_colours(&std::fs::read(tmp.path().join("castle.ply")).unwrap());
    assert!(colours.len() >= 2, "a colour per block: {colours:?}");
}
