//! The compiled formulas that rules and production bodies share: a
//! produced module's parameter, and what counts as a true condition. Kept
//! apart from both so a body's `produce` and a rule's successor use one
//! definition without the two files naming each other.

use genform_core::Draws;
use genform_core::expr::{Arith, Operand, Program, Trivial};

/// A compiled successor parameter. Most are a constant, a parameter, or one
/// operation on two of those (`x*p`, `t-1`); those skip the bytecode
/// interpreter and perform the same IEEE operation, so results are
/// bit-identical to [`Program::eval`].
#[derive(Clone, Debug)]
pub(crate) enum Arg {
    Value(Operand),
    Bin(Arith, Operand, Operand),
    Run(Program),
}

impl Arg {
    pub(crate) fn of(prog: Program) -> Arg {
        match prog.trivial() {
            Some(Trivial::Value(a)) => Arg::Value(a),
            Some(Trivial::Bin(op, a, b)) => Arg::Bin(op, a, b),
            None => Arg::Run(prog),
        }
    }

    #[inline(always)]
    pub(crate) fn eval(&self, env: &[f64], draws: &mut impl Draws) -> f64 {
        match self {
            Arg::Value(a) => a.value(env),
            Arg::Bin(op, a, b) => op.apply(a.value(env), b.value(env)),
            Arg::Run(p) => p.eval_draws(env, draws),
        }
    }
}

/// True as the expression language defines it: non-zero and not NaN.
#[inline]
pub(crate) fn is_true(v: f64) -> bool {
    v != 0.0 && !v.is_nan()
}
