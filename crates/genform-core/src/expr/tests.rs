use super::*;
use crate::rng::Rng;

const NAMES: &Names<'static> = &Names(&["x", "y", "size.x", "has(next)", "inside()"]);

fn eval(src: &str) -> f64 {
    let ast = parse(src).unwrap_or_else(|e| panic!("{src}: {e:?}"));
    let p = compile(&ast, NAMES).unwrap_or_else(|e| panic!("{src}: {e:?}"));
    p.eval(&[2.0, 3.0, 0.5, 1.0, 7.0])
}

fn err(src: &str) -> String {
    match parse(src) {
        Err(d) => d.message,
        Ok(ast) => {
            compile(&ast, NAMES).expect_err("an error").into_iter().map(|d| d.message).collect::<Vec<_>>().join("; ")
        }
    }
}

#[test]
fn arithmetic_and_precedence() {
    let cases = [
        ("1 + 2 * 3", 7.0),
        ("(1 + 2) * 3", 9.0),
        ("2 ^ 3 ^ 2", 512.0),
        ("-2 ^ 2", -4.0),
        ("2 ** 3", 8.0),
        ("7 % 4", 3.0),
        ("x * y - size.x", 5.5),
        ("1 / 4 + .5e1", 5.25),
        ("-x + +y", 1.0),
    ];
    for (s, v) in cases {
        assert_eq!(eval(s), v, "{s}");
    }
}

#[test]
fn logic_comparisons_and_conditionals() {
    let cases = [
        ("x < y", 1.0),
        ("x >= y", 0.0),
        ("x == 2 && y != 2", 1.0),
        ("x > 5 || y > 5", 0.0),
        ("not (x > 5) and y", 1.0),
        ("!x", 0.0),
        ("x > 1 ? 10 : 20", 10.0),
        ("x > 9 ? 10 : y > 2 ? 30 : 40", 30.0),
        ("if(x > 9, 1, 2)", 2.0),
        ("has(next) ? 1 : 0", 1.0),
        ("inside() * 2", 14.0),
        ("true + false", 1.0),
    ];
    for (s, v) in cases {
        assert_eq!(eval(s), v, "{s}");
    }
}

#[test]
fn functions_and_constants() {
    assert!((eval("sin(pi / 2)") - 1.0).abs() < 1e-12);
    assert_eq!(eval("min(x, y) + max(x, y)"), 5.0);
    assert_eq!(eval("clamp(5, 0, 1)"), 1.0);
    assert_eq!(eval("mix(0, 10, 0.25)"), 2.5);
    assert_eq!(eval("smootherstep(0, 1, 0.5)"), 0.5);
    assert_eq!(eval("mod(-1, 3)"), 2.0);
    assert_eq!(eval("deg(pi)"), 180.0);
    assert_eq!(eval("exp(0)"), 1.0);
}

#[test]
fn constants_fold() {
    let p = compile(&parse("2 * pi / 4 + sqrt(16)").unwrap(), NAMES).unwrap();
    assert_eq!(p.constant(), Some(std::f64::consts::FRAC_PI_2 + 4.0));
    let p = compile(&parse("x + 1").unwrap(), NAMES).unwrap();
    assert_eq!(p.constant(), None);
}

#[test]
fn random_draws_use_the_given_stream() {
    let p = compile(&parse("uniform(2, 3) + rand() * 0").unwrap(), NAMES).unwrap();
    assert!(p.uses_rng());
    let a = p.eval_rng(&[], &mut Rng::from_seed(4));
    let b = p.eval_rng(&[], &mut Rng::from_seed(4));
    assert_eq!(a, b);
    assert!((2.0..3.0).contains(&a));
}

#[test]
fn errors_name_the_problem_with_hints() {
    assert!(err("x +").contains("expected an expression, found end of input"));
    assert!(err("(x").contains("expected `)` to close `(`"));
    assert!(err("sizex").contains("unknown name `sizex`"));
    assert!(err("min(1)").contains("`min` takes 2 arguments, found 1"));
    assert!(err("sine(1)").contains("unknown function `sine`"));
    assert!(err("outside()").contains("unknown function `outside`"));
    assert!(err("1 2").contains("found number `2`"));
    let ast = parse("sizex").unwrap();
    let e = compile(&ast, NAMES).unwrap_err();
    assert_eq!(e[0].hints, vec!["did you mean `size.x`?".to_string()]);
    // Every error is reported, not only the first.
    assert_eq!(compile(&parse("a + b + min(1)").unwrap(), NAMES).unwrap_err().len(), 3);
}

