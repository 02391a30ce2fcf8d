//! cpfg/L-Py query modules `?P ?H ?U ?L`: after each derivation step the
//! turtle reads the string (interpretation rules included, nothing drawn)
//! and each query module's parameters receive the turtle's position,
//! heading, up or left vector where the module stands, so the next step's
//! productions can react to where a module is (ABOP-style environmental
//! sensitivity, e.g. pruning against a shape).

use super::state::Turtle;
use crate::compile::LSystem;
use crate::derive::{Scratch, Site};
use crate::string::ModuleString;
use genform_core::{Rng, Scene};
use glam::DVec3;

/// What a query module receives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Query {
    /// `?P`: the position.
    Position,
    /// `?H`: the heading.
    Heading,
    /// `?U`: the up vector.
    Up,
    /// `?L`: the left vector.
    Left,
}

impl Query {
    /// The query of a module name, if it is one genform fills.
    pub(crate) fn of(name: &str) -> Option<Query> {
        Some(match name {
            "?P" => Query::Position,
            "?H" => Query::Heading,
            "?U" => Query::Up,
            "?L" => Query::Left,
            _ => return None,
        })
    }
}

impl LSystem {
    /// Per symbol: the query it is, if any (`None` overall when the
    /// alphabet has no query module with parameters).
    pub(crate) fn queries(&self) -> Option<Vec<Option<Query>>> {
        let q: Vec<Option<Query>> =
            self.alphabet.symbols.iter().map(|s| Query::of(&s.name).filter(|_| s.arity > 0)).collect();
        q.iter().any(Option::is_some).then_some(q)
    }

