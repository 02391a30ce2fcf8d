//! 2D vector formulas, compiled to one scalar [`Program`] per component.
//!
//! Front ends with geometry (the graph grammar's positions) let formulas mix
//! numbers and 2D vectors: `A + v / 3 + perp_left(v) / 3`. This module
//! infers which sub-expressions are vectors, then expands every vector
//! sub-expression into its x and y scalar formulas, so the result runs on
//! the ordinary bytecode machine with no vector values at run time.
//!
//! Vector values are the names a [`VecScope`] declares as vectors, `vec(x,
//! y)`, sums and differences of vectors, vectors times or divided by
//! numbers, `-v`, `c ? v : w`, and the helpers `rotate(v, degrees)`
//! (counter-clockwise), `normalize(v)`, `perp_left(v)` (v turned +90°),
//! `perp_right(v)` (−90°) and `lerp(a, b, t)` / `mix(a, b, t)`. Numbers from
//! vectors: `norm(v)`, `dot(a, b)`, `cross(a, b)` (the z of the 3D cross
//! product), `angle(v)` (degrees from +x, counter-clockwise) and
//! `dist(a, b)`.
//!
//! Random draws inside a vector sub-expression are refused: its formula is
//! evaluated once per component, so `rotate(v, uniform(0, 90))` would turn
//! x and y by different angles. Draw the value once into a variable instead.

use super::Scope;
use super::compile::{Program, builtin_constant, compile, is_random_function};
use super::parse::{Ast, BinOp, Node, UnOp};
use crate::diag::{Diagnostic, Span};

/// Largest expansion (in syntax-tree nodes per component) accepted, so
/// nested `rotate`s cannot blow up exponentially.
const MAX_NODES: u64 = 20_000;

/// A [`Scope`] that also knows vector-valued names.
pub trait VecScope: Scope {
    /// The scalar names (resolved through [`Scope::variable`] or
    /// [`Scope::constant`]) of the x and y components of vector `name`, e.g.
    /// `A` → `["A.x", "A.y"]`; `None` when `name` is not a vector.
    fn vector(&self, name: &str) -> Option<[String; 2]>;
}

/// A compiled formula that may be a number or a vector.
#[derive(Clone, Debug, PartialEq)]
pub enum Compiled {
    /// A number.
    Scalar(Program),
    /// A vector: the x and y programs.
    Vector([Program; 2]),
}

/// Compiles a formula that must be a vector. Every error is reported
/// (unknown names, type mismatches such as `v * w`, random draws).
pub fn compile_vec2(ast: &Ast, scope: &dyn VecScope) -> Result<[Program; 2], Vec<Diagnostic>> {
    match compile_any(ast, scope)? {
        Compiled::Vector(p) => Ok(p),
        Compiled::Scalar(_) => Err(vec![
            Diagnostic::error(ast.span, "expected a vector, found a number")
                .with_hint("write a point such as `A`, `vec(x, y)` or `A + v / 2`"),
        ]),
    }
}

/// Compiles a formula that must be a number; vector sub-expressions are
/// allowed where a function turns them into numbers (`norm(B - A) > 2`).
pub fn compile_scalar(ast: &Ast, scope: &dyn VecScope) -> Result<Program, Vec<Diagnostic>> {
    match compile_any(ast, scope)? {
        Compiled::Scalar(p) => Ok(p),
        Compiled::Vector(_) => Err(vec![
            Diagnostic::error(ast.span, "expected a number, found a vector")
                .with_hint("use `norm(v)` for its length, or `v.x` / `v.y` for a component"),
        ]),
    }
}

/// Compiles a formula that may be either a number or a vector.
pub fn compile_any(ast: &Ast, scope: &dyn VecScope) -> Result<Compiled, Vec<Diagnostic>> {
    let mut errors = Vec::new();
    let ty = infer(ast, scope, &mut errors);
    if !errors.is_empty() {
        return Err(errors);
    }
    let size = cost(ast);
    if size > MAX_NODES {
        return Err(vec![
            Diagnostic::error(ast.span, "this vector formula is too large once split into components")
                .with_hint("name intermediate vectors in variables or `vectors:`"),
        ]);
    }
    let ex = Expander { scope };
    if ty != Ty::Vector {
        let lowered = ex.lower(ast, &mut errors);
        if !errors.is_empty() {
            return Err(errors);
        }
        return compile(&lowered, scope).map(Compiled::Scalar);
    }
    if let Some(span) = random_call(ast) {
        return Err(vec![random_in_vector(span)]);
    }
    let [x, y] = [0, 1].map(|c| ex.expand(ast, c, &mut errors));
    if !errors.is_empty() {
        return Err(errors);
    }
    let (px, py) = (compile(&x, scope), compile(&y, scope));
    match (px, py) {
        (Ok(px), Ok(py)) => Ok(Compiled::Vector([px, py])),
        // Both components name the same unknowns; report them once.
        (Err(e), _) | (Ok(_), Err(e)) => Err(e),
    }
}

