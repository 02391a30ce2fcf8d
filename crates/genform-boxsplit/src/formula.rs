//! Constraint and size formulas: their syntax tree, and their translation
//! to the project's one expression compiler (`genform_core::expr`).
//!
//! The `.bsg` front end parses formulas itself because two of its tokens
//! mean something else to the core lexer: `#` starts a comment here, and
//! `//` is integer division (a comment there). A parsed formula is written
//! back as core expression text — fully parenthesized, `a // b` as
//! `floor((a) / (b))`, `a % b` as `mod(a, b)`, observers as the host query
//! `FULL(t3)` that the core resolves through [`Scope::variable`] — and
//! compiled by the core; every span the core reports is mapped back into
//! the `.bsg` file.

use crate::observe::TypeTable;
use crate::syntax::Ident;
use genform_core::diag::{Diagnostic, SourceFile, Span};
use genform_core::expr::{self, Program, Scope};
use std::collections::HashMap;
use std::fmt::Write;

/// A formula as written.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum ExprKind {
    Num(f64),
    Name(String),
    /// A function call: name, the name's span, arguments.
    Call(String, Span, Vec<Expr>),
    Observe(Observer, Ident),
    Unary(UnOp, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
}

/// What an observer asks about the pre-existing world in the scope's box.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Observer {
    /// Every cell is of the type.
    Full,
    /// At least one cell is.
    NonEmpty,
    /// No cell is.
    Empty,
    /// How many cells are.
    Count,
}

impl Observer {
    pub(crate) fn from_name(name: &str) -> Option<Observer> {
        Some(match name {
            "FULL" => Observer::Full,
            "NONEMPTY" => Observer::NonEmpty,
            "EMPTY" => Observer::Empty,
            "COUNT" => Observer::Count,
            _ => return None,
        })
    }

    fn name(self) -> &'static str {
        match self {
            Observer::Full => "FULL",
            Observer::NonEmpty => "NONEMPTY",
            Observer::Empty => "EMPTY",
            Observer::Count => "COUNT",
        }
    }

    /// The observer's value for `count` matching cells of `volume`.
    #[inline]
    pub(crate) fn value(self, count: u64, volume: u64) -> f64 {
        let b = |c: bool| if c { 1.0 } else { 0.0 };
        match self {
            Observer::Full => b(count == volume),
            Observer::NonEmpty => b(count > 0),
            Observer::Empty => b(count == 0),
            Observer::Count => count as f64,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UnOp {
    Neg,
    Not,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BinOp {
    Or,
    And,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    Add,
    Sub,
    Mul,
    Div,
    IntDiv,
    Rem,
    Pow,
}

/// The scope variables every formula can read, in env order. Sizes are in
/// the scope's local axes; world sizes, corners and offsets in world axes.
pub(crate) const VARIABLES: &[&str] = &[
    "X", "Y", "Z", "WORLD_X", "WORLD_Y", "WORLD_Z", "SMALLEST", "LARGEST", "MIN_X", "MIN_Y", "MIN_Z", "OFFSET_X",
    "OFFSET_Y", "OFFSET_Z",
];

/// Env index of the first observer value.
pub(crate) const FIXED: usize = VARIABLES.len();

/// A compiled formula.
#[derive(Clone, Debug)]
pub(crate) struct Formula {
    pub program: Program,
    /// Observer slots the program reads (env index − [`FIXED`]).
    pub observers: Vec<u32>,
    /// The value when it does not depend on the scope.
    pub constant: Option<f64>,
    /// The divisors of its `/`, `//` and `%`, inner ones first: checked
    /// before each evaluation, since a zero divisor would otherwise give
    /// an infinity or NaN that comparisons silently turn into true or false.
    pub divisors: Vec<Divisor>,
}

/// The right operand of one division in a formula.
#[derive(Clone, Debug)]
pub(crate) struct Divisor {
    pub program: Program,
    /// Conditions under which the division is evaluated at all (the left
    /// side of `&&` / `||`, the test of `if`), each with the truth value
    /// that reaches it.
    pub guards: Vec<(Program, bool)>,
    /// `file:line:col` of the division.
    pub at: String,
    /// The division as written.
    pub text: String,
}

impl Formula {
    /// The first division (in evaluation order) whose divisor is zero on
    /// `env`, or `None`.
    #[inline]
    pub(crate) fn zero_divisor(&self, env: &[f64]) -> Option<&Divisor> {
        let holds = |v: f64| v != 0.0 && !v.is_nan();
        self.divisors
            .iter()
            .find(|d| d.program.eval(env) == 0.0 && d.guards.iter().all(|(g, want)| holds(g.eval(env)) == *want))
    }
}

/// A `let` definition.
#[derive(Clone, Debug)]
struct Let {
    expr: Expr,
    /// Set when the formula is a constant (then it is a core constant).
    constant: Option<f64>,
}

/// Formula compilation state shared by a whole grammar: `let`s and the
/// observer slots (one per distinct observer and block type).
#[derive(Default, Debug)]
pub(crate) struct Formulas {
    lets: HashMap<String, Let>,
    let_order: Vec<String>,
    constants: HashMap<String, f64>,
    /// Observer and block type per slot.
    pub slots: Vec<(Observer, u32)>,
    slot_keys: HashMap<String, u32>,
    /// The file, to locate divisions in derivation errors.
    source: Option<SourceFile>,
}

struct Lowered {
    text: String,
    /// Generated byte range → source span, for every node.
    map: Vec<(usize, usize, Span)>,
    /// Each division's span, right operand and guards, inner ones first.
    divisions: Vec<(Span, Expr, Guards)>,
    /// The conditions around the node being lowered.
    guards: Guards,
}

/// Conditions with the truth value that reaches a node (see
/// [`Divisor::guards`]).
type Guards = Vec<(Expr, bool)>;

struct LowerScope<'a> {
    constants: &'a HashMap<String, f64>,
    slot_keys: &'a HashMap<String, u32>,
    lets: &'a [String],
}

impl Scope for LowerScope<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        if let Some(i) = VARIABLES.iter().position(|v| *v == name) {
            return Some(i as u32);
        }
        self.slot_keys.get(name).map(|s| (FIXED as u32) + s)
    }
    fn constant(&self, name: &str) -> Option<f64> {
        self.constants.get(name).copied()
    }
    fn names(&self) -> Vec<String> {
        VARIABLES.iter().map(|s| s.to_string()).chain(self.lets.iter().cloned()).collect()
    }
}