    /// Fills the parameters of every query module of `s` (the first three:
    /// x, y, z) with the turtle state where it stands. Interpretation rules
    /// apply as when drawing, their random draws from a stream seeded with
    /// `seed`; rules read the global `state`.
    pub(crate) fn fill_queries(&self, s: &mut ModuleString, kinds: &[Option<Query>], state: &[f64], seed: u64) {
        let mut scene = Scene::new();
        let mut t = Turtle::new(self, &mut scene, usize::MAX, true);
        let mut sc = Scratch::with_state(state);
        let mut rng = Rng::from_seed(seed);
        // Interpretation rules with a context or several predecessor modules
        // see the string as it was before the queries were filled.
        let before = if self.interpretation.context { s.clone() } else { ModuleString::default() };
        let (mut partners, mut offsets) = (Vec::new(), Vec::new());
        if self.interpretation.context {
            self.view_parts(&before.syms, &mut partners, &mut offsets);
        }
        let view = self.view(&before.syms, &partners);
        let mut off = 0;
        let mut skip = 0;
        for i in 0..s.syms.len() {
            let sym = s.syms[i];
            let n = self.alphabet.arity(sym);
            if let Some(q) = kinds[sym as usize] {
                let st = &t.state;
                let v: DVec3 = match q {
                    Query::Position => st.pos,
                    Query::Heading => st.h,
                    Query::Up => st.u,
                    Query::Left => st.l,
                };
                let v = if self.settings.lpy { crate::axes::to_lpy_axes(v) } else { v };
                for (k, p) in s.params[off..off + n.min(3)].iter_mut().enumerate() {
                    *p = v[k];
                }
            }
            let params = &s.params[off..off + n];
            let mut st = t.state;
            if skip > 0 {
                skip -= 1;
            } else if self.interpretation.is_empty() {
                t.apply(&mut st, sym, params);
            } else if self.interpretation.context {
                let site = Site { sym, params, ctx: Some((i, &view, &offsets[..], &before.params[..])) };
                skip = self
                    .expand_site(&self.interpretation, &site, &mut rng, &mut sc, &mut |s, p| {
                        t.apply(&mut st, s, p);
                        true
                    })
                    .0;
            } else {
                self.expand(&self.interpretation, (sym, params), 0, &mut rng, &mut sc, &mut |s, p| {
                    t.apply(&mut st, s, p);
                    true
                });
            }
            t.state = st;
            off += n;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::compile::compile_text;
    use genform_core::Rng;

    /// The parameters of every module, in order, after `n` steps.
    fn derive(text: &str, n: u32) -> Vec<(String, Vec<f64>)> {
        let (s, w) = compile_text(text).unwrap();
        assert!(w.is_empty(), "{w:?}");
        let m = s.derive(n, &mut Rng::from_seed(0)).unwrap();
        m.modules(&s.alphabet).map(|(sym, p)| (s.alphabet.symbols[sym as usize].name.clone(), p.to_vec())).collect()
    }

    fn query(out: &[(String, Vec<f64>)], k: usize) -> [f64; 3] {
        let q: Vec<&Vec<f64>> = out.iter().filter(|(n, _)| n.starts_with('?')).map(|(_, p)| p).collect();
        let p = q[k];
        // Rounded: the turns leave 1e-16 residues.
        [p[0], p[1], p[2]].map(|v| (v * 1e9).round() / 1e9 + 0.0)
    }

    #[test]
    fn a_planar_path_by_hand() {
        // Heading +y, U = +z, so L = U × H = −x and `+` (90°) turns H to −x.
        // F(2) → (0,2,0); + F(3) → (−3,2,0); the branch − F(1) → (−3,3,0);
        // after `]` the turtle is back at (−3,2,0) heading −x, L = −y.
        let text =
            "axiom: F(2) ?P(9,9,9) + F(3) ?P(9,9,9) ?H(9,9,9) [ - F(1) ?P(9,9,9) ] ?P(9,9,9) ?L(9,9,9) ?U(9,9,9)\n";
        let out = derive(text, 0);
        assert_eq!(query(&out, 0), [0.0, 2.0, 0.0]);
        assert_eq!(query(&out, 1), [-3.0, 2.0, 0.0]);
        assert_eq!(query(&out, 2), [-1.0, 0.0, 0.0]);
        assert_eq!(query(&out, 3), [-3.0, 3.0, 0.0]);
        assert_eq!(query(&out, 4), [-3.0, 2.0, 0.0]);
        assert_eq!(query(&out, 5), [0.0, -1.0, 0.0]);
        assert_eq!(query(&out, 6), [0.0, 0.0, 1.0]);
    }

    #[test]
    fn a_pitched_path_and_interpretation_rules_by_hand() {
        // `&` pitches H towards −U: from H = +y, U = +z, `&(90)` gives
        // H = −z, U = +y. `S` is drawn as F(2) by an interpretation rule, so
        // the query after it sees the moved turtle: (0, 1, 0) + 2·(0, 0, −1).
        let text = "axiom: F &(90) ?H(0,0,0) ?U(0,0,0) S ?P(0,0,0)\ninterpretation:\nS -> F(2)\n";
        let out = derive(text, 0);
        assert_eq!(query(&out, 0), [0.0, 0.0, -1.0]);
        assert_eq!(query(&out, 1), [0.0, 1.0, 0.0]);
        assert_eq!(query(&out, 2), [0.0, 1.0, -2.0]);
    }

    #[test]
    fn productions_see_the_position_of_the_previous_step() {
        // An apex grows one unit per step and stops once its query says it
        // is above y = 2.5: after steps 1, 2, 3 it stands at y = 1, 2, 3.
        let text = "axiom: A ?P(0,0,0)\nproduction:\nA > ?P(x, y, z) : y > 2.5 -> K\nA -> F A\n";
        let out = derive(text, 6);
        let names: String = out.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, "FFFK?P");
        assert_eq!(query(&out, 0), [0.0, 3.0, 0.0]);
        // Fewer than three parameters take the first components.
        let out = derive("axiom: F ?P(0, 0)\n", 0);
        assert_eq!(out[1].1, [0.0, 1.0]);
    }
}
