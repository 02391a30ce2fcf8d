//! Genr8's GE extensions against the paper: the §5.2 worked example over
//! the Figure 6 grammar (`examples/ge/genr8.bnf`), the distribution of
//! `{ }` repetition counts, and the three shipped EA grammars mapping
//! random genomes to well-formed `.gr8` rewrite systems that genform's
//! `.gr8` reader accepts.

use genform_core::{Rng, SourceFile};
use genform_ge::{Bnf, Genr8Options, MapOptions, Mapper, StepKind};
use std::collections::BTreeSet;

fn load(name: &str) -> Bnf {
    let path = format!("{}/../../examples/ge/{name}.bnf", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    match genform_ge::compile(&SourceFile::new(format!("{name}.bnf"), text)) {
        Ok((bnf, warnings)) => {
            assert!(warnings.items.is_empty(), "{}", warnings.short());
            bnf
        }
        Err(e) => panic!("{}", e.short()),
    }
}

#[test]
fn worked_example_of_section_5_2_maps_the_axiom_with_eight_genes() {
    let bnf = load("genr8");
    // The paper's prefix; the rest of the genome is arbitrary.
    let mut genome = vec![212, 187, 632, 832, 800, 517, 338, 39, 878, 185, 954, 863];
    let mut rng = Rng::from_seed(52);
    genome.extend((0..300).map(|_| rng.below(1000) as u32));
    let mut mapper = Mapper::new(&bnf, MapOptions::genr8()).unwrap();
    let t = mapper.trace(&genome);
    let table: Vec<(&str, u32, u32, u32, StepKind)> =
        t.steps[..9].iter().map(|s| (s.nt.as_str(), s.codon, s.n, s.choice, s.kind)).collect();
    assert_eq!(
        table,
        [
            ("<L-System>", 212, 1, 0, StepKind::Expand),
            ("<Axiom>", 187, 1, 0, StepKind::Expand),
            ("Edge", 632, 3, 2, StepKind::Edge), // 632 mod 3 = 2, new type: max_ID → 3
            ("Edge", 832, 4, 0, StepKind::Edge), // 832 mod 4 = 0
            ("Edge", 800, 4, 0, StepKind::Edge), // 800 mod 4 = 0
            ("<Axiom>", 517, 2, 1, StepKind::Repeat), // 517 mod 2 = 1 > 0: repeat
            ("Edge", 338, 4, 2, StepKind::Edge), // 338 mod 4 = 2
            ("<Axiom>", 39, 3, 0, StepKind::Repeat), // 39 mod 3 = 0 ≤ 1: stop
            ("<RewriteRule>", 878, 1, 0, StepKind::Expand), // the ninth gene
        ]
    );
    assert_eq!(t.steps[8].pos, 8, "eight genes consumed before <RewriteRule>");
    let phenotype = t.phenotype.expect("valid");
    assert_eq!(phenotype.lines().next(), Some("Edge2 + Edge0 + Edge0 + Edge2"));
    genform_hemls::parse_str("example.gr8", &phenotype).unwrap_or_else(|e| panic!("{phenotype}\n{}", e.short()));
}

#[test]
fn repetition_counts_follow_k_plus_1_over_k_plus_2_factorial() {
    let bnf = genform_ge::parse_str("repeat.bnf", "<s> ::= { \"a\" }").unwrap();
    let options = MapOptions { genr8: Some(Genr8Options::default()), ..MapOptions::default() };
    let mut mapper = Mapper::new(&bnf, options).unwrap();
    let mut rng = Rng::from_seed(2024);
    // 720720 is divisible by 2..=16, so `g mod (c + 2)` is exactly uniform.
    const N: usize = 20_000;
    let mut counts = [0usize; 5];
    let mut sum = 0usize;
    for _ in 0..N {
        let mut genome = [0u32; 17];
        for g in &mut genome[1..] {
            *g = rng.below(720_720) as u32;
        }
        mapper.map(&genome);
        let k = mapper.phenotype().expect("16 decisions suffice").len();
        counts[k.min(4)] += 1;
        sum += k;
    }
    // P(k) = (k+1)/(k+2)!: 1/2, 1/3, 1/8, 1/30, and 1/120 for k ≥ 4.
    let p = [1.0 / 2.0, 1.0 / 3.0, 1.0 / 8.0, 1.0 / 30.0, 1.0 / 120.0];
    let chi2: f64 = counts
        .iter()
        .zip(p)
        .map(|(&o, p)| {
            let e = p * N as f64;
            (o as f64 - e).powi(2) / e
        })
        .sum();
    // 4 degrees of freedom: 18.47 is the 0.999 quantile.
    assert!(chi2 < 18.47, "chi-square {chi2:.2} for counts {counts:?}");
    let mean = sum as f64 / N as f64;
    // Standard deviation of k is √(4 − e − (e − 2)²) ≈ 0.875; 4σ/√N ≈ 0.025.
    assert!((mean - (std::f64::consts::E - 2.0)).abs() < 0.025, "mean {mean}");
}

/// The items of one successor, split from its `Weight w` (if any).
fn successor_body(succ: &str) -> Vec<&str> {
    let toks: Vec<&str> = succ.split(' ').collect();
    match toks.iter().position(|&t| t == "Weight") {
        Some(w) => {
            assert_eq!(w + 2, toks.len(), "`Weight w` ends a successor: {succ}");
            assert!(toks[w + 1].parse::<u32>().is_ok_and(|v| (1..=4).contains(&v)), "{succ}");
            toks[..w].to_vec()
        }
        None => toks,
    }
}

fn is_edge(t: &str) -> bool {
    t.strip_prefix("Edge").is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

fn edge_id(t: &str) -> u32 {
    t[4..].parse().expect("edge id")
}

/// Checks a successor's items: brackets balance, every branch ends with an
/// edge, `~` stands right before an edge, it ends with an edge, and the
/// turns outside brackets balance per axis.
fn check_successor(items: &[&str], line: &str) {
    assert!(items.last().is_some_and(|t| is_edge(t)), "a successor ends with an edge: {line}");
    let mut depth = 0i32;
    let mut turns = [0i32; 3];
    for (i, &t) in items.iter().enumerate() {
        match t {
            "[" => depth += 1,
            "]" => {
                assert!(i > 0 && is_edge(items[i - 1]), "a branch ends with an edge: {line}");
                depth -= 1;
                assert!(depth >= 0, "unbalanced brackets: {line}");
            }
            "~" => assert!(items.get(i + 1).is_some_and(|n| is_edge(n)), "`~` before an edge: {line}"),
            _ if is_edge(t) => {}
            turn => {
                let (axis, sign) = match turn {
                    "+" => (0, 1),
                    "-" => (0, -1),
                    "&" => (1, 1),
                    "^" => (1, -1),
                    "\\" => (2, 1),
                    "/" => (2, -1),
                    other => panic!("unexpected token `{other}` in {line}"),
                };
                if depth == 0 {
                    turns[axis] += sign;
                }
            }
        }
    }
    assert_eq!(depth, 0, "unbalanced brackets: {line}");
    assert_eq!(turns, [0, 0, 0], "main-line turns must balance: {line}");
}

/// The §6.6 structure: an axiom of ≥ 3 edges joined by `+`, one or more
/// rules, `Angle`, optional `Sync`, `BranchAngle`; every edge type has a
/// rule after repair. Returns the rules' successor bodies.
fn check_structure(text: &str, angles: &[&str]) -> Vec<Vec<String>> {
    let lines: Vec<&str> = text.lines().collect();
    assert!(text.ends_with('\n') && lines.len() >= 4, "{text}");
    let axiom: Vec<&str> = lines[0].split(' ').collect();
    assert!(axiom.len() >= 5 && axiom.len() % 2 == 1, "axiom: {text}");
    for (i, t) in axiom.iter().enumerate() {
        assert!(if i % 2 == 0 { is_edge(t) } else { *t == "+" }, "axiom: {}", lines[0]);
    }
    let mut types: BTreeSet<u32> = axiom.iter().filter(|t| is_edge(t)).map(|t| edge_id(t)).collect();
    let mut with_rule = BTreeSet::new();
    let mut rest = lines[1..].iter().peekable();
    let mut successors = Vec::new();
    while let Some(line) = rest.next_if(|l| l.contains(" -> ")) {
        let mut parts = line.split(" -> ");
        let pred: Vec<&str> = parts.next().unwrap().split(' ').collect();
        let strict = match pred[..] {
            [e] => e,
            [_, "<", e] | [e, ">", _] | [_, "<", e, ">", _] => e,
            _ => panic!("predecessor: {line}"),
        };
        assert!(pred.iter().enumerate().all(|(i, t)| if i % 2 == 0 { is_edge(t) } else { true }), "{line}");
        with_rule.insert(edge_id(strict));
        types.extend(pred.iter().filter(|t| is_edge(t)).map(|t| edge_id(t)));
        for succ in parts {
            let items = successor_body(succ);
            check_successor(&items, line);
            types.extend(items.iter().filter(|t| is_edge(t)).map(|t| edge_id(t)));
            successors.push(items.iter().map(|s| s.to_string()).collect());
        }
    }
    assert!(!successors.is_empty(), "at least one rule: {text}");
    let angle = rest.next().and_then(|l| l.strip_prefix("Angle ")).unwrap_or_else(|| panic!("Angle: {text}"));
    assert!(angles.contains(&angle), "{text}");
    rest.next_if(|l| **l == "Sync");
    let branch = rest.next().and_then(|l| l.strip_prefix("BranchAngle ")).unwrap_or_else(|| panic!("{text}"));
    assert!(["15", "30", "45", "60", "75"].contains(&branch), "{text}");
    assert_eq!(rest.next(), None, "{text}");
    assert_eq!(types, types.intersection(&with_rule).copied().collect(), "repair left types without rules: {text}");
    successors
}

/// Maps 1,000 random genomes (codons 0..999, lengths 50–200) and checks
/// every valid phenotype; returns how many were valid.
fn thousand(name: &str, angles: &[&str], mut extra: impl FnMut(&str, &[Vec<String>])) -> usize {
    let bnf = load(name);
    let mut mapper = Mapper::new(&bnf, MapOptions::genr8()).unwrap();
    let mut rng = Rng::stream(6, &[name.len() as u64]);
    let mut valid = 0;
    for _ in 0..1000 {
        let len = 50 + rng.below(151) as usize;
        let genome: Vec<u32> = (0..len).map(|_| rng.below(1000) as u32).collect();
        if !mapper.map(&genome).valid() {
            continue;
        }
        valid += 1;
        let text = mapper.phenotype().expect("valid");
        let successors = check_structure(text, angles);
        extra(text, &successors);
        if let Err(e) = genform_hemls::parse_str(&format!("{name}.gr8"), text) {
            panic!("{text}\nis not read by genform-hemls:\n{}", e.short());
        }
    }
    valid
}

#[test]
fn figure_6_grammar_maps_random_genomes_to_well_formed_gr8() {
    let valid = thousand("genr8", &["30", "45"], |text, _| assert!(!text.contains("Weight"), "{text}"));
    assert!(valid >= 950, "{valid} of 1000 valid");
}

#[test]
fn stochastic_grammar_maps_random_genomes_to_weighted_rules() {
    let mut weighted = 0;
    let valid = thousand("genr8_stochastic", &["30", "45"], |text, _| {
        for line in text.lines().filter(|l| l.contains(" -> ")) {
            let arrows = line.matches(" -> ").count();
            let weights = line.matches(" Weight ").count();
            // Deterministic, or every successor weighted (two or more).
            assert!(weights == 0 && arrows == 1 || weights == arrows && arrows >= 2, "{line}");
        }
        weighted += usize::from(text.contains(" Weight "));
    });
    assert!(valid >= 850, "{valid} of 1000 valid");
    assert!(weighted > valid / 4, "only {weighted} of {valid} have weighted rules");
}

#[test]
fn symmetric_grammar_maps_random_genomes_to_mirror_symmetric_rules() {
    let valid = thousand("genr8_symmetric", &["45"], |text, successors| {
        // The seed reads the same around a mirror axis.
        let sides: Vec<&str> = text.lines().next().unwrap().split(" + ").collect();
        let ok = match sides[..] {
            [a, _, c] => a == c,
            [a, b, c, d] => a == c && b == d || a == b && c == d,
            [a, b, c, d, e, f] => a == c && c == e && b == d && d == f,
            _ => false,
        };
        assert!(ok, "seed: {text}");
        // Every successor is a palindrome once each branch pair is one token.
        for items in successors {
            let mut folded: Vec<String> = Vec::new();
            let mut depth = 0;
            for t in items {
                if depth > 0 {
                    folded.last_mut().unwrap().push_str(t);
                } else {
                    folded.push(t.clone());
                }
                depth += i32::from(t == "[") - i32::from(t == "]");
            }
            let mut reversed = folded.clone();
            reversed.reverse();
            assert_eq!(folded, reversed, "not mirror-symmetric: {}", items.join(" "));
        }
    });
    assert!(valid >= 950, "{valid} of 1000 valid");
}
