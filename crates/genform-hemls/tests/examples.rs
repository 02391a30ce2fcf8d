//! The shipped grammars (`examples/hemls/*.gr8`): Genr8's four predefined
//! grammars exactly as the help files give them, and the extension examples.

use genform_core::SourceFile;
use genform_hemls::{Age, Cmp, Condition, Hemls, Item, Turn, compile, parse_str};

fn dir() -> String {
    format!("{}/../../examples/hemls", env!("CARGO_MANIFEST_DIR"))
}

fn load(name: &str) -> Hemls {
    let path = format!("{}/{name}.gr8", dir());
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    match compile(&SourceFile::new(path.as_str(), text)) {
        Ok((h, warnings)) => {
            assert!(warnings.items.is_empty(), "{name}: {}", warnings.short());
            h
        }
        Err(e) => panic!("{name}:\n{}", e.short()),
    }
}

fn names() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "gr8").then(|| p.file_stem().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    names.sort();
    names
}

fn unspanned(mut h: Hemls) -> Hemls {
    for r in &mut h.rules {
        r.span = Default::default();
    }
    h
}

#[test]
fn every_example_compiles_without_warnings_and_round_trips() {
    let names = names();
    assert!(names.len() >= 8, "{names:?}");
    for name in names {
        let h = load(&name);
        assert_eq!(h.name, name);
        let text = h.to_string();
        let again =
            parse_str(&format!("{name}.gr8"), &text).unwrap_or_else(|e| panic!("{name}:\n{text}\n{}", e.short()));
        assert_eq!(unspanned(again), unspanned(h), "{name}:\n{text}");
    }
}

#[test]
fn predefined_grammars_match_the_help_files() {
    let koch = load("koch");
    assert_eq!((koch.axiom.len(), koch.rules.len(), koch.angle, koch.sync), (3, 1, 60.0, false));
    assert_eq!(koch.rules[0].to_string(), "Edge0 -> Edge0 - Edge0 + + Edge0 - Edge0");

    let quad = load("quadratic_koch");
    assert_eq!((quad.axiom.len(), quad.angle), (4, 90.0));
    assert_eq!(quad.rules[0].to_string(), "Edge0 -> Edge0 + Edge0 - Edge0 - Edge0 Edge0 + Edge0 + Edge0 - Edge0");

    let t4 = load("tiles4");
    assert_eq!(
        t4.axiom.iter().map(|s| (s.kind, s.reversed)).collect::<Vec<_>>(),
        [(0, false), (1, true), (0, false), (1, true)]
    );
    assert!(!t4.sync);
    assert_eq!(t4.rules[1].to_string(), "Edge1 -> Edge1 [ + Edge0 ] [ - Edge0 ] Edge1");

    let t3 = load("tiles3");
    assert!(t3.sync);
    assert_eq!(t3.angle, 60.0);
    assert_eq!(t3.branch_angle, None);
    assert_eq!(t3.rules[0].to_string(), "Edge0 -> Edge0 [ + Edge2 ] [ + + Edge1 ] [ - Edge1 ] [ - - Edge2 ] Edge0");
    // Each tile rule: old edge split in two, four branches from the midpoint.
    for r in &t3.rules {
        let items = &r.successors[0].items;
        assert_eq!(items.iter().filter(|i| matches!(i, Item::Branch(_))).count(), 4);
        assert_eq!(items.iter().filter(|i| matches!(i, Item::Edge(_))).count(), 2);
    }
}

#[test]
fn extension_examples_use_their_extension() {
    let s = load("stochastic_tiles");
    assert!(s.rules.iter().all(|r| r.successors.len() == 2 && r.successors[0].weight > r.successors[1].weight));

    let t = load("timed_tiles");
    assert!(t.rules[0].pred.timed);
    assert_eq!(t.rules[0].condition, Some(Condition { cmp: Cmp::Less, value: 3 }));
    assert!(t.rules[0].successors[0].items.iter().any(|i| matches!(i, Item::Edge(e) if e.age == Age::Plus1)));

    let c = load("context_tiles");
    assert!(c.rules.iter().any(|r| r.pred.left.is_some() && r.pred.right.is_some()));
    assert!(c.rules.iter().any(|r| r.pred.left.is_some() && r.pred.right.is_none()));
    assert!(c.rules.iter().any(|r| r.pred.left.is_none() && r.pred.right.is_some()));

    let f = load("folded_tiles");
    let pitches = |items: &[Item]| {
        items.iter().any(|i| match i {
            Item::Turn(t) => *t == Turn::PitchDown,
            Item::Branch(b) => b.turns.contains(&Turn::PitchDown),
            Item::Edge(_) => false,
        })
    };
    assert!(f.rules.iter().all(|r| pitches(&r.successors[0].items)));
    assert_eq!(f.branch_angle, Some(45.0));
}
