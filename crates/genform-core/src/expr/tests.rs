use super::*;
use crate::rng::Rng;

const NAMES: &Names<'static> = &Names(&["x", "y", "size.x", "has(next)"]);

fn eval(src: &str) -> f64 {
    let ast = parse(src).unwrap_or_else(|e| panic!("{src}: {e:?}"));
    let p = compile(&ast, NAMES).unwrap_or_else(|e| panic!("{src}: {e:?}"));
    p.eval(&[2.0, 3.0, 0.5, 1.0])
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
}

proptest::proptest! {
    #[test]
    fn parser_never_panics(s in "\\PC{0,64}") {
        if let Ok(p) = parse(&s).map_err(|_| ()).and_then(|ast| compile(&ast, NAMES).map_err(|_| ())) {
            let _ = p.eval(&[1.0, 2.0, 3.0, 4.0]);
        }
        let _ = parse_prefix(&s);
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
    assert_eq!(super::edit_distance("ab", "ba"), 1);
    assert_eq!(super::edit_distance("", "ab"), 2);
}
