//! Properties of the `.gr8` front end: any valid system written by
//! `Display` compiles back to the same value, and no input makes the parser
//! panic.

use genform_core::SourceFile;
use genform_hemls::{
    Age, AxiomSide, Branch, Cmp, Condition, EdgeSym, Hemls, Item, Predecessor, Rule, Successor, Turn, compile,
    parse_str,
};
use proptest::prelude::*;

const TURNS: [Turn; 6] = [Turn::Right, Turn::Left, Turn::PitchDown, Turn::PitchUp, Turn::RollLeft, Turn::RollRight];

fn kind() -> impl Strategy<Value = u32> {
    prop_oneof![4 => 0u32..4, 1 => 0u32..=1_000_000]
}

fn turn() -> impl Strategy<Value = Turn> {
    (0..6usize).prop_map(|i| TURNS[i])
}

fn edge(timed: bool) -> impl Strategy<Value = EdgeSym> {
    let ages = if timed { vec![Age::Zero, Age::Same, Age::Plus1, Age::Minus1] } else { vec![Age::Zero] };
    (kind(), any::<bool>(), proptest::sample::select(ages)).prop_map(|(kind, reversed, age)| EdgeSym {
        kind,
        reversed,
        age,
    })
}

fn weight() -> impl Strategy<Value = f64> {
    prop_oneof![Just(1.0), 1e-6f64..1e6, (1u32..100).prop_map(f64::from)]
}

/// A successor whose main line has at least one edge and balanced turns.
fn successor(timed: bool) -> impl Strategy<Value = Successor> {
    let edges = proptest::collection::vec(edge(timed).prop_map(Item::Edge), 1..4);
    let branches = proptest::collection::vec(
        (proptest::collection::vec(turn(), 0..4), edge(timed))
            .prop_map(|(turns, edge)| Item::Branch(Branch { turns, edge })),
        0..4,
    );
    // Each pair is a turn and its inverse, so the counts balance.
    let pairs = proptest::collection::vec(0..3usize, 0..3).prop_map(|ps| {
        ps.into_iter().flat_map(|p| [Item::Turn(TURNS[2 * p]), Item::Turn(TURNS[2 * p + 1])]).collect::<Vec<_>>()
    });
    (edges, branches, pairs, weight()).prop_flat_map(|(mut items, b, p, weight)| {
        items.extend(b);
        items.extend(p);
        Just(items).prop_shuffle().prop_map(move |items| Successor { items, weight })
    })
}

fn rule() -> impl Strategy<Value = Rule> {
    (kind(), any::<bool>(), proptest::option::of(kind()), proptest::option::of(kind())).prop_flat_map(
        |(kind, timed, left, right)| {
            let pred = Predecessor { kind, timed, left, right };
            let cond = if timed {
                proptest::option::of(
                    (proptest::sample::select(vec![Cmp::Less, Cmp::Equal, Cmp::Greater]), any::<i64>())
                        .prop_map(|(cmp, value)| Condition { cmp, value }),
                )
                .boxed()
            } else {
                Just(None).boxed()
            };
            (cond, proptest::collection::vec(successor(timed), 1..4)).prop_map(move |(condition, successors)| Rule {
                pred,
                condition,
                successors,
                span: Default::default(),
            })
        },
    )
}

fn hemls() -> impl Strategy<Value = Hemls> {
    (
        proptest::collection::vec(
            (kind(), any::<bool>()).prop_map(|(kind, reversed)| AxiomSide { kind, reversed }),
            3..7,
        ),
        proptest::collection::vec(rule(), 1..5),
        prop_oneof![Just(60.0), 0.0f64..=360.0],
        any::<bool>(),
        proptest::option::of(0.0f64..=90.0),
    )
        .prop_map(|(axiom, rules, angle, sync, branch_angle)| Hemls {
            name: "random".to_string(),
            axiom,
            rules,
            angle,
            sync,
            branch_angle,
        })
}

fn unspanned(mut h: Hemls) -> Hemls {
    for r in &mut h.rules {
        r.span = Default::default();
    }
    h
}

/// Words the parser knows, glued at random into lines.
const VOCABULARY: &[&str] = &[
    "Edge0",
    "Edge1",
    "Edge2_i",
    "Edge3_i+1",
    "Edge0_i-1",
    "Edge",
    "EdgeX",
    "Edge9999999",
    "+",
    "-",
    "&",
    "^",
    "\\",
    "/",
    "~",
    "[",
    "]",
    "->",
    "<",
    ">",
    "=",
    "Angle",
    "Sync",
    "BranchAngle",
    "Weight",
    "If",
    "i",
    "60",
    "-1",
    "2.5",
    "nan",
    "inf",
    "//",
    "angle",
    "\n",
    "\n",
    "\n",
    "\r\n",
    "\t",
    "é",
    "[[",
    "Edge0+Edge1",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn written_systems_compile_back_equal(h in hemls()) {
        let text = h.to_string();
        let back = parse_str("random.gr8", &text).map_err(|e| TestCaseError::fail(format!("{text}\n{}", e.short())))?;
        prop_assert_eq!(unspanned(back), h, "{}", text);
    }

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let _ = compile(&SourceFile::new("bytes.gr8", text));
    }

    #[test]
    fn random_token_soup_never_panics(words in proptest::collection::vec(proptest::sample::select(VOCABULARY), 0..80)) {
        let _ = compile(&SourceFile::new("soup.gr8", words.join(" ")));
    }

    #[test]
    fn edited_valid_files_never_panic_and_round_trip_when_accepted(
        h in hemls(),
        edits in proptest::collection::vec((any::<usize>(), proptest::sample::select(VOCABULARY)), 1..4),
    ) {
        let text = h.to_string();
        let mut words: Vec<&str> = text.split(' ').collect();
        for (at, word) in edits {
            let n = words.len();
            words[at % n] = word;
        }
        let text = words.join(" ");
        if let Ok((h, _)) = compile(&SourceFile::new("edited.gr8", text.as_str())) {
            let back = parse_str("edited.gr8", &h.to_string()).map_err(|e| TestCaseError::fail(e.short()))?;
            prop_assert_eq!(unspanned(back), unspanned(h));
        }
    }
}