impl Formulas {
    /// Formula state for the grammar in `file`.
    pub(crate) fn for_file(file: &SourceFile) -> Formulas {
        Formulas { source: Some(file.clone()), ..Formulas::default() }
    }

    /// Defines `let name = expr`. Errors go to `errors`.
    pub(crate) fn define(&mut self, name: &Ident, e: &Expr, types: &mut TypeTable, errors: &mut Vec<Diagnostic>) {
        if VARIABLES.contains(&name.name.as_str()) || Observer::from_name(&name.name).is_some() {
            errors.push(Diagnostic::error(name.span, format!("`{}` is a built-in name", name.name)));
            return;
        }
        if self.lets.contains_key(&name.name) {
            errors.push(Diagnostic::error(name.span, format!("`{}` is defined twice", name.name)));
            return;
        }
        let Some(f) = self.compile(e, types, errors) else { return };
        self.lets.insert(name.name.clone(), Let { expr: e.clone(), constant: f.constant });
        if let Some(v) = f.constant {
            self.constants.insert(name.name.clone(), v);
        }
        self.let_order.push(name.name.clone());
    }

    /// Compiles a formula; `None` after reporting its errors.
    pub(crate) fn compile(&mut self, e: &Expr, types: &mut TypeTable, errors: &mut Vec<Diagnostic>) -> Option<Formula> {
        self.compile_with(e, types, errors, true)
    }

