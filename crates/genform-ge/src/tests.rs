//! Unit tests of the front end and the mapper on small grammars, with
//! expected results worked out by hand.

use crate::*;

fn bnf(text: &str) -> Bnf {
    parse_str("test.bnf", text).unwrap_or_else(|e| panic!("{}", e.short()))
}

fn genr8_options(spaced: bool) -> MapOptions {
    MapOptions { spaced, genr8: Some(Genr8Options::default()), ..MapOptions::default() }
}

fn phenotype(b: &Bnf, options: MapOptions, genome: &[u32]) -> Option<String> {
    map(b, genome, &options).expect("options").phenotype
}

#[test]
fn extensions_of_the_format_are_read() {
    let b = bnf(concat!(
        "// a comment line\n",
        "<s> ::= \"a\\n\" [? \"~\" ] { <t> [ \"\\\\\" ] }   # trailing comment\n",
        "  | \"tab\\t\" \"q\\\"\"\n",
        "<t> ::= \"x\" // another\n",
    ));
    assert_eq!(b.rules.len(), 2);
    let s = &b.rules[0];
    assert_eq!(s.alternatives.len(), 2, "the `|` line continues <s>");
    let texts: Vec<&str> = b.terminals.iter().map(String::as_str).collect();
    assert_eq!(texts, ["a\n", "~", "\\", "tab\t", "q\"", "x"]);
    match &s.alternatives[0].items[..] {
        [Item::Terminal(_), Item::Optional { evolved: false, .. }, Item::Repeat(g)] => {
            assert!(matches!(&g[..], [Item::NonTerminal(RuleId(1)), Item::Optional { evolved: true, .. }]));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn display_writes_text_that_compiles_to_the_same_grammar() {
    let text = include_str!("../../../examples/ge/genr8.bnf");
    let b = bnf(text);
    let written = b.to_string();
    let again = bnf(&written);
    assert_eq!(again.to_string(), written);
    assert_eq!(again.rules.len(), b.rules.len());
    assert_eq!(again.terminals, b.terminals);
    assert!(written.contains("[? \"~\" ]") && written.contains("\"\\\\\"") && written.contains("\"\\n\""));
}

#[test]
fn every_nonterminal_reads_a_codon_and_wraps_count_only_when_needed() {
    let b = bnf("<s> ::= \"a\" <t>\n<t> ::= \"b\"");
    let exact = map(&b, &[0, 0], &MapOptions::standard(0, None)).unwrap();
    assert_eq!((exact.phenotype.as_deref(), exact.used_codons, exact.wraps), (Some("ab"), 2, 0));
    let wrapped = map(&b, &[7], &MapOptions::standard(1, None)).unwrap();
    assert_eq!((wrapped.phenotype.as_deref(), wrapped.used_codons, wrapped.wraps), (Some("ab"), 2, 1));
    assert_eq!(wrapped.steps[1].pos, 0);
    let short = map(&b, &[7], &MapOptions::standard(0, None)).unwrap();
    assert_eq!((short.valid, short.fail, short.used_codons), (false, Some(Failure::WrapLimit), 1));
    assert_eq!(short.phenotype, None);
    let empty = map(&b, &[], &MapOptions::standard(3, None)).unwrap();
    assert_eq!(empty.fail, Some(Failure::EmptyGenome));
}

#[test]
fn per_choice_layout_reads_one_interleaved_stream_per_kind_of_decision() {
    // Kinds: <s> 0, <a> 1, <b> 2, edge IDs 3; so K = 4 and the i-th
    // decision of kind k reads codon i·4 + k.
    let b = bnf("<s> ::= <a> <b> <a>\n<a> ::= \"x\" | \"y\"\n<b> ::= \"p\" | \"q\"");
    let per_choice = |wraps| MapOptions { layout: CodonLayout::PerChoice, ..MapOptions::standard(wraps, None) };
    let genome = [0, 1, 1, 9, 9, 0];
    let mut m = Mapper::new(&b, per_choice(0)).unwrap();
    let out = m.map(&genome);
    assert_eq!((m.phenotype(), out.used_codons, out.extent, out.wraps), (Some("yqx"), 4, 6, 0));
    // Standard GE reads the same codons left to right.
    let mut seq = Mapper::new(&b, MapOptions::standard(0, None)).unwrap();
    let out = seq.map(&genome);
    assert_eq!((seq.phenotype(), out.extent), (Some("yqy"), 4));
    // A new choice for <b> leaves both choices of <a> as they were...
    assert_eq!(m.map(&[0, 1, 0, 9, 9, 0]).fail, None);
    assert_eq!(m.phenotype(), Some("ypx"));
    // ...where in standard GE a new choice for the first <a> would shift
    // every later read; here the second <a> still reads codon 5.
    m.map(&[0, 0, 1, 9, 9, 1]);
    assert_eq!(m.phenotype(), Some("xqy"));
    // The second <a> lies past a 4-codon genome: invalid without wrapping,
    // codon 5 mod 4 = 1 with one wrap.
    assert_eq!(m.map(&[0, 1, 1, 9]).fail, Some(Failure::WrapLimit));
    let mut wrapping = Mapper::new(&b, per_choice(1)).unwrap();
    let out = wrapping.map(&[0, 1, 1, 9]);
    assert_eq!((wrapping.phenotype(), out.wraps, out.extent), (Some("yqy"), 1, 4));
    assert_eq!(wrapping.map(&[]).fail, Some(Failure::EmptyGenome));
    // Traces name the positions read.
    let trace = Mapper::new(&b, per_choice(0)).unwrap().trace(&genome);
    assert_eq!(trace.steps.iter().map(|s| s.pos).collect::<Vec<_>>(), [0, 1, 2, 5]);
}

#[test]
fn depth_limit_counts_the_root_as_one_and_terminal_leaves() {
    let b = bnf("<s> ::= \"(\" <s> \")\" | \"x\"");
    let ok = map(&b, &[0, 1], &MapOptions::standard(0, Some(3))).unwrap();
    assert_eq!(ok.phenotype.as_deref(), Some("(x)"), "x is at depth 3");
    let deep = map(&b, &[0, 0, 1], &MapOptions::standard(0, Some(3))).unwrap();
    assert_eq!((deep.fail, deep.used_codons), (Some(Failure::DepthLimit), 2), "<s> at depth 3 fails");
    let leaf = map(&b, &[0, 1], &MapOptions::standard(0, Some(2))).unwrap();
    assert_eq!(leaf.fail, Some(Failure::DepthLimit), "a terminal at depth 3 > 2 fails too");
}

#[test]
fn repetition_decisions_follow_the_counter_rule() {
    let b = bnf("<s> ::= { \"a\" }");
    // 517 mod 2 = 1 > 0: repeat; 39 mod 3 = 0 ≤ 1: stop (the paper's numbers).
    assert_eq!(phenotype(&b, genr8_options(false), &[0, 517, 39]).as_deref(), Some("a"));
    // 1 mod 2 = 1, 2 mod 3 = 2, 3 mod 4 = 3: repeat thrice; 0 mod 5 = 0: stop.
    let t = map(&b, &[0, 1, 2, 3, 0], &genr8_options(false)).unwrap();
    assert_eq!(t.phenotype.as_deref(), Some("aaa"));
    assert_eq!(t.choices, [0, 1, 2, 3, 0]);
    assert_eq!(t.steps.iter().map(|s| s.n).collect::<Vec<_>>(), [1, 2, 3, 4, 5]);
    assert!(t.steps[1..].iter().all(|s| s.kind == StepKind::Repeat && s.nt == "<s>"));
    // The constant is adjustable: with 3, counter 0 stops on g mod 3 = 0 only.
    let mut three = genr8_options(false);
    three.genr8.as_mut().unwrap().repeat_constant = 3;
    assert_eq!(phenotype(&b, three.clone(), &[0, 2, 0]).as_deref(), Some("a"));
    assert_eq!(phenotype(&b, three, &[0, 3]).as_deref(), Some(""));
    // Groups use the same rule in standard mode.
    assert_eq!(phenotype(&b, MapOptions::default(), &[0, 517, 39]).as_deref(), Some("a"));
}

#[test]
fn options_read_one_gene_unless_not_evolved() {
    let b = bnf("<s> ::= \"a\" [ \"b\" ] [? \"c\" ] \"d\"");
    let t = map(&b, &[0, 1], &genr8_options(false)).unwrap();
    assert_eq!((t.phenotype.as_deref(), t.used_codons), (Some("abd"), 2));
    assert_eq!(t.steps[1].kind, StepKind::Option);
    assert_eq!(phenotype(&b, genr8_options(false), &[0, 2]).as_deref(), Some("ad"));
}

#[test]
fn edge_ids_grow_max_id_and_reset_per_genome() {
    let b = bnf("<s> ::= \"Edge\" \"Edge\" \"Edge\"");
    let mut m = Mapper::new(&b, genr8_options(true)).unwrap();
    m.map(&[0, 632, 832, 800]);
    assert_eq!(m.phenotype(), Some("Edge2 Edge0 Edge0"));
    // 2 mod 3 = 2 (new), 3 mod 4 = 3 (new), 4 mod 5 = 4.
    m.map(&[0, 2, 3, 4]);
    assert_eq!(m.phenotype(), Some("Edge2 Edge3 Edge4"));
    let t = m.trace(&[0, 2, 3, 4]);
    assert_eq!(t.steps.iter().map(|s| (s.n, s.choice)).collect::<Vec<_>>(), [(1, 0), (3, 2), (4, 3), (5, 4)]);
    // Without edge IDs "Edge" is a plain terminal.
    assert_eq!(phenotype(&b, MapOptions::default(), &[0]).as_deref(), Some("EdgeEdgeEdge"));
}

#[test]
fn bound_edges_share_an_id_per_production_instance() {
    let b = bnf("<s> ::= \"EdgeX\" \"EdgeY\" \"EdgeX\" <t> \"EdgeY\" \"EdgeZ\"\n<t> ::= \"EdgeX\"");
    // X reads 1 → 1; Y reads 0 → 0; X reuses 1; <t>'s own X reads 2 → 2 (new);
    // Y reuses 0; Z reads 5 mod 4 = 1.
    let t = map(&b, &[0, 1, 0, 0, 2, 5], &genr8_options(true)).unwrap();
    assert_eq!(t.phenotype.as_deref(), Some("Edge1 Edge0 Edge1 Edge2 Edge0 Edge1"));
    assert_eq!(t.used_codons, 6);
    // Inside a group of the same alternative the binding holds.
    let g = bnf("<s> ::= \"EdgeX\" { \"EdgeX\" }");
    assert_eq!(phenotype(&g, genr8_options(true), &[0, 1, 1, 0]).as_deref(), Some("Edge1 Edge1"));
}

#[test]
fn depth_limited_choice_uses_only_terminal_alternatives() {
    let b = bnf("<m> ::= \"+\" <m> \"-\" | \"a\" | <m> <m> | \"b\"");
    let mut o = genr8_options(true);
    o.genr8.as_mut().unwrap().max_depth = Some(2);
    // Depth 1: 0 → `+ <m> -`; depth 2 ≥ 2: among [a, b], 3 mod 2 = 1 → b.
    let t = map(&b, &[0, 3], &o).unwrap();
    assert_eq!(t.phenotype.as_deref(), Some("+ b -"));
    assert_eq!((t.steps[1].kind, t.steps[1].n, t.steps[1].choice), (StepKind::Limited, 2, 3));
    // A rule with no terminal-only alternative stays unrestricted.
    let u = bnf("<s> ::= <t> | <t> <t>\n<t> ::= \"x\"");
    let mut o1 = genr8_options(false);
    o1.genr8.as_mut().unwrap().max_depth = Some(1);
    assert_eq!(phenotype(&u, o1, &[1, 0, 0]).as_deref(), Some("xx"));
}

#[test]
fn spaced_output_starts_lines_without_spaces() {
    let b = bnf("<s> ::= \"a\" \"b\" \"\\n\" \"c\" \"\" \"d\" \"\\n\"");
    let o = MapOptions { spaced: true, ..MapOptions::default() };
    assert_eq!(phenotype(&b, o, &[0]).as_deref(), Some("a b\nc d\n"));
}

#[test]
fn repair_adds_a_rule_for_every_edge_type_without_one() {
    let b = bnf(concat!(
        "<S> ::= <Axiom> \"\\n\" <RewriteRule> \"\\n\" \"Angle\" \"\\n\"\n",
        "<Axiom> ::= \"Edge\" \"+\" \"Edge\"\n",
        "<RewriteRule> ::= <Predecessor> \"->\" \"Edge\"\n",
        "<Predecessor> ::= \"Edge\" | \"Edge\" \"<\" \"Edge\"\n",
    ));
    let options = MapOptions { max_wraps: 0, ..MapOptions::genr8() };
    // Axiom Edge0 + Edge1; rule Edge0 -> Edge2 (5 mod 3, new). Repair Edge1
    // (rule gene 0, successor 1 mod 4) and then Edge2 (rule 0, 2 mod 4).
    let genome = [0, 0, 0, 1, 0, 0, 0, 5, 0, 1, 0, 2];
    let t = map(&b, &genome, &options).unwrap();
    assert_eq!(
        t.phenotype.as_deref(),
        Some("Edge0 + Edge1\nEdge0 -> Edge2\nEdge1 -> Edge1\nEdge2 -> Edge2\nAngle\n"),
        "{t:?}"
    );
    assert_eq!(t.used_codons, genome.len());
    // The strict edge of `A < B` is B: Edge1 has a rule; Edge0 and Edge2
    // get one each, and Edge3, which Edge2's new rule introduces, too.
    let genome = [0, 0, 0, 1, 0, 1, 0, 1, 5, 0, 0, 0, 3, 0, 3];
    let t = map(&b, &genome, &options).unwrap();
    assert_eq!(
        t.phenotype.as_deref(),
        Some("Edge0 + Edge1\nEdge0 < Edge1 -> Edge2\nEdge0 -> Edge0\nEdge2 -> Edge3\nEdge3 -> Edge3\nAngle\n"),
        "{t:?}"
    );
    // Repair that runs out of genes makes the individual invalid.
    let t = map(&b, &genome[..9], &options).unwrap();
    assert_eq!(t.fail, Some(Failure::WrapLimit));
}

#[test]
fn inconsistent_options_are_refused() {
    let b = bnf("<s> ::= \"Edge\"");
    let err = Mapper::new(&b, MapOptions::genr8()).unwrap_err();
    assert_eq!(err, MapError::UnknownRule("<RewriteRule>".into()));
    let mut o = genr8_options(false);
    o.genr8.as_mut().unwrap().repeat_constant = 0;
    assert_eq!(Mapper::new(&b, o).unwrap_err(), MapError::ZeroRepeatConstant);
}

#[test]
fn trace_json_uses_the_golden_field_names() {
    let b = bnf("<s> ::= { \"Edge\" }");
    let t = map(&b, &[4, 1, 7, 0], &genr8_options(true)).unwrap();
    let json = serde_json::to_string(&t).unwrap();
    assert!(
        json.starts_with("{\"valid\":true,\"fail\":null,\"phenotype\":\"Edge1\",\"used_codons\":4,\"wraps\":0,"),
        "{json}"
    );
    assert!(json.contains("{\"nt\":\"<s>\",\"pos\":0,\"codon\":4,\"n\":1,\"choice\":0,\"depth\":1}"), "{json}");
    assert!(json.contains("\"kind\":\"repeat\"") && json.contains("\"kind\":\"edge\""), "{json}");
    let back: Mapping = serde_json::from_str(&json).unwrap();
    assert_eq!(back, t);
}

#[test]
fn subtrees_cover_each_expansion_and_swapping_one_keeps_the_rest_aligned() {
    // <e> ::= "(" <e> <e> ")" | "x" | "y": genome 0 0 1 2 2 reads
    // e0 → ( e1 e4 ), e1 → ( e2 e3 ), e2 = x, e3 = y, e4 = y.
    let b = bnf("<s> ::= <e>\n<e> ::= \"(\" <e> <e> \")\" | \"x\" | \"y\"");
    let options = MapOptions::standard(0, None);
    let m = map(&b, &[0, 0, 0, 1, 2, 2], &options).unwrap();
    assert_eq!(m.phenotype.as_deref(), Some("((xy)y)"));
    let spans: Vec<(&str, usize, usize)> = m.subtrees().iter().map(|t| (t.nt, t.start, t.end)).collect();
    assert_eq!(spans, [("<e>", 1, 6), ("<e>", 2, 5), ("<e>", 3, 4), ("<e>", 4, 5), ("<e>", 5, 6)]);
    // Replace the subtree (xy) at 2..5 by the single codon of `x`: the last
    // `y` is still read as the outer pair's second child.
    let m2 = map(&b, &[0, 0, 1, 2], &options).unwrap();
    assert_eq!(m2.phenotype.as_deref(), Some("(xy)"));
    // Wrapped or failed mappings give none.
    let wrapped = map(&b, &[0, 0, 1], &MapOptions::standard(3, None)).unwrap();
    assert!(wrapped.wraps > 0 && wrapped.subtrees().is_empty());
}
