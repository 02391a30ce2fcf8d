//! The turtle for the commonest drawing: lines, in a view without solids,
//! of a string without parameters that draws, moves, turns about U and
//! branches. Its state is the position, H and L, 72 bytes where [`State`]
//! has 128: width, colour, scale and U cannot change, so they stay out of
//! the loop, and the tag is looked up once per polyline instead of once per
//! segment. (The taper width [`State::drawn`] is read by solids only.)
//!
//! Every number is computed by the same operations, in the same order, as
//! in [`Turtle::apply`], so the drawing is bit-identical. At the first
//! module it has no command for, it hands its state and stack over to the
//! general turtle, which goes on from there.

use super::state::{State, Turtle};
use crate::alphabet::{Command, Sym};
use crate::settings::View;
use genform_core::scene::Polyline;
use glam::DVec3;

/// What a symbol does in the flat turtle.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Op {
    Nothing,
    Draw,
    Move,
    Left,
    Right,
    TurnAround,
    Push,
    Pop,
    /// A command for the general turtle: the flat one stops before it.
    Other,
}

impl Op {
    fn of(command: Command) -> Op {
        match command {
            Command::None | Command::Cut => Op::Nothing,
            Command::Draw => Op::Draw,
            Command::Move => Op::Move,
            Command::Left => Op::Left,
            Command::Right => Op::Right,
            Command::TurnAround => Op::TurnAround,
            Command::Push => Op::Push,
            Command::Pop => Op::Pop,
            _ => Op::Other,
        }
    }
}

/// The part of a [`State`] that the flat turtle's commands change.
#[derive(Clone, Copy)]
struct Flat {
    pos: DVec3,
    h: DVec3,
    l: DVec3,
}

impl Turtle<'_> {
    /// Whether the flat turtle may start here: nothing but lines are drawn
    /// (no solids, tropism or dry run) and nothing is pending
    /// (polygon, branch, cylinder, open polyline).
    fn flat_may_start(&self) -> bool {
        let st = &self.sys.settings;
        st.view != View::Solid
            && (st.tropism.is_none() || st.elasticity == 0.0)
            && !self.dry
            && self.polygons.is_empty()
            && self.stack.is_empty()
            && self.open_line.is_none()
            && self.state.cylinder().is_none()
    }

    /// Draws the first modules of `syms` as [`Turtle::apply`] would, up to
    /// the first one whose command the flat turtle lacks or the module that
    /// goes over the limit; returns how many it has carried out (0 when it
    /// may not start), having left the state, stack and open polyline as
    /// the general turtle would have.
    #[inline(never)]
    pub(super) fn draw_flat(&mut self, syms: &[Sym]) -> usize {
        if !self.flat_may_start() {
            return 0;
        }
        // A `~name` surface's symbol keeps the command `None`.
        let surface = &self.sys.surface_of;
        let ops: Vec<Op> = (self.commands.iter().zip(surface))
            .map(|(&c, s)| if s.is_some() { Op::Other } else { Op::of(c) })
            .collect();
        let s = self.state;
        let step = self.sys.settings.step;
        let len = step * s.scale;
        let w = (s.width * s.scale) as f32;
        let [(sin, cos), (nsin, ncos)] = self.turns;
        let (limit, mut segments, mut over) = (self.limit, self.segments, self.over);
        let mut stack: Vec<Flat> = Vec::new();
        let mut t = Flat { pos: s.pos, h: s.h, l: s.l };
        // Whether the scene's last polyline is this branch's, ending at `t.pos`.
        let mut open = false;
        let mut done = 0;
        for &sym in syms {
            match ops[sym as usize] {
                Op::Nothing => {}
                Op::Draw => {
                    let to = t.pos + t.h * len;
                    segments += 1;
                    over |= segments > limit;
                    if open {
                        let lines = &mut self.scene.polylines;
                        debug_assert_eq!(lines.points().last(), Some(&t.pos.as_vec3()));
                        lines.extend_last(to.as_vec3());
                    } else {
                        let tag = self.tag(s.color);
                        let points = [t.pos.as_vec3(), to.as_vec3()];
                        self.scene.polylines.push(Polyline { points: &points, width: w, tag });
                        open = true;
                        over |= self.primitives() > limit;
                    }
                    t.pos = to;
                }
                Op::Move => {
                    t.pos += t.h * step * s.scale;
                    open = false;
                }
                Op::Left => (t.h, t.l) = (t.h * cos + t.l * sin, t.l * cos - t.h * sin),
                Op::Right => (t.h, t.l) = (t.h * ncos + t.l * nsin, t.l * ncos - t.h * nsin),
                Op::TurnAround => (t.h, t.l) = (-t.h, -t.l),
                Op::Push => {
                    stack.push(t);
                    open = false;
                }
                Op::Pop => {
                    if let Some(prev) = stack.pop() {
                        t = prev;
                    }
                    open = false;
                }
                Op::Other => break,
            }
            done += 1;
            if over {
                break;
            }
        }
        let state = |f: Flat| State { pos: f.pos, h: f.h, l: f.l, ..s };
        self.stack.extend(stack.into_iter().map(state));
        self.state = state(t);
        if open {
            self.open_line = Some((self.tag(s.color), w));
        }
        (self.segments, self.over) = (segments, over);
        done
    }
}