#[test]
fn prefix_parsing_stops_where_the_expression_ends() {
    for (src, expect) in
        [("sz / 2); box;", "sz / 2"), ("2: A | 1r: B", "2"), ("1r", "1"), ("a ? b : c ]", "a ? b : c"), ("x y", "x")]
    {
        let (_, n) = parse_prefix(src).unwrap();
        assert_eq!(&src[..n], expect, "{src}");
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let src = format!("{}1{}", "(".repeat(10_000), ")".repeat(10_000));
    assert!(parse(&src).unwrap_err().message.contains("nested too deeply"));
    let src = "-".repeat(10_000) + "1";
    assert!(parse(&src).is_err());
    // `+` and `^` recurse too.
    for src in ["+".repeat(10_000) + "1", "2^".repeat(10_000) + "1"] {
        assert!(parse(&src).unwrap_err().message.contains("nested too deeply"));
    }
    let src = format!("{}x < 1", "not ".repeat(10_000));
    assert!(parse_prefix_in(&src, 0, HASH).unwrap_err().message.contains("formula is nested too deeply"));
}

/// A dialect like box-split's: `#` comments, `//` floor division, word
/// logic, raw block-type arguments to `FULL`.
const HASH: Dialect<'static> = Dialect {
    hash_comments: true,
    word_logic: true,
    digit_separators: true,
    dotted_names: false,
    reserved: &["when"],
    raw_argument: Some(RawArgument {
        calls: &["FULL"],
        noun: "block type",
        hint: "a block id",
        scan: |s, i| i + s[i..].find(|c: char| c == ')' || c.is_whitespace()).unwrap_or(s.len() - i),
    }),
    wording: Wording { expression: "a formula", hint: "", end: "the end of the file", quote_source: true },
};

fn hash_eval(src: &str) -> f64 {
    let (ast, _) = parse_prefix_in(src, 0, HASH).unwrap_or_else(|e| panic!("{src}: {e:?}"));
    compile(&ast, NAMES).unwrap_or_else(|e| panic!("{src}: {e:?}")).eval(&[2.0, 3.0, 0.5, 1.0, 7.0])
}

fn hash_err(src: &str) -> (String, u32) {
    let d = parse_prefix_in(src, 0, HASH).expect_err("an error");
    (d.message, d.span.unwrap().start)
}

#[test]
fn a_hash_dialect_floors_and_reads_words_loosely() {
    let cases = [
        ("-7 // 2", -4.0),
        ("-7 % 3", 2.0),
        ("x // 2 * 2 + x % 2 # a comment", 2.0),
        ("1_000 + y", 1003.0),
        // `not` takes the whole comparison; `!` too.
        ("not x < 1", 1.0),
        ("! x > 1 or y == 3", 1.0),
        ("not not x == 2 and y > 2", 1.0),
    ];
    for (s, v) in cases {
        assert_eq!(hash_eval(s), v, "{s}");
    }
    // The standard dialect reads the same text differently.
    assert_eq!(eval("!x < 1"), 1.0);
    assert_eq!(eval("-7 % 3"), -1.0);
}

#[test]
fn a_hash_dialect_reports_its_own_mistakes_where_they_are() {
    assert_eq!(hash_err("1 < x < 3"), ("comparisons do not chain".into(), 6));
    assert_eq!(hash_err("x = 3"), ("`=` is not a comparison".into(), 2));
    assert_eq!(hash_err("x < not y"), ("expected a formula, found `not`".into(), 4));
    assert_eq!(hash_err("when > 1"), ("expected a formula, found `when`".into(), 0));
    assert_eq!(hash_err("x +"), ("expected a formula, found the end of the file".into(), 3));
    assert_eq!(hash_err("FULL( )"), ("expected a block type in `FULL(…)`".into(), 6));
    assert_eq!(hash_err("FULL(a:b c"), ("expected `)` after the block type of `FULL`, found `c`".into(), 9));
    assert_eq!(hash_err("min(1 2)"), ("expected `,` or `)` in the arguments of `min`, found `2`".into(), 6));
    // `?:` and dotted names are not part of it: the formula ends there.
    for (src, expect) in [("x ? 1 : 2", "x"), ("size.x", "size"), ("x // 2 ]", "x // 2")] {
        let (_, n) = parse_prefix_in(src, 0, HASH).unwrap();
        assert_eq!(&src[..n], expect, "{src}");
    }
}

#[test]
fn raw_arguments_and_offsets_keep_file_positions() {
    let text = "let a = FULL(minecraft:stone) // 2;";
    let (ast, end) = parse_prefix_in(text, 8, HASH).unwrap();
    assert_eq!(&text[8..end], "FULL(minecraft:stone) // 2");
    assert_eq!((ast.span.start, ast.span.end), (8, end as u32));
    let Node::Call(f, _, args) = &ast.kind else { panic!("{ast:?}") };
    assert_eq!(f, "floor");
    let Node::Binary(BinOp::Div, lhs, _) = &args[0].kind else { panic!("{ast:?}") };
    let Node::Call(obs, _, raw) = &lhs.kind else { panic!("{lhs:?}") };
    assert_eq!(obs, "FULL");
    assert_eq!(raw[0].kind, Node::Var("minecraft:stone".into()));
    assert_eq!((raw[0].span.start, raw[0].span.end), (13, 28));
}