    /// [`Formulas::compile`]; the divisor checks only when `checks` (the
    /// divisors and guards themselves need none: their divisions are
    /// already listed, and compiling them again would cost exponential
    /// time in the nesting).
    fn compile_with(
        &mut self,
        e: &Expr,
        types: &mut TypeTable,
        errors: &mut Vec<Diagnostic>,
        checks: bool,
    ) -> Option<Formula> {
        let mut out = Lowered { text: String::new(), map: Vec::new(), divisions: Vec::new(), guards: Vec::new() };
        let before = errors.len();
        self.lower(e, types, errors, &mut out);
        if errors.len() > before {
            return None;
        }
        let ast = match expr::parse(&out.text) {
            Ok(a) => a,
            Err(d) => {
                errors.push(Diagnostic::error(e.span, format!("internal: formula did not translate ({})", d.message)));
                return None;
            }
        };
        let scope = LowerScope { constants: &self.constants, slot_keys: &self.slot_keys, lets: &self.let_order };
        match expr::compile(&ast, &scope) {
            Ok(program) if program.uses_rng() => {
                errors.push(
                    Diagnostic::error(e.span, "random functions are not available in box-split formulas")
                        .with_hint("every random choice goes through weighted alternatives and materials"),
                );
                None
            }
            Ok(program) => {
                let observers =
                    program.loads().filter(|&i| i as usize >= FIXED).map(|i| i - FIXED as u32).collect::<Vec<_>>();
                let mut observers = observers;
                observers.sort_unstable();
                observers.dedup();
                let constant = program.constant();
                let mut divisors = Vec::with_capacity(out.divisions.len());
                for (span, b, guard_exprs) in out.divisions.iter().filter(|_| checks) {
                    // Nested divisions are already in `out.divisions`.
                    let program = self.compile_with(b, types, errors, false)?.program;
                    let mut guards = Vec::with_capacity(guard_exprs.len());
                    for (g, want) in guard_exprs {
                        guards.push((self.compile_with(g, types, errors, false)?.program, *want));
                    }
                    if constant.is_some() {
                        // Folded now and never evaluated again: report here.
                        if program.constant() == Some(0.0) {
                            errors.push(
                                Diagnostic::error(*span, "division by zero")
                                    .with_hint("`/`, `//` and `%` need a divisor that is not 0"),
                            );
                            return None;
                        }
                        continue;
                    }
                    let (at, text) = match &self.source {
                        Some(f) => (
                            f.location(span.start),
                            f.text.get(span.start as usize..span.end as usize).unwrap_or("").to_string(),
                        ),
                        None => (format!("byte {}", span.start), String::new()),
                    };
                    divisors.push(Divisor { program, guards, at, text });
                }
                Some(Formula { program, observers, constant, divisors })
            }
            Err(ds) => {
                for d in ds {
                    let mapped = map_back(&out, d.span, e.span);
                    let d = Diagnostic { span: Some(mapped), labels: Vec::new(), ..d };
                    if !errors.iter().any(|x| x.span == d.span && x.message == d.message) {
                        errors.push(d);
                    }
                }
                None
            }
        }
    }

    fn lower(&mut self, e: &Expr, types: &mut TypeTable, errors: &mut Vec<Diagnostic>, out: &mut Lowered) {
        let start = out.text.len();
        match &e.kind {
            ExprKind::Num(v) => {
                let _ = write!(out.text, "{v:?}");
            }
            ExprKind::Name(n) => match self.lets.get(n) {
                Some(l) if l.constant.is_none() => {
                    // Scope-dependent: the definition is evaluated in the
                    // scope of each use.
                    let inner = l.expr.clone();
                    out.text.push('(');
                    self.lower(&inner, types, errors, out);
                    out.text.push(')');
                }
                _ => out.text.push_str(n),
            },
            ExprKind::Call(name, name_span, args) => {
                out.text.push_str(name);
                out.map.push((start, out.text.len(), *name_span));
                out.text.push('(');
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        out.text.push_str(", ");
                    }
                    // `if(c, a, b)` evaluates only one branch.
                    let guarded = name == "if" && args.len() == 3 && i > 0;
                    if guarded {
                        out.guards.push((args[0].clone(), i == 1));
                    }
                    self.lower(a, types, errors, out);
                    if guarded {
                        out.guards.pop();
                    }
                }
                out.text.push(')');
            }
            ExprKind::Observe(obs, arg) => match types.resolve(arg) {
                Ok(t) => {
                    let key = format!("{}(t{t})", obs.name());
                    if !self.slot_keys.contains_key(&key) {
                        self.slot_keys.insert(key.clone(), self.slots.len() as u32);
                        self.slots.push((*obs, t));
                    }
                    out.text.push_str(&key);
                }
                Err(d) => {
                    errors.push(d);
                    out.text.push('0');
                }
            },
            ExprKind::Unary(op, a) => {
                out.text.push_str(match op {
                    UnOp::Neg => "-(",
                    UnOp::Not => "!(",
                });
                self.lower(a, types, errors, out);
                out.text.push(')');
            }
            ExprKind::Binary(op, a, b) => {
                let (open, mid, close) = match op {
                    BinOp::IntDiv => ("floor((", ") / (", "))"),
                    BinOp::Rem => ("mod(", ", ", ")"),
                    BinOp::Or => ("(", " || ", ")"),
                    BinOp::And => ("(", " && ", ")"),
                    BinOp::Eq => ("(", " == ", ")"),
                    BinOp::Ne => ("(", " != ", ")"),
                    BinOp::Lt => ("(", " < ", ")"),
                    BinOp::Le => ("(", " <= ", ")"),
                    BinOp::Gt => ("(", " > ", ")"),
                    BinOp::Ge => ("(", " >= ", ")"),
                    BinOp::Add => ("(", " + ", ")"),
                    BinOp::Sub => ("(", " - ", ")"),
                    BinOp::Mul => ("(", " * ", ")"),
                    BinOp::Div => ("(", " / ", ")"),
                    BinOp::Pow => ("(", " ^ ", ")"),
                };
                out.text.push_str(open);
                self.lower(a, types, errors, out);
                out.text.push_str(mid);
                // `&&` and `||` evaluate their right side only as needed.
                let guarded = matches!(op, BinOp::And | BinOp::Or);
                if guarded {
                    out.guards.push(((**a).clone(), *op == BinOp::And));
                }
                self.lower(b, types, errors, out);
                if guarded {
                    out.guards.pop();
                }
                out.text.push_str(close);
                if matches!(op, BinOp::Div | BinOp::IntDiv | BinOp::Rem) {
                    out.divisions.push((e.span, (**b).clone(), out.guards.clone()));
                }
            }
        }
        out.map.push((start, out.text.len(), e.span));
    }
}

