//! Direct evaluation of trivial expressions.
//!
//! Most operands in a grammar are constants, gene parameters, scope sizes,
//! or one arithmetic operation on those (`sz / 2`, `sz * move`). Running
//! such a program through the bytecode evaluator costs many times the
//! arithmetic itself, and expression is the inner loop of optimizers. The
//! compiler says which programs are trivial ([`Program::trivial`]); here
//! their loads are resolved to the interpreter's operands (scope size or
//! gene env), performing the same IEEE operations on the same values in the
//! same order as the evaluator, so results are bit-identical.

use crate::builtins::ENV_SX;
use genform_core::expr::{self, Arith, Program, Trivial};
use glam::DVec3;

/// A value an operation reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Operand {
    Const(f64),
    /// Component `axis` of the scope size (`sx`, `sy`, `sz`).
    Size(u8),
    /// An env slot of the running gene.
    Env(u32),
}

/// How the interpreter evaluates an expression.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Fast {
    /// The program only yields this value.
    Value(Operand),
    /// The program applies one operation to two values.
    Bin(Arith, Operand, Operand),
    /// Anything else: run the program.
    Run,
}

impl Operand {
    fn of(op: expr::Operand) -> Operand {
        match op {
            expr::Operand::Const(v) => Operand::Const(v),
            expr::Operand::Load(idx) => match (idx as usize).checked_sub(ENV_SX) {
                Some(axis) if axis < 3 => Operand::Size(axis as u8),
                _ => Operand::Env(idx),
            },
        }
    }

    /// See [`Fast::eval`].
    #[inline(always)]
    fn get(self, size: &DVec3, env: &[f64], base: usize) -> f64 {
        match self {
            Operand::Const(v) => v,
            Operand::Size(axis) => size.to_array()[axis as usize],
            // What the evaluator loads outside the gene's env.
            Operand::Env(i) => env.get(base + i as usize).copied().unwrap_or(f64::NAN),
        }
    }
}

impl Fast {
    /// The shortcut for `prog`, or [`Fast::Run`].
    pub fn of(prog: &Program) -> Fast {
        match prog.trivial() {
            Some(Trivial::Value(a)) => Fast::Value(Operand::of(a)),
            Some(Trivial::Bin(op, a, b)) => Fast::Bin(op, Operand::of(a), Operand::of(b)).strength_reduced(),
            None => Fast::Run,
        }
    }

    /// `x / c` as `x * (1 / c)` when `c` is a power of two: `1 / c` is then
    /// exact, and both round the same real number, so results are
    /// identical (NaN, infinities, zeros and subnormals included) while a
    /// multiplication is several times quicker than a division, which
    /// `sx / 2`-style placements put on the critical path.
    fn strength_reduced(self) -> Fast {
        match self {
            Fast::Bin(Arith::Div, a, Operand::Const(c)) if is_power_of_two(c) => {
                Fast::Bin(Arith::Mul, a, Operand::Const(1.0 / c))
            }
            fast => fast,
        }
    }

    /// The value of the expression in a scope of size `size` for the gene
    /// whose env is `env[base..]` (the last on the stack). Not for
    /// [`Fast::Run`] (which gives NaN).
    #[inline(always)]
    pub fn eval(&self, size: &DVec3, env: &[f64], base: usize) -> f64 {
        match *self {
            Fast::Value(a) => a.get(size, env, base),
            Fast::Bin(op, a, b) => op.apply(a.get(size, env, base), b.get(size, env, base)),
            Fast::Run => f64::NAN,
        }
    }
}

/// Whether `c` is ±2^k, a normal number whose reciprocal is exact.
fn is_power_of_two(c: f64) -> bool {
    const MANTISSA: u64 = (1 << 52) - 1;
    c.is_normal() && c.to_bits() & MANTISSA == 0 && (1.0 / c).is_normal()
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::expr::{Names, compile, parse};

    const NAMES: [&str; 8] = ["sx", "sy", "sz", "depth", "index", "count", "a", "b"];

    fn program(text: &str) -> Program {
        compile(&parse(text).unwrap(), &Names(&NAMES)).unwrap()
    }

    #[test]
    fn trivial_programs_get_shortcuts() {
        let cases = [
            ("2.5", Fast::Value(Operand::Const(2.5))),
            ("1 + 2", Fast::Value(Operand::Const(3.0))),
            ("sy", Fast::Value(Operand::Size(1))),
            ("a", Fast::Value(Operand::Env(6))),
            ("sz / 2", Fast::Bin(Arith::Mul, Operand::Size(2), Operand::Const(0.5))),
            ("sz / -0.25", Fast::Bin(Arith::Mul, Operand::Size(2), Operand::Const(-4.0))),
            // A subnormal divisor has no exact reciprocal: divide.
            ("sz / 1e-320", Fast::Bin(Arith::Div, Operand::Size(2), Operand::Const(1e-320))),
            ("sz * b", Fast::Bin(Arith::Mul, Operand::Size(2), Operand::Env(7))),
            ("b - a", Fast::Bin(Arith::Sub, Operand::Env(7), Operand::Env(6))),
            ("0.1 - a", Fast::Bin(Arith::Sub, Operand::Const(0.1), Operand::Env(6))),
            ("a + 1e-7", Fast::Bin(Arith::Add, Operand::Env(6), Operand::Const(1e-7))),
            ("3 / sx", Fast::Bin(Arith::Div, Operand::Const(3.0), Operand::Size(0))),
            ("a / 3", Fast::Bin(Arith::Div, Operand::Env(6), Operand::Const(3.0))),
            ("a - 0", Fast::Bin(Arith::Sub, Operand::Env(6), Operand::Const(0.0))),
            ("-a", Fast::Run),
            ("a * a * 2", Fast::Run),
            ("a < 2", Fast::Run),
            ("sin(a)", Fast::Run),
            ("a % 2", Fast::Run),
        ];
        for (text, want) in cases {
            assert_eq!(Fast::of(&program(text)), want, "{text}");
        }
    }

    #[test]
    fn shortcuts_agree_with_the_evaluator_bit_for_bit() {
        let texts = [
            "sz / 2",
            "sx * a",
            "a + b",
            "b - sy",
            "a / b",
            "2 - a",
            "a * 0.1",
            "1e300 * a",
            "a - 1e-300",
            "7 / a",
            "a",
            "sy",
            "a / 0.125",
            "a / 8",
            "a / 3",
            "a / 2e-300",
            "a / 1024",
            "sz / 1e-320",
            "a - 0",
        ];
        let values = [
            0.0,
            -0.0,
            1.0,
            -2.5,
            0.1,
            1e-310,
            -3e-320,
            f64::MIN_POSITIVE,
            1e308,
            f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            3.0,
        ];
        for text in texts {
            let prog = program(text);
            let fast = Fast::of(&prog);
            assert_ne!(fast, Fast::Run, "{text}");
            for &u in &values {
                for &v in &values {
                    let size = DVec3::new(u, v, -u);
                    let env = [u, v, -u, 0.0, 0.0, 1.0, v, u];
                    let (want, got) = (prog.eval(&env), fast.eval(&size, &env, 0));
                    assert!(want.to_bits() == got.to_bits() || (want.is_nan() && got.is_nan()), "{text} at {u}, {v}");
                }
            }
        }
    }
}
