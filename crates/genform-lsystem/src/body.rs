//! The statement language of production bodies (`A(x) -> { … }`) and of
//! the Start/StartEach/EndEach/End hooks: assignments, `if`/`else`, and, in
//! bodies, `produce`/`nproduce`. Formulas are the ordinary compiled
//! [`Program`]s; a statement list runs over one mutable environment.

use crate::alphabet::{Alphabet, Sym};
use crate::arg::{Arg, is_true};
use crate::string::ModuleString;
use genform_core::Draws;
use genform_core::diag::Span;
use genform_core::expr::Program;

/// One compiled statement.
#[derive(Clone, Debug)]
pub(crate) enum Op {
    /// Stores the formula's value in an environment slot; the span is the
    /// assigned name's.
    Assign(u32, Program, Span),
    /// Runs the first list when the condition holds, else the second.
    If(Program, Vec<Op>, Vec<Op>),
    /// Appends modules; `end` (`produce`) finishes the body.
    Produce { syms: Vec<Sym>, args: Vec<Arg>, end: bool },
}

/// A production's body: its statements and how many local variables they
/// use (slots after the formal parameters and the global state).
#[derive(Clone, Debug)]
pub(crate) struct Body {
    pub ops: Vec<Op>,
    pub locals: usize,
}

/// The first non-finite values statements computed.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Faults {
    /// A produced module's parameter.
    pub param: Option<f64>,
    /// An assignment's slot, where the assigned name is, and the value.
    pub assign: Option<(u32, Span, f64)>,
}

/// What running statements produced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Outcome {
    /// Some `produce` or `nproduce` ran (the production applies).
    pub produced: bool,
    /// A `produce` ran (the body is finished).
    pub ended: bool,
}

/// Runs `ops` over `env`, appending produced modules to `out`. The first
/// non-finite module parameter and assigned value are kept in `bad` (the
/// run goes on).
pub(crate) fn run(
    ops: &[Op],
    env: &mut [f64],
    alphabet: &Alphabet,
    out: &mut ModuleString,
    draws: &mut impl Draws,
    bad: &mut Faults,
) -> Outcome {
    let mut outcome = Outcome::default();
    for op in ops {
        match op {
            Op::Assign(slot, p, span) => {
                let v = p.eval_draws(env, draws);
                if !v.is_finite() {
                    bad.assign.get_or_insert((*slot, *span, v));
                }
                if let Some(cell) = env.get_mut(*slot as usize) {
                    *cell = v;
                }
            }
            Op::If(c, then, els) => {
                let branch = if is_true(c.eval_draws(env, draws)) { then } else { els };
                let inner = run(branch, env, alphabet, out, draws, bad);
                outcome.produced |= inner.produced;
                if inner.ended {
                    outcome.ended = true;
                    return outcome;
                }
            }
            Op::Produce { syms, args, end } => {
                let mut a = 0;
                for &s in syms {
                    out.syms.push(s);
                    for _ in 0..alphabet.arity(s) {
                        let v = args[a].eval(env, draws);
                        if !v.is_finite() {
                            bad.param.get_or_insert(v);
                        }
                        out.params.push(v);
                        a += 1;
                    }
                }
                outcome.produced = true;
                if *end {
                    outcome.ended = true;
                    return outcome;
                }
            }
        }
    }
    outcome
}