proptest::proptest! {
    #[test]
    fn parser_never_panics(s in "\\PC{0,64}") {
        if let Ok(p) = parse(&s).map_err(|_| ()).and_then(|ast| compile(&ast, NAMES).map_err(|_| ())) {
            let _ = p.eval(&[1.0, 2.0, 3.0, 4.0, 5.0]);
        }
        let _ = parse_prefix(&s);
    }

    #[test]
    fn the_hash_dialect_never_panics_and_spans_stay_in_the_text(s in "[-+*/%^()<>=!&|#,_ .0-9a-zA-Z:\n]{0,48}", at in 0usize..8) {
        let at = at.min(s.len());
        match parse_prefix_in(&s, at, HASH) {
            Ok((ast, end)) => {
                proptest::prop_assert!(at <= ast.span.start as usize && ast.span.end as usize <= end && end <= s.len());
                let _ = compile(&ast, NAMES).map(|p| p.eval(&[1.0, 2.0, 3.0, 4.0, 5.0]));
            }
            Err(d) => {
                let span = d.span.unwrap();
                proptest::prop_assert!(at <= span.start as usize && span.end as usize <= s.len(), "{d:?}");
            }
        }
    }

    #[test]
    fn printed_sums_evaluate_to_their_value(xs in proptest::collection::vec(-1000i32..1000, 1..20)) {
        let src = xs.iter().map(|x| format!("({x})")).collect::<Vec<_>>().join(" + ");
        let want: i64 = xs.iter().map(|x| *x as i64).sum();
        proptest::prop_assert_eq!(eval(&src), want as f64);
    }
}

#[test]
fn trivial_programs_describe_themselves() {
    let trivial = |src: &str| compile(&parse(src).unwrap(), NAMES).unwrap().trivial();
    use Operand::{Const, Load};
    assert_eq!(trivial("2.5"), Some(Trivial::Value(Const(2.5))));
    assert_eq!(trivial("1 + 2"), Some(Trivial::Value(Const(3.0))), "folded");
    assert_eq!(trivial("size.x"), Some(Trivial::Value(Load(2))));
    assert_eq!(trivial("x / 2"), Some(Trivial::Bin(Arith::Div, Load(0), Const(2.0))));
    assert_eq!(trivial("0.1 - y"), Some(Trivial::Bin(Arith::Sub, Const(0.1), Load(1))));
    assert_eq!(trivial("x * y"), Some(Trivial::Bin(Arith::Mul, Load(0), Load(1))));
    for src in ["-x", "x * x * 2", "x < 2", "sin(x)", "x % 2", "uniform(0, 1)"] {
        assert_eq!(trivial(src), None, "{src}");
    }
}

#[test]
fn did_you_mean_counts_a_swap_as_one_typo() {
    assert_eq!(super::did_you_mean("stpes", ["steps", "scale"]), Some("steps"));
    assert_eq!(super::did_you_mean("repellor", ["repeller", "attractor"]), Some("repeller"));
    assert_eq!(super::did_you_mean("xyzzy", ["steps", "scale"]), None);
    assert_eq!(super::suggest::edit_distance("ab", "ba"), 1);
    assert_eq!(super::suggest::edit_distance("", "ab"), 2);
}

/// The full alignment table, as `did_you_mean` computed it before the
/// bounded search (the oracle of the property below).
fn full_table_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut rows = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    (0..=a.len()).for_each(|i| rows[i][0] = i);
    (0..=b.len()).for_each(|j| rows[0][j] = j);
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut d = (rows[i - 1][j - 1] + cost).min(rows[i - 1][j] + 1).min(rows[i][j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(rows[i - 2][j - 2] + 1);
            }
            rows[i][j] = d;
        }
    }
    rows[a.len()][b.len()]
}

proptest::proptest! {
    /// The bounded search finds what comparing every candidate in full found.
    #[test]
    fn did_you_mean_picks_what_the_full_table_picks(
        name in "[abc_]{0,9}",
        candidates in proptest::collection::vec("[abc_]{0,9}", 0..8),
    ) {
        let mut best: Option<(usize, &str)> = None;
        for c in &candidates {
            let d = full_table_distance(&name, c);
            let limit = (name.chars().count().max(c.chars().count()) / 3).max(1);
            if d <= limit && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, c));
            }
        }
        proptest::prop_assert_eq!(super::did_you_mean(&name, candidates.iter().map(String::as_str)), best.map(|(_, c)| c));
        for c in &candidates {
            proptest::prop_assert_eq!(super::suggest::edit_distance(&name, c), full_table_distance(&name, c));
        }
    }
}

#[test]
fn formulas_of_every_stack_depth_evaluate() {
    // `x + (x + (… + x))` keeps one value pending per level: the short
    // stack, its edge and the full one.
    for depth in [1, 7, 8, 9, 20, 63] {
        let src = (0..depth).fold("y".to_string(), |inner, _| format!("x + ({inner})"));
        assert_eq!(eval(&src), 2.0 * depth as f64 + 3.0, "{depth}");
    }
}