#[cfg(test)]
mod tests {
    use crate::compile::compile_text;
    use genform_core::Rng;
    use genform_core::scene::Scene;
    use proptest::prelude::{ProptestConfig, prop_assert_eq, proptest};
    use proptest::sample::select;

    /// The axiom of `text`, with an unmatched `]` inserted at `stray` (the
    /// language allows none in a file, a string made otherwise may have
    /// one), drawn with and without the flat turtle: the results and
    /// scenes, as their exact `Debug` text.
    fn both(text: &str, stray: Option<usize>, limit: usize) -> [(String, String); 2] {
        let (s, _) = compile_text(text).expect("compiles");
        let mut m = s.axiom.clone();
        if let (Some(k), Some(close)) = (stray, s.alphabet.find("]", 0)) {
            m.syms.insert(k % (m.syms.len() + 1), close);
        }
        [true, false].map(|flat| {
            let mut scene = Scene::new();
            let end = s.interpret_with(&m, &mut Rng::from_seed(0), limit, &mut scene, flat);
            (format!("{end:?}"), format!("{scene:?}"))
        })
    }

    /// `text` with its unmatched `]` dropped and its open `[` closed,
    /// after an `X` (an axiom is never empty).
    fn balanced(text: &str) -> String {
        let mut depth = 0usize;
        let mut out: String = text
            .chars()
            .filter(|&c| match c {
                '[' => {
                    depth += 1;
                    true
                }
                ']' if depth == 0 => false,
                ']' => {
                    depth -= 1;
                    true
                }
                _ => true,
            })
            .collect();
        out.extend(std::iter::repeat_n(']', depth));
        format!("X {out}")
    }

    #[test]
    fn a_plant_is_drawn_by_the_flat_turtle_alone() {
        let (s, _) = compile_text("angle: 25.7\naxiom: X\nproduction:\nX -> F[+X][-X]FX\nF -> FF\n").unwrap();
        let m = s.derive_limited(4, &mut Rng::from_seed(0), usize::MAX, |_, _| {}).unwrap();
        let mut scene = Scene::new();
        let mut t = super::Turtle::new(&s, &mut scene, usize::MAX, false);
        assert_eq!(t.draw_flat(&m.syms), m.syms.len());
        // A colour change is the general turtle's: the flat one stops there.
        let (s, _) = compile_text("axiom: F+F'F\n").unwrap();
        let mut scene = Scene::new();
        let mut t = super::Turtle::new(&s, &mut scene, usize::MAX, false);
        assert_eq!(t.draw_flat(&s.axiom.syms), 3);
    }

    /// The flat turtle's commands.
    const FLAT: &[&str] = &["F", "f", "G", "+", "-", "|", "[", "]", "X", "%"];
    /// The general turtle's.
    const OTHERS: &[&str] = &["!", "'", "&", "^", "/", "\\", "$", "{", "}", ".", "@O", "@Gc", "@Ge", "~l"];

    proptest! {
        #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

        /// Strings mixing the flat turtle's commands with others (width,
        /// colour, pitch, roll, polygons, spheres, surfaces, cylinders),
        /// in both views, any heading, any angle, with and without
        /// tropism, under tight and loose limits: the same scene, bit for
        /// bit, and the same result as the general turtle's.
        #[test]
        fn the_flat_turtle_draws_what_the_general_one_does(
            axiom in proptest::collection::vec(
                proptest::prop_oneof![24 => select(FLAT), 1 => select(OTHERS)], 1..80),
            view in 0usize..2,
            heading in 0usize..6,
            angle in -400.0f64..400.0,
            width in 0.0f64..2.0,
            tropism in 0usize..2,
            limit in 1usize..40,
            stray in proptest::option::of(0usize..64),
        ) {
            let text = format!(
                "view: {}\nheading: {}\nangle: {angle}\nwidth: {width}\n{}axiom: {}\n",
                ["2d", "3d"][view],
                ["+x", "-x", "+y", "-y", "+z", "-z"][heading],
                ["", "tropism: 0, -1, 0\nelasticity: 0.3\n"][tropism],
                balanced(&axiom.join(" ")),
            );
            for limit in [limit, usize::MAX] {
                let [flat, general] = both(&text, stray, limit);
                prop_assert_eq!(flat, general);
            }
        }
    }
}