fn random_in_vector(span: Span) -> Diagnostic {
    Diagnostic::error(span, "a vector formula cannot draw random numbers (each component would draw its own)")
        .with_hint("draw the value once in a per-application variable and use the variable here")
}

/// The span of the first random draw in `ast`.
fn random_call(ast: &Ast) -> Option<Span> {
    match &ast.kind {
        Node::Num(_) | Node::Var(_) => None,
        Node::Unary(_, a) => random_call(a),
        Node::Binary(_, a, b) => random_call(a).or_else(|| random_call(b)),
        Node::Cond(c, a, b) => random_call(c).or_else(|| random_call(a)).or_else(|| random_call(b)),
        Node::Call(name, span, args) => {
            if is_random_function(name) {
                Some(*span)
            } else {
                args.iter().find_map(random_call)
            }
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ty {
    Scalar,
    Vector,
    /// An unknown name: compatible with anything, so that the compiler
    /// reports it as unknown instead of a type mismatch.
    Unknown,
}

fn ty_name(t: Ty) -> &'static str {
    match t {
        Ty::Scalar | Ty::Unknown => "a number",
        Ty::Vector => "a vector",
    }
}

/// Whether a value of type `have` may stand where `want` is expected.
fn fits(want: Ty, have: Ty) -> bool {
    want == have || have == Ty::Unknown || want == Ty::Unknown
}

/// The vector helpers: name, argument types, result type.
fn vector_function(name: &str, args: &[Ty]) -> Option<(&'static [Ty], Ty)> {
    use Ty::{Scalar as S, Vector as V};
    Some(match name {
        "vec" => (&[S, S], V),
        "rotate" => (&[V, S], V),
        "normalize" => (&[V], V),
        "perp_left" | "perp_right" => (&[V], V),
        "norm" => (&[V], S),
        "dot" | "cross" | "dist" => (&[V, V], S),
        "angle" => (&[V], S),
        // Scalar `lerp`/`mix` stay the built-ins.
        "lerp" | "mix" if args.first() == Some(&V) => (&[V, V, S], V),
        _ => return None,
    })
}

/// Infers the type of `ast`, recording mismatches.
fn infer(ast: &Ast, scope: &dyn VecScope, errors: &mut Vec<Diagnostic>) -> Ty {
    use Ty::{Scalar as S, Unknown as U, Vector as V};
    match &ast.kind {
        Node::Num(_) => S,
        Node::Var(name) => {
            if scope.variable(name).is_some() || scope.constant(name).is_some() || builtin_constant(name).is_some() {
                S
            } else if scope.vector(name).is_some() {
                V
            } else {
                U
            }
        }
        Node::Unary(op, a) => {
            let t = infer(a, scope, errors);
            if *op == UnOp::Not && t == V {
                errors.push(Diagnostic::error(ast.span, "`not` needs a number, found a vector"));
                return S;
            }
            t
        }
        Node::Binary(op, a, b) => {
            let (ta, tb) = (infer(a, scope, errors), infer(b, scope, errors));
            let any_vector = ta == V || tb == V;
            match op {
                BinOp::Add | BinOp::Sub => {
                    if (ta == V && tb == S) || (ta == S && tb == V) {
                        errors.push(
                            Diagnostic::error(
                                ast.span,
                                format!("cannot combine {} and {} with `+`/`-`", ty_name(ta), ty_name(tb)),
                            )
                            .with_hint("write `vec(x, y)` to make a vector from numbers"),
                        );
                    }
                    if any_vector {
                        V
                    } else if ta == S || tb == S {
                        S
                    } else {
                        U
                    }
                }
                BinOp::Mul if ta == V && tb == V => {
                    errors.push(
                        Diagnostic::error(ast.span, "cannot multiply two vectors")
                            .with_hint("use `dot(a, b)` for the dot product or `cross(a, b)` for the cross product"),
                    );
                    V
                }
                BinOp::Div if tb == V => {
                    errors.push(Diagnostic::error(ast.span, "cannot divide by a vector"));
                    V
                }
                BinOp::Mul | BinOp::Div => {
                    if any_vector {
                        V
                    } else if ta == S || tb == S {
                        S
                    } else {
                        U
                    }
                }
                _ => {
                    if any_vector {
                        errors.push(
                            Diagnostic::error(ast.span, "this operator needs numbers, found a vector")
                                .with_hint("compare lengths with `norm(v)` or components with `v.x` / `v.y`"),
                        );
                    }
                    S
                }
            }
        }
        Node::Cond(c, a, b) => {
            if infer(c, scope, errors) == V {
                errors.push(Diagnostic::error(c.span, "a condition must be a number, found a vector"));
            }
            let (ta, tb) = (infer(a, scope, errors), infer(b, scope, errors));
            if !fits(ta, tb) {
                errors.push(Diagnostic::error(
                    ast.span,
                    format!("the branches of `?:` differ: {} and {}", ty_name(ta), ty_name(tb)),
                ));
            }
            if ta == U { tb } else { ta }
        }
        Node::Call(name, _, args) => {
            let tys: Vec<Ty> = args.iter().map(|a| infer(a, scope, errors)).collect();
            match vector_function(name, &tys) {
                Some((want, result)) => {
                    if want.len() != args.len() {
                        let n = want.len();
                        errors.push(Diagnostic::error(
                            ast.span,
                            format!(
                                "`{name}` takes {n} argument{}, found {}",
                                if n == 1 { "" } else { "s" },
                                args.len()
                            ),
                        ));
                    } else {
                        for (i, (w, t)) in want.iter().zip(&tys).enumerate() {
                            if !fits(*w, *t) {
                                errors.push(Diagnostic::error(
                                    args[i].span,
                                    format!(
                                        "argument {} of `{name}` must be {}, found {}",
                                        i + 1,
                                        ty_name(*w),
                                        ty_name(*t)
                                    ),
                                ));
                            }
                        }
                    }
                    result
                }
                None => {
                    if let Some(i) = tys.iter().position(|t| *t == V) {
                        errors.push(
                            Diagnostic::error(args[i].span, format!("`{name}` needs numbers, found a vector"))
                                .with_hint("vector functions: rotate, normalize, perp_left, perp_right, norm, dot, cross, angle, dist, lerp, vec"),
                        );
                    }
                    S
                }
            }
        }
    }
}

/// Nodes in the expansion of `ast` (one component for vectors), saturating.
fn cost(ast: &Ast) -> u64 {
    let c = |a: &Ast| cost(a);
    match &ast.kind {
        Node::Num(_) | Node::Var(_) => 1,
        Node::Unary(_, a) => 1 + c(a),
        Node::Binary(_, a, b) => 1u64.saturating_add(c(a)).saturating_add(c(b)),
        Node::Cond(x, a, b) => 1u64.saturating_add(c(x)).saturating_add(c(a)).saturating_add(c(b)),
        Node::Call(name, _, args) => {
            let a: Vec<u64> = args.iter().map(c).collect();
            let sum = a.iter().fold(1u64, |s, x| s.saturating_add(*x));
            // How often each argument's (component) tree is copied.
            let k = match name.as_str() {
                "rotate" | "normalize" | "norm" | "dot" | "cross" | "dist" | "angle" => 3,
                "lerp" | "mix" => 2,
                _ => 1,
            };
            sum.saturating_mul(k).saturating_add(8)
        }
    }
}

struct Expander<'s> {
    scope: &'s dyn VecScope,
}

fn node(kind: Node, span: Span) -> Ast {
    Ast { kind, span }
}

fn bin(op: BinOp, a: Ast, b: Ast, span: Span) -> Ast {
    node(Node::Binary(op, Box::new(a), Box::new(b)), span)
}

fn call(name: &str, args: Vec<Ast>, span: Span) -> Ast {
    node(Node::Call(name.to_string(), span, args), span)
}

fn neg(a: Ast, span: Span) -> Ast {
    node(Node::Unary(UnOp::Neg, Box::new(a)), span)
}

impl Expander<'_> {
    fn is_vector(&self, ast: &Ast) -> bool {
        let mut sink = Vec::new();
        infer(ast, self.scope, &mut sink) == Ty::Vector
    }

    /// A scalar sub-tree with its vector parts turned into numbers.
    fn lower(&self, ast: &Ast, errors: &mut Vec<Diagnostic>) -> Ast {
        let span = ast.span;
        match &ast.kind {
            Node::Num(_) | Node::Var(_) => ast.clone(),
            Node::Unary(op, a) => node(Node::Unary(*op, Box::new(self.lower(a, errors))), span),
            Node::Binary(op, a, b) => bin(*op, self.lower(a, errors), self.lower(b, errors), span),
            Node::Cond(c, a, b) => node(
                Node::Cond(
                    Box::new(self.lower(c, errors)),
                    Box::new(self.lower(a, errors)),
                    Box::new(self.lower(b, errors)),
                ),
                span,
            ),
            Node::Call(name, name_span, args) => {
                let vector_args = args.iter().any(|a| self.is_vector(a));
                if !vector_args {
                    let args = args.iter().map(|a| self.lower(a, errors)).collect();
                    return node(Node::Call(name.clone(), *name_span, args), span);
                }
                if let Some(s) = args.iter().find_map(random_call) {
                    errors.push(random_in_vector(s));
                    return node(Node::Num(f64::NAN), span);
                }
                let comps =
                    |a: &Ast, errors: &mut Vec<Diagnostic>| [self.expand(a, 0, errors), self.expand(a, 1, errors)];
                match (name.as_str(), args.as_slice()) {
                    ("norm", [v]) => {
                        let [x, y] = comps(v, errors);
                        call("hypot", vec![x, y], span)
                    }
                    ("angle", [v]) => {
                        let [x, y] = comps(v, errors);
                        call("deg", vec![call("atan2", vec![y, x], span)], span)
                    }
                    ("dist", [a, b]) => {
                        let ([ax, ay], [bx, by]) = (comps(a, errors), comps(b, errors));
                        call("hypot", vec![bin(BinOp::Sub, bx, ax, span), bin(BinOp::Sub, by, ay, span)], span)
                    }
                    ("dot", [a, b]) => {
                        let ([ax, ay], [bx, by]) = (comps(a, errors), comps(b, errors));
                        bin(BinOp::Add, bin(BinOp::Mul, ax, bx, span), bin(BinOp::Mul, ay, by, span), span)
                    }
                    ("cross", [a, b]) => {
                        let ([ax, ay], [bx, by]) = (comps(a, errors), comps(b, errors));
                        bin(BinOp::Sub, bin(BinOp::Mul, ax, by, span), bin(BinOp::Mul, ay, bx, span), span)
                    }
                    // Type errors were reported by `infer`.
                    _ => node(Node::Num(f64::NAN), span),
                }
            }
        }
    }

    /// Component `c` (0 = x, 1 = y) of a vector sub-tree.
    fn expand(&self, ast: &Ast, c: usize, errors: &mut Vec<Diagnostic>) -> Ast {
        let span = ast.span;
        match &ast.kind {
            Node::Var(name) => match self.scope.vector(name) {
                Some(names) => node(Node::Var(names[c].clone()), span),
                // Unknown: left for the compiler to report.
                None => ast.clone(),
            },
            Node::Unary(UnOp::Neg, a) => neg(self.expand(a, c, errors), span),
            Node::Binary(op @ (BinOp::Add | BinOp::Sub), a, b) => {
                bin(*op, self.expand(a, c, errors), self.expand(b, c, errors), span)
            }
            Node::Binary(op @ (BinOp::Mul | BinOp::Div), a, b) => {
                if self.is_vector(a) {
                    bin(*op, self.expand(a, c, errors), self.lower(b, errors), span)
                } else {
                    bin(*op, self.lower(a, errors), self.expand(b, c, errors), span)
                }
            }
            Node::Cond(x, a, b) => node(
                Node::Cond(
                    Box::new(self.lower(x, errors)),
                    Box::new(self.expand(a, c, errors)),
                    Box::new(self.expand(b, c, errors)),
                ),
                span,
            ),
            Node::Call(name, _, args) => self.expand_call(name, args, c, span, errors),
            // Scalars in vector position were reported by `infer`.
            _ => node(Node::Num(f64::NAN), span),
        }
    }

    fn expand_call(&self, name: &str, args: &[Ast], c: usize, span: Span, errors: &mut Vec<Diagnostic>) -> Ast {
        let x = |a: &Ast, errors: &mut Vec<Diagnostic>| self.expand(a, 0, errors);
        let y = |a: &Ast, errors: &mut Vec<Diagnostic>| self.expand(a, 1, errors);
        match (name, args) {
            ("vec", [a, b]) => self.lower(if c == 0 { a } else { b }, errors),
            ("rotate", [v, deg]) => {
                let r = || call("rad", vec![self.lower(deg, &mut Vec::new())], span);
                let (cos, sin) = (call("cos", vec![r()], span), call("sin", vec![r()], span));
                let (vx, vy) = (x(v, errors), y(v, errors));
                if c == 0 {
                    bin(BinOp::Sub, bin(BinOp::Mul, vx, cos, span), bin(BinOp::Mul, vy, sin, span), span)
                } else {
                    bin(BinOp::Add, bin(BinOp::Mul, vx, sin, span), bin(BinOp::Mul, vy, cos, span), span)
                }
            }
            ("normalize", [v]) => {
                let len = call("hypot", vec![x(v, errors), y(v, errors)], span);
                bin(BinOp::Div, self.expand(v, c, errors), len, span)
            }
            ("perp_left", [v]) => {
                if c == 0 {
                    neg(y(v, errors), span)
                } else {
                    x(v, errors)
                }
            }
            ("perp_right", [v]) => {
                if c == 0 {
                    y(v, errors)
                } else {
                    neg(x(v, errors), span)
                }
            }
            ("lerp" | "mix", [a, b, t]) => {
                let (ac, bc) = (self.expand(a, c, errors), self.expand(b, c, errors));
                let delta = bin(BinOp::Sub, bc, ac.clone(), span);
                bin(BinOp::Add, ac, bin(BinOp::Mul, delta, self.lower(t, errors), span), span)
            }
            _ => node(Node::Num(f64::NAN), span),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::parse;

    /// `A` = (1, 2), `v` = (3, 4) (components at env 0–3), `s` = 2 (env 4).
    struct Geo;

    impl Scope for Geo {
        fn variable(&self, name: &str) -> Option<u32> {
            ["A.x", "A.y", "v.x", "v.y", "s"].iter().position(|n| *n == name).map(|i| i as u32)
        }
        fn names(&self) -> Vec<String> {
            ["A", "v", "s", "A.x", "A.y", "v.x", "v.y"].iter().map(|s| s.to_string()).collect()
        }
    }

    impl VecScope for Geo {
        fn vector(&self, name: &str) -> Option<[String; 2]> {
            matches!(name, "A" | "v").then(|| [format!("{name}.x"), format!("{name}.y")])
        }
    }

    const ENV: [f64; 5] = [1.0, 2.0, 3.0, 4.0, 2.0];

    fn vec_of(src: &str) -> [f64; 2] {
        let p = compile_vec2(&parse(src).unwrap(), &Geo).unwrap_or_else(|e| panic!("{src}: {e:?}"));
        [p[0].eval(&ENV), p[1].eval(&ENV)]
    }

    fn scalar(src: &str) -> f64 {
        compile_scalar(&parse(src).unwrap(), &Geo).unwrap_or_else(|e| panic!("{src}: {e:?}")).eval(&ENV)
    }

    fn errors(src: &str) -> Vec<String> {
        let ast = parse(src).unwrap();
        let e = match compile_any(&ast, &Geo) {
            Ok(_) => compile_vec2(&ast, &Geo).err().unwrap_or_default(),
            Err(e) => e,
        };
        e.into_iter().map(|d| d.message).collect()
    }

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    #[test]
    fn vector_arithmetic_and_helpers() {
        let cases: [(&str, [f64; 2]); 12] = [
            ("A", [1.0, 2.0]),
            ("A + v / 2", [2.5, 4.0]),
            ("s * v - A", [5.0, 6.0]),
            ("-v", [-3.0, -4.0]),
            ("vec(s, s + 1)", [2.0, 3.0]),
            ("perp_left(v)", [-4.0, 3.0]),
            ("perp_right(v)", [4.0, -3.0]),
            ("rotate(v, 90)", [-4.0, 3.0]),
            ("rotate(vec(1, 0), 180)", [-1.0, 0.0]),
            ("normalize(v)", [0.6, 0.8]),
            ("lerp(A, A + v, 0.5)", [2.5, 4.0]),
            ("s > 1 ? A : v", [1.0, 2.0]),
        ];
        for (src, want) in cases {
            assert!(close(vec_of(src), want), "{src}: {:?}", vec_of(src));
        }
        // The paper's Koch point: A + v/2 + perp_left(v)/3.
        assert!(close(vec_of("A + v/2 + perp_left(v)/3"), [2.5 - 4.0 / 3.0, 4.0 + 1.0]));
    }

    #[test]
    fn numbers_from_vectors() {
        assert_eq!(scalar("norm(v)"), 5.0);
        assert_eq!(scalar("dot(A, v)"), 11.0);
        assert_eq!(scalar("cross(A, v)"), -2.0);
        assert_eq!(scalar("dist(A, A + v)"), 5.0);
        assert!((scalar("angle(vec(0, 1))") - 90.0).abs() < 1e-12);
        assert_eq!(scalar("norm(v) > 4 && v.x == 3"), 1.0);
        // Scalar `mix` is still the built-in.
        assert_eq!(scalar("mix(0, 10, 0.5)"), 5.0);
    }

    #[test]
    fn type_errors_are_reported_with_hints() {
        assert_eq!(errors("v * v"), ["cannot multiply two vectors"]);
        assert_eq!(errors("v + 1"), ["cannot combine a vector and a number with `+`/`-`"]);
        assert_eq!(errors("v < A"), ["this operator needs numbers, found a vector"]);
        assert_eq!(errors("sin(v)"), ["`sin` needs numbers, found a vector"]);
        assert_eq!(errors("rotate(s, v)").len(), 2);
        assert_eq!(errors("norm(v, v)"), ["`norm` takes 1 argument, found 2"]);
        assert_eq!(errors("s"), ["expected a vector, found a number"]);
        let e = compile_scalar(&parse("v").unwrap(), &Geo).unwrap_err();
        assert!(e[0].hints[0].contains("norm(v)"));
        // Unknown names keep their spans and hints.
        let e = compile_vec2(&parse("A + w").unwrap(), &Geo).unwrap_err();
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].message, "unknown name `w`");
        assert_eq!(e[0].span, Some(Span::new(4, 5)));
    }

    #[test]
    fn random_draws_inside_vectors_are_refused() {
        for src in ["rotate(v, uniform(0, 90))", "v * rand()", "A + vec(normal(0, 1), 0)"] {
            let e = errors(src);
            assert_eq!(e.len(), 1, "{src}: {e:?}");
            assert!(e[0].contains("cannot draw random numbers"), "{src}");
        }
        assert!(errors("norm(v * rand())")[0].contains("cannot draw random numbers"));
        // A scalar draw outside any vector is fine.
        let p = compile_scalar(&parse("norm(v) * uniform(1, 2)").unwrap(), &Geo).unwrap();
        assert!(p.uses_rng());
    }

    proptest::proptest! {
        #[test]
        fn any_formula_compiles_or_fails_cleanly(s in "[Avs0-9+*/(), .xy-]{0,40}|rotate\\(v, [0-9]{1,3}\\)") {
            if let Ok(ast) = parse(&s) {
                match compile_any(&ast, &Geo) {
                    Ok(Compiled::Scalar(p)) => { let _ = p.eval(&ENV); }
                    Ok(Compiled::Vector([x, y])) => { let _ = (x.eval(&ENV), y.eval(&ENV)); }
                    Err(e) => proptest::prop_assert!(!e.is_empty()),
                }
            }
        }
    }

    #[test]
    fn nested_rotations_are_bounded() {
        let mut src = "v".to_string();
        for _ in 0..12 {
            src = format!("rotate({src}, 10)");
        }
        assert!(errors(&src)[0].contains("too large"));
        let ok = (0..3).fold("v".to_string(), |s, _| format!("rotate({s}, 30)"));
        assert!(close(vec_of(&ok), [-4.0, 3.0]));
    }
}
