//! Test helpers: grammars from a tiny `.gr8`-like notation (space-separated
//! tokens, nested brackets flattened into sibling branches), independent of
//! the real front end. Shared by the unit tests and `tests/growth.rs`
//! (included there with `#[path]`, where `crate::grammar` is a re-export).
#![allow(dead_code)]

use crate::grammar::{
    Age, AxiomSide, Branch, Cmp, Condition, EdgeSym, Hemls, Item, Predecessor, Rule, Successor, Turn,
};
use crate::settings::Settings;
use genform_core::Span;
use glam::DVec3;

/// Settings with `steps` steps and uniform `scale`, everything else default.
pub fn settings(steps: u32, scale: f64) -> Settings {
    Settings { steps, scale: DVec3::splat(scale), ..Settings::default() }
}

/// `Edge3`, `Edge3_i`, `Edge3_i+1`, `Edge3_i-1` → (type, age rule, timed).
fn edge(tok: &str) -> (u32, Age, bool) {
    let rest = tok.strip_prefix("Edge").unwrap_or_else(|| panic!("not an edge: {tok}"));
    let (num, age) = match rest.find('_') {
        Some(i) => (
            &rest[..i],
            match &rest[i..] {
                "_i" => Age::Same,
                "_i+1" => Age::Plus1,
                "_i-1" => Age::Minus1,
                other => panic!("bad age {other}"),
            },
        ),
        None => (rest, Age::Zero),
    };
    (num.parse().unwrap_or_else(|_| panic!("bad edge {tok}")), age, age != Age::Zero)
}

fn turn(tok: &str) -> Option<Turn> {
    Some(match tok {
        "+" => Turn::Right,
        "-" => Turn::Left,
        "&" => Turn::PitchDown,
        "^" => Turn::PitchUp,
        "\\" => Turn::RollLeft,
        "/" => Turn::RollRight,
        _ => return None,
    })
}

/// A successor's items: `Edge0 [ [ + Edge1 ] - Edge1 ] ~ Edge0`.
pub fn items(text: &str) -> Vec<Item> {
    let mut out = Vec::new();
    // One turn list per open bracket, each starting from its parent's turns.
    let mut stack: Vec<Vec<Turn>> = Vec::new();
    let mut reversed = false;
    for tok in text.split_whitespace() {
        match tok {
            "[" => {
                let start = stack.last().cloned().unwrap_or_default();
                stack.push(start);
            }
            "]" => {
                stack.pop().expect("unbalanced ]");
            }
            "~" => reversed = true,
            t if turn(t).is_some() => {
                let t = turn(t).unwrap();
                match stack.last_mut() {
                    Some(top) => top.push(t),
                    None => out.push(Item::Turn(t)),
                }
            }
            t => {
                let (kind, age, _) = edge(t);
                let sym = EdgeSym { kind, reversed, age };
                reversed = false;
                match stack.last() {
                    Some(top) => out.push(Item::Branch(Branch { turns: top.clone(), edge: sym })),
                    None => out.push(Item::Edge(sym)),
                }
            }
        }
    }
    assert!(stack.is_empty(), "unbalanced [");
    out
}

/// A rule: `L < Edge0 > R -> succ [Weight w] [If i < c] -> succ [Weight w] …`.
pub fn rule(text: &str) -> Rule {
    let mut parts = text.split("->");
    let pred: Vec<&str> = parts.next().unwrap().split_whitespace().collect();
    let (left, strict, right) = match pred.as_slice() {
        [e] => (None, *e, None),
        [l, "<", e] => (Some(*l), *e, None),
        [e, ">", r] => (None, *e, Some(*r)),
        [l, "<", e, ">", r] => (Some(*l), *e, Some(*r)),
        other => panic!("bad predecessor {other:?}"),
    };
    let (kind, _, timed) = edge(strict);
    let pred = Predecessor { kind, timed, left: left.map(|t| edge(t).0), right: right.map(|t| edge(t).0) };
    let mut condition = None;
    let mut successors = Vec::new();
    for part in parts {
        let mut body = part.trim().to_string();
        if let Some(i) = body.find("If i ") {
            let c: Vec<&str> = body[i + 5..].split_whitespace().collect();
            let cmp = match c[0] {
                "<" => Cmp::Less,
                "=" => Cmp::Equal,
                ">" => Cmp::Greater,
                other => panic!("bad comparison {other}"),
            };
            condition = Some(Condition { cmp, value: c[1].parse().unwrap() });
            body.truncate(i);
        }
        let mut weight = 1.0;
        if let Some(i) = body.find("Weight") {
            weight = body[i + 6..].trim().parse().unwrap();
            body.truncate(i);
        }
        successors.push(Successor { items: items(&body), weight });
    }
    Rule { pred, condition, successors, span: Span::default() }
}

/// A grammar from its axiom, rules, Angle and Sync.
pub fn hemls(axiom: &str, rules: &[&str], angle: f64, sync: bool) -> Hemls {
    let mut sides = Vec::new();
    let mut reversed = false;
    for tok in axiom.split_whitespace() {
        match tok {
            "+" => {}
            "~" => reversed = true,
            t => {
                sides.push(AxiomSide { kind: edge(t).0, reversed });
                reversed = false;
            }
        }
    }
    Hemls {
        name: "test".into(),
        axiom: sides,
        rules: rules.iter().map(|r| rule(r)).collect(),
        angle,
        sync,
        branch_angle: None,
    }
}

/// Koch snowflake.
pub fn koch() -> Hemls {
    hemls("Edge0 + Edge0 + Edge0", &["Edge0 -> Edge0 - Edge0 + + Edge0 - Edge0"], 60.0, false)
}

/// Quadratic Koch island.
pub fn quadratic_koch() -> Hemls {
    hemls(
        "Edge0 + Edge0 + Edge0 + Edge0",
        &["Edge0 -> Edge0 + Edge0 - Edge0 - Edge0 Edge0 + Edge0 + Edge0 - Edge0"],
        90.0,
        false,
    )
}

/// Four-sided tiles (async), written as in the predefined file.
pub fn four_sided_tiles() -> Hemls {
    hemls(
        "Edge0 + ~ Edge1 + Edge0 + ~ Edge1",
        &["Edge0 -> Edge0 [ [ + Edge1 ] - Edge1 ] Edge0", "Edge1 -> Edge1 [ [ + Edge0 ] - Edge0 ] Edge1"],
        90.0,
        false,
    )
}

/// Three-sided tiles (Sync), written as in the predefined file.
pub fn three_sided_tiles() -> Hemls {
    hemls(
        "Edge0 + Edge1 + Edge2",
        &[
            "Edge0 -> Edge0 [ [ [ [ + Edge2 ] + + Edge1 ] - Edge1 ] - - Edge2 ] Edge0",
            "Edge1 -> Edge1 [ [ [ [ + Edge0 ] + + Edge2 ] - Edge2 ] - - Edge0 ] Edge1",
            "Edge2 -> Edge2 [ [ [ [ + Edge1 ] + + Edge0 ] - Edge0 ] - - Edge1 ] Edge2",
        ],
        60.0,
        true,
    )
}
