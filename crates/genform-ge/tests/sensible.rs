//! Sensible (ramped half-and-half) initialisation: a generated genome maps
//! back to the tree it was written from, within the depth limit, on plain
//! BNF and on Genr8's grammar with all its extensions.

use genform_core::{Rng, SourceFile};
use genform_ge::{Bnf, Growth, MapOptions, Mapper, Sensible, StepKind};
use proptest::prelude::*;

fn load(name: &str) -> Bnf {
    let path = format!("{}/../../examples/ge/{name}.bnf", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    genform_ge::compile(&SourceFile::new(format!("{name}.bnf"), text)).unwrap_or_else(|e| panic!("{}", e.short())).0
}

const ARITH: &str = "<expr> ::= <expr> <op> <expr> | \"(\" <expr> <op> <expr> \")\" | <pre> \"(\" <expr> \")\" | <var>
<op> ::= \"+\" | \"-\"
<pre> ::= \"sin\" | \"cos\"
<var> ::= \"x\" | \"1.0\"";

/// Deepest non-terminal expansion of a mapping (root = 1).
fn deepest(mapper: &mut Mapper, codons: &[u32]) -> u32 {
    let t = mapper.trace(codons);
    t.steps.iter().filter(|s| matches!(s.kind, StepKind::Expand | StepKind::Limited)).map(|s| s.depth).max().unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Full trees on a recursive grammar reach their limit exactly and
    /// grown ones stay under it; either maps back, reading every codon
    /// once, to the phenotype the generator left in the mapper.
    #[test]
    fn generated_codons_map_back_to_their_tree(seed: u64, depth in 1u32..9, full: bool, range in 8u32..2000) {
        let bnf = genform_ge::parse_str("arith.bnf", ARITH).unwrap();
        let mut mapper = Mapper::new(&bnf, MapOptions::standard(0, None)).unwrap();
        prop_assert_eq!(mapper.min_tree_depth(), 2);
        let growth = if full { Growth::Full } else { Growth::Grow };
        let spec = Sensible { growth, max_depth: depth, codon_range: range, max_codons: 100_000 };
        let codons = mapper.generate(&spec, &mut Rng::from_seed(seed)).unwrap();
        let phenotype = mapper.phenotype().unwrap().to_string();
        prop_assert!(codons.iter().all(|&c| c < range));
        let out = mapper.map(&codons);
        prop_assert!(out.valid());
        prop_assert_eq!((out.used_codons, out.wraps), (codons.len(), 0));
        prop_assert_eq!(mapper.phenotype().unwrap(), phenotype.as_str());
        let d = deepest(&mut mapper, &codons);
        let limit = depth.max(2);
        if full { prop_assert_eq!(d, limit) } else { prop_assert!(d <= limit) }
    }

    /// Genr8's grammars: every generated genome is valid without wrapping
    /// (repetitions, edge IDs, bindings and repair unmapped as they map),
    /// and the ramped genome adds a tail of half its read codons.
    #[test]
    fn genr8_genomes_are_valid_and_ramped_ones_carry_a_tail(seed: u64, index in 0usize..40, which in 0usize..3) {
        let name = ["genr8", "genr8_stochastic", "genr8_symmetric"][which];
        let bnf = load(name);
        let mut mapper = Mapper::new(&bnf, MapOptions::genr8()).unwrap();
        let mut rng = Rng::from_seed(seed);
        let codons = mapper.ramped(index, 10, 1000, 1000, &mut rng).unwrap();
        let out = mapper.map(&codons);
        prop_assert!(out.valid(), "{:?}", out.fail);
        prop_assert_eq!(out.wraps, 0);
        let read = out.used_codons;
        prop_assert_eq!(codons.len(), read + (read / 2).max(1).min(1000 - read));
        prop_assert!(deepest(&mut mapper, &codons) <= 10);
    }
}

#[test]
fn ramped_genomes_spread_over_depths_and_both_growths() {
    let bnf = load("genr8");
    let mut mapper = Mapper::new(&bnf, MapOptions::genr8()).unwrap();
    // <L-System> → <RewriteRule> → <Successor> is the shallowest tree.
    assert_eq!(mapper.min_tree_depth(), 3);
    let mut rng = Rng::from_seed(1);
    let mut phenotypes = std::collections::HashSet::new();
    let mut depths = std::collections::BTreeSet::new();
    for i in 0..100 {
        let codons = mapper.ramped(i, 8, 1000, 1000, &mut rng).unwrap();
        mapper.map(&codons);
        phenotypes.insert(mapper.phenotype().unwrap().to_string());
        depths.insert(deepest(&mut mapper, &codons));
    }
    // Depth limits 3..=8, each reached by its full trees.
    assert_eq!(depths, (3..=8).collect());
    assert!(phenotypes.len() >= 95, "{} distinct of 100", phenotypes.len());
}
