//! Constraint and size formulas in the `.bsg` dialect of the project's one
//! expression language (`genform_core::expr`).
//!
//! The core parser reads them in [`DIALECT`](crate::dialect::DIALECT): `#` starts a comment there and
//! `//` is integer division, `%` the floored remainder, `not` binds looser
//! than comparisons, and observers such as `FULL(minecraft:stone)` take a
//! block type as written. This module resolves what only a grammar knows —
//! observers become host variables `FULL(t3)` with a slot each, `let`
//! definitions are folded or inlined — and lists every division with the
//! conditions that guard it, so a zero divisor is reported at its
//! `file:line:col` instead of turning into a silent infinity.

use crate::observe::TypeTable;
use crate::syntax::Ident;
use genform_core::diag::{Diagnostic, SourceFile, Span};
use genform_core::expr::{self, Ast, BinOp, Node, Program, Scope};
use std::collections::HashMap;

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
    expr: Ast,
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

/// The divisions met while lowering a formula.
#[derive(Default)]
struct Lowered {
    /// Each division's span, lowered right operand and guards, inner ones
    /// first.
    divisions: Vec<(Span, Ast, Guards)>,
    /// The conditions around the node being lowered.
    guards: Guards,
}

/// Lowered conditions with the truth value that reaches a node (see
/// [`Divisor::guards`]).
type Guards = Vec<(Ast, bool)>;

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
    pub(crate) fn define(&mut self, name: &Ident, e: &Ast, types: &mut TypeTable, errors: &mut Vec<Diagnostic>) {
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
    pub(crate) fn compile(&mut self, e: &Ast, types: &mut TypeTable, errors: &mut Vec<Diagnostic>) -> Option<Formula> {
        let mut out = Lowered::default();
        let before = errors.len();
        let lowered = self.lower(e, types, errors, &mut out);
        if errors.len() > before {
            return None;
        }
        let program = self.program(&lowered, errors)?;
        if program.uses_rng() {
            errors.push(
                Diagnostic::error(e.span, "random functions are not available in box-split formulas")
                    .with_hint("every random choice goes through weighted alternatives and materials"),
            );
            return None;
        }
        let mut observers =
            program.loads().filter(|&i| i as usize >= FIXED).map(|i| i - FIXED as u32).collect::<Vec<_>>();
        observers.sort_unstable();
        observers.dedup();
        let constant = program.constant();
        let mut divisors = Vec::with_capacity(out.divisions.len());
        for (span, b, guard_asts) in &out.divisions {
            let program = self.program(b, errors)?;
            let mut guards = Vec::with_capacity(guard_asts.len());
            for (g, want) in guard_asts {
                guards.push((self.program(g, errors)?, *want));
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

    /// The core program of a lowered formula; `None` after reporting the
    /// core's errors (their spans are already positions in the file).
    fn program(&self, ast: &Ast, errors: &mut Vec<Diagnostic>) -> Option<Program> {
        let scope = LowerScope { constants: &self.constants, slot_keys: &self.slot_keys, lets: &self.let_order };
        match expr::compile(ast, &scope) {
            Ok(p) => Some(p),
            Err(ds) => {
                for d in ds {
                    // An inlined `let` reports its mistakes once per use.
                    if !errors.iter().any(|x| x.span == d.span && x.message == d.message) {
                        errors.push(d);
                    }
                }
                None
            }
        }
    }

    /// `e` with the grammar's names resolved: observers become the host
    /// variables of their slots, scope-dependent `let`s are inlined (and
    /// evaluated in the scope of each use); divisions are listed in `out`.
    fn lower(&mut self, e: &Ast, types: &mut TypeTable, errors: &mut Vec<Diagnostic>, out: &mut Lowered) -> Ast {
        if let Some((obs, arg)) = observer_call(e) {
            let kind = match types.resolve(&arg) {
                Ok(t) => {
                    let key = format!("{}(t{t})", obs.name());
                    if !self.slot_keys.contains_key(&key) {
                        self.slot_keys.insert(key.clone(), self.slots.len() as u32);
                        self.slots.push((obs, t));
                    }
                    Node::Var(key)
                }
                Err(d) => {
                    errors.push(d);
                    Node::Num(0.0)
                }
            };
            return Ast { kind, span: e.span };
        }
        let kind = match &e.kind {
            Node::Var(n) => match self.lets.get(n) {
                Some(l) if l.constant.is_none() => {
                    let inner = l.expr.clone();
                    return self.lower(&inner, types, errors, out);
                }
                _ => e.kind.clone(),
            },
            Node::Call(name, name_span, args) => {
                // `if(c, a, b)` evaluates only one branch.
                let branches = name == "if" && args.len() == 3;
                let mut lowered: Vec<Ast> = Vec::with_capacity(args.len());
                for (i, a) in args.iter().enumerate() {
                    if branches && i > 0 {
                        out.guards.push((lowered[0].clone(), i == 1));
                    }
                    lowered.push(self.lower(a, types, errors, out));
                    if branches && i > 0 {
                        out.guards.pop();
                    }
                }
                if name == "mod" && lowered.len() == 2 {
                    out.divisions.push((e.span, lowered[1].clone(), out.guards.clone()));
                }
                Node::Call(name.clone(), *name_span, lowered)
            }
            Node::Unary(op, a) => Node::Unary(*op, Box::new(self.lower(a, types, errors, out))),
            Node::Binary(op, a, b) => {
                let a = self.lower(a, types, errors, out);
                // `&&` and `||` evaluate their right side only as needed.
                let guarded = matches!(op, BinOp::And | BinOp::Or);
                if guarded {
                    out.guards.push((a.clone(), *op == BinOp::And));
                }
                let b = self.lower(b, types, errors, out);
                if guarded {
                    out.guards.pop();
                }
                if matches!(op, BinOp::Div | BinOp::Rem) {
                    out.divisions.push((e.span, b.clone(), out.guards.clone()));
                }
                Node::Binary(*op, Box::new(a), Box::new(b))
            }
            Node::Cond(c, t, f) => {
                let c = self.lower(c, types, errors, out);
                out.guards.push((c.clone(), true));
                let t = self.lower(t, types, errors, out);
                out.guards.pop();
                out.guards.push((c.clone(), false));
                let f = self.lower(f, types, errors, out);
                out.guards.pop();
                Node::Cond(Box::new(c), Box::new(t), Box::new(f))
            }
            Node::Num(_) => e.kind.clone(),
        };
        Ast { kind, span: e.span }
    }
}

/// An observer call (`FULL(SOLID)`) and its block type as written: the
/// dialect reads the arguments of the observers as raw text.
fn observer_call(e: &Ast) -> Option<(Observer, Ident)> {
    let Node::Call(name, _, args) = &e.kind else { return None };
    let obs = Observer::from_name(name)?;
    match args.as_slice() {
        [Ast { kind: Node::Var(text), span }] => Some((obs, Ident { name: text.clone(), span: *span })),
        _ => None,
    }
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