/// The source span of a span in generated text: the node generated exactly
/// there, else the smallest node around its start, else the whole formula.
fn map_back(out: &Lowered, span: Option<Span>, whole: Span) -> Span {
    let Some(s) = span else { return whole };
    let (a, b) = (s.start as usize, s.end as usize);
    if let Some(&(_, _, src)) = out.map.iter().find(|(x, y, _)| *x == a && *y == b) {
        return src;
    }
    out.map.iter().filter(|(x, y, _)| *x <= a && a < *y).min_by_key(|(x, y, _)| y - x).map_or(whole, |m| m.2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax;

    /// Compiles the condition of `A { when <src> { skip } }`.
    fn formula(src: &str) -> Result<(Formula, Formulas), Vec<Diagnostic>> {
        let text = format!("A {{ when {src} {{ skip }} }}");
        let (items, errors) = syntax::parse(&text);
        assert!(errors.is_empty(), "{errors:?}");
        let syntax::Item::Rule(r) = &items[0] else { panic!() };
        let syntax::Guard::When(e) = &r.alts[0].guard else { panic!() };
        let mut f = Formulas::default();
        let mut errors = Vec::new();
        let mut types = TypeTable::new();
        match f.compile(e, &mut types, &mut errors) {
            Some(p) => Ok((p, f)),
            None => Err(errors),
        }
    }

    fn eval(src: &str, env: &[f64]) -> f64 {
        formula(src).unwrap().0.program.eval(env)
    }

    #[test]
    fn integer_division_and_remainder_floor() {
        assert_eq!(eval("7 // 2", &[]), 3.0);
        assert_eq!(eval("-7 // 2", &[]), -4.0);
        assert_eq!(eval("7 % 3", &[]), 1.0);
        assert_eq!(eval("-7 % 3", &[]), 2.0);
        assert_eq!(eval("X // 4 * 4 + X % 4", &[13.0]), 13.0);
        assert_eq!(eval("2 ^ 3 ^ 2", &[]), 512.0);
    }

    #[test]
    fn logic_and_comparisons() {
        let env = [5.0, 3.0, 8.0];
        assert_eq!(eval("X > 4 and Y < 4", &env), 1.0);
        assert_eq!(eval("X > 4 and not Y < 4", &env), 0.0);
        assert_eq!(eval("X < 4 or Z == 8", &env), 1.0);
        assert_eq!(eval("!(X == 5) || Y != 3", &env), 0.0);
        assert_eq!(eval("min(X, Y) + max(X, Z)", &env), 11.0);
    }

    #[test]
    fn observers_get_slots_after_the_fixed_variables() {
        let (f, fs) = formula("FULL(SOLID) and NONEMPTY(water) or FULL(SOLID)").unwrap();
        assert_eq!(fs.slots.len(), 2);
        assert_eq!(f.observers, vec![0, 1]);
        let mut env = vec![0.0; FIXED + 2];
        env[FIXED] = 1.0;
        env[FIXED + 1] = 1.0;
        assert_eq!(f.program.eval(&env), 1.0);
        env[FIXED + 1] = 0.0;
        assert_eq!(f.program.eval(&env), 1.0);
        env[FIXED] = 0.0;
        assert_eq!(f.program.eval(&env), 0.0);
    }

    #[test]
    fn core_errors_point_into_the_bsg_file() {
        let errs = formula("X > 2 and  Wdth < 3").unwrap_err();
        assert_eq!(errs.len(), 1);
        let s = errs[0].span.unwrap();
        assert_eq!((s.start, s.end), (20, 24), "{errs:?}");
        assert!(errs[0].message.contains("unknown name `Wdth`"));
        let errs = formula("mn(X, 2) > 1").unwrap_err();
        assert_eq!(errs[0].span.unwrap().start, 9);
        assert!(errs[0].message.contains("unknown function"), "{errs:?}");
        let errs = formula("FULL(ROCK)").unwrap_err();
        assert!(errs[0].message.contains("ROCK"), "{errs:?}");
    }
}