/// Every module a statement list can produce.
pub(crate) fn produced_syms(ops: &[Op], out: &mut Vec<Sym>) {
    for op in ops {
        match op {
            Op::Assign(..) => {}
            Op::If(_, a, b) => {
                produced_syms(a, out);
                produced_syms(b, out);
            }
            Op::Produce { syms, .. } => out.extend_from_slice(syms),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::compile::{LSystem, compile_text};
    use crate::derive::DeriveError;
    use crate::string::ModuleString;
    use genform_core::Rng;

    fn system(text: &str) -> LSystem {
        match compile_text(text) {
            Ok((s, w)) => {
                assert!(w.is_empty(), "{w:?}");
                s
            }
            Err(e) => panic!("{e:?}"),
        }
    }

    fn derive(text: &str, n: u32) -> (LSystem, ModuleString) {
        let s = system(text);
        let m = s.derive(n, &mut Rng::from_seed(1)).unwrap();
        (s, m)
    }

    fn errors(text: &str) -> Vec<String> {
        match compile_text(text) {
            Ok(_) => Vec::new(),
            Err(e) => e.into_iter().map(|d| d.message).collect(),
        }
    }

    #[test]
    fn end_each_counts_steps_and_productions_read_the_count() {
        // A counter that EndEach doubles: 1, 2, 4, 8 after steps 1..3 (the
        // production at step k sees 2^(k-1)).
        let text = "global c = 1\naxiom: A\nproduction:\nA -> B(c) A\nEndEach:\nc = c * 2\n";
        let (s, m) = derive(text, 3);
        assert_eq!(m.display(&s.alphabet, true), "B(1)B(2)B(4)A");
        assert_eq!(m.state, [3.0, 8.0], "iteration = steps done, then c");
    }

    #[test]
    fn hooks_run_in_order_and_iteration_is_l_pys_iteration_number() {
        // Start sets, StartEach records the iteration, End doubles.
        let text = "global a = 5\nglobal last = -1\naxiom: X\nproduction:\nX -> X I(iteration, last)\n\
                    Start:\na = 0\nStartEach:\nlast = iteration\nEnd:\na = a + 100 + iteration\n";
        let (s, m) = derive(text, 3);
        assert_eq!(m.display(&s.alphabet, true), "XI(2,2)I(1,1)I(0,0)");
        assert_eq!(m.state, [3.0, 103.0, 2.0]);
    }

    #[test]
    fn if_else_in_hooks_and_random_draws_are_seeded() {
        let text = "global n = 0\nglobal odd = 0\naxiom: X\nEndEach:\nn = n + 1\nif n % 2 == 1: odd = odd + 1\n\
                    else: odd = odd - 10\n";
        let (_, m) = derive(text, 5);
        assert_eq!(m.state, [5.0, 5.0, 3.0 - 20.0]);
        let text = "global r = 0\naxiom: X\nStart:\nr = uniform(0, 1)\n";
        let s = system(text);
        let a = s.derive(1, &mut Rng::from_seed(3)).unwrap();
        let b = s.derive(1, &mut Rng::from_seed(3)).unwrap();
        assert_eq!(a.state, b.state);
        assert!(a.state[1] > 0.0 && a.state[1] < 1.0);
    }

    #[test]
    fn interpretation_rules_read_the_final_globals() {
        let text = "global len = 1\naxiom: A\nproduction:\nA -> A\nEnd:\nlen = 3\ninterpretation:\nA -> F(len)\n";
        let (s, m) = derive(text, 2);
        let mut scene = genform_core::Scene::new();
        let end = s.interpret(&m, &mut Rng::from_seed(0), 100, &mut scene).unwrap();
        assert!((end.position.y - 3.0).abs() < 1e-12);
        // A string that was not derived sees the declared value.
        let end = s.interpret(&s.axiom, &mut Rng::from_seed(0), 100, &mut scene).unwrap();
        assert!((end.position.y - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_body_produces_the_first_branch_that_holds() {
        // ABOP-style counter written as one production with branches.
        let text = "axiom: A(0)\nproduction:\nA(x) -> {\n  y = x + 1\n  if y > 3: produce B(y)\n  \
                    elif y > 2: produce C(y)\n  else: produce A(y)\n}\n";
        for (n, want) in [(1, "A(1)"), (2, "A(2)"), (3, "C(3)"), (4, "C(3)")] {
            let (s, m) = derive(text, n);
            assert_eq!(m.display(&s.alphabet, true), want, "step {n}");
        }
    }

    #[test]
    fn nproduce_accumulates_and_a_body_without_produce_does_not_apply() {
        let text = "axiom: A(3) A(0)\nproduction:\nA(x) : x > 0 -> {\n  nproduce F(x)\n  x = x - 1\n  \
                    nproduce [+F(x)]\n  if x > 1: produce A(x)\n}\nA(x) -> {\n  if x > 100: produce Z\n}\n\
                    A(x) -> B\n";
        let (s, m) = derive(text, 1);
        // A(3): F(3) [+F(2)] A(2); A(0): first body produces nothing, so
        // the next production applies.
        assert_eq!(m.display(&s.alphabet, true), "F(3)[+F(2)]A(2)B");
        let (s, m) = derive(text, 2);
        assert_eq!(m.display(&s.alphabet, true), "F(3)[+F(2)]F(2)[+F(1)]B");
    }

    #[test]
    fn bodies_report_non_finite_parameters_with_the_rule() {
        let text = "axiom: A(0)\nproduction:\nA(x) -> {\n  produce B(1 / x)\n}\n";
        let s = system(text);
        let e = s.derive(1, &mut Rng::from_seed(0)).unwrap_err();
        assert!(matches!(e, DeriveError::NonFinite { step: 1, .. }), "{e}");
        let text = "global g = 1\naxiom: A\nEndEach:\ng = g / 0\n";
        let e = system(text).derive(2, &mut Rng::from_seed(0)).unwrap_err();
        assert!(
            matches!(&e, DeriveError::NonFiniteGlobal { step: 1, hook: "EndEach", name, .. } if name == "g"),
            "{e}"
        );
    }

    #[test]
    fn statement_errors_name_the_problem() {
        let cases = [
            ("global iteration = 1\naxiom: A\n", "derivation step"),
            ("global g = 1\nglobal g = 2\naxiom: A\n", "declared twice"),
            ("global g = 1\naxiom: A\nEndEach:\nh = 2\n", "unknown global `h`"),
            ("global g = 1\naxiom: A\nEndEach:\niteration = 2\n", "cannot be assigned"),
            ("global g = 1\naxiom: A\nproduction:\nA -> {\n  g = 2\n  produce B\n}\n", "cannot change in a production"),
            ("axiom: A\nproduction:\nA -(1)-> {\n  produce B\n}\n", "cannot have a weight"),
            ("axiom: A\nproduction:\nA -> {\n  produce B [\n}\n", "never closes"),
            ("axiom: A\nproduction:\nA -> {\n  produce B\n", "never closed"),
            ("axiom: A\nEndEach:\nproduce B\n", "belongs in a production body"),
            ("axiom: A\nproduction:\nA -> {\n  else: produce B\n}\n", "follows no `if`"),
            ("axiom: A\nproduction:\nA -> {\n  if 1 produce B\n}\n", "expected `:`"),
            ("axiom: A\nproduction:\nA -> {\n  B C\n}\n", "expected a statement"),
        ];
        for (text, want) in cases {
            let e = errors(text);
            assert!(e.iter().any(|m| m.contains(want)), "{text:?}: {e:?}");
        }
    }
}
