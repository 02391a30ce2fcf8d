//! The turtle: modules to geometry in a [`Scene`] (ABOP §1.5 and p. 19).
//!
//! State: position and a right-handed frame H (heading), L (left), U (up),
//! width, colour index. `+`/`-` turn about U (`+` towards L:
//! counter-clockwise seen from U), `&`/`^` pitch about L (`&` down, towards
//! −U), `\`/`/` roll about H (`/` right: L towards U), `|` turns around,
//! `$` rolls L horizontal (perpendicular to +y). Polygons: `{` starts one
//! at the current position, every move inside it (and `.`) adds a vertex,
//! `}` closes it. Generalized cylinders: in the solid view, `@Gc` starts
//! one at the current position, every `F` on the same branch adds a ring
//! instead of drawing a frustum, and `@Ge` (or the end of the branch, or of
//! the string) closes it into one mesh (see [`cylinder`]). Modules without
//! a drawing meaning are ignored.

mod cylinder;
mod flat;
pub(crate) mod query;
mod state;

use crate::alphabet::{Command, Sym};
use crate::compile::LSystem;
use crate::derive::{Scratch, Site};
use crate::settings::{Settings, View};
use crate::string::ModuleString;
use cylinder::Cylinder;
use genform_core::Rng;
use genform_core::scene::{Instance, Polygon, Polyline, Primitive, Scene};
use glam::{Affine3A, DMat3, DVec3, Vec3};
use state::{MAX_COLOR, NO_CYLINDER, NOT_DRAWN, State, Turtle, tropism};
use std::sync::Arc;

/// Why a drawing stopped.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TurtleError {
    /// The drawing has more primitives than allowed.
    #[error(
        "the drawing has more than {limit} primitives (segments, polygons); raise it with --max-primitives or derive fewer steps"
    )]
    TooManyPrimitives {
        /// The limit.
        limit: usize,
    },
}

/// What the turtle ended with (for tests and summaries).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurtleEnd {
    /// Final position.
    pub position: DVec3,
    /// Drawn segments (`F`).
    pub segments: usize,
}

impl LSystem {
    /// Draws `s` into `scene`, after applying the interpretation rules
    /// (their random draws come from `rng`). At most `max_primitives`
    /// polylines, instances and polygons.
    pub fn interpret(
        &self,
        s: &ModuleString,
        rng: &mut Rng,
        max_primitives: usize,
        scene: &mut Scene,
    ) -> Result<TurtleEnd, TurtleError> {
        self.interpret_with(s, rng, max_primitives, scene, true)
    }

    /// [`LSystem::interpret`], with or without the flat turtle (see
    /// [`flat`]; tests compare the two).
    fn interpret_with(
        &self,
        s: &ModuleString,
        rng: &mut Rng,
        max_primitives: usize,
        scene: &mut Scene,
        flat: bool,
    ) -> Result<TurtleEnd, TurtleError> {
        // PlantGL's turtle skips the rest of a branch after `%` (a cut that
        // L-Py's last step wrote and no step read; `.ls` steps leave none).
        let cut;
        let s = if self.settings.lpy
            && self.alphabet.symbols.iter().any(|x| x.command == Command::Cut)
            && s.syms.iter().any(|&x| self.alphabet.command(x) == Command::Cut)
        {
            let mut c = s.clone();
            self.cut(&mut c);
            cut = c;
            &cut
        } else {
            s
        };
        let mut t = Turtle::new(self, scene, max_primitives, false);
        // Interpretation rules read the global state the derivation ended
        // with, or the declared one for a string not derived.
        let state = if s.state.len() == self.initial_state.len() { &s.state } else { &self.initial_state };
        let mut sc = Scratch::with_state(state);
        if self.interpretation.is_empty() && s.params.is_empty() {
            t.draw_plain(&s.syms, flat);
            if t.over {
                return Err(TurtleError::TooManyPrimitives { limit: max_primitives });
            }
        } else if self.interpretation.context {
            // Interpretation rules with a context or several predecessor
            // modules see the derived string around each module.
            let (mut partners, mut offsets) = (Vec::new(), Vec::new());
            self.view_parts(&s.syms, &mut partners, &mut offsets);
            let view = self.view(&s.syms, &partners);
            let mut st = t.state;
            let (mut off, mut skip) = (0, 0);
            for (i, &sym) in s.syms.iter().enumerate() {
                let n = self.alphabet.arity(sym);
                let params = &s.params[off..off + n];
                off += n;
                if skip > 0 {
                    skip -= 1;
                    continue;
                }
                let site = Site { sym, params, ctx: Some((i, &view, &offsets[..], &s.params[..])) };
                skip = self
                    .expand_site(&self.interpretation, &site, rng, &mut sc, &mut |s, p| {
                        t.apply(&mut st, s, p);
                        !t.over
                    })
                    .0;
                if t.over {
                    return Err(TurtleError::TooManyPrimitives { limit: max_primitives });
                }
            }
            t.state = st;
        } else {
            let mut st = t.state;
            for (sym, params) in s.modules(&self.alphabet) {
                if self.interpretation.is_empty() {
                    t.apply(&mut st, sym, params);
                } else {
                    self.expand(&self.interpretation, (sym, params), 0, rng, &mut sc, &mut |s, p| {
                        t.apply(&mut st, s, p);
                        !t.over
                    });
                }
                if t.over {
                    return Err(TurtleError::TooManyPrimitives { limit: max_primitives });
                }
            }
            t.state = st;
        }
        // Cylinders still open (no `@Ge`, or an unclosed `[`) end with the string.
        for k in 0..t.cylinders.len() {
            t.finish_cylinder(k);
        }
        if t.over {
            return Err(TurtleError::TooManyPrimitives { limit: max_primitives });
        }
        Ok(TurtleEnd { position: t.state.pos, segments: t.segments })
    }
}

/// A colour index from a parameter: negative or non-finite values give 0.
fn color_index(c: f64) -> u32 {
    if c.is_finite() && c >= 0.0 { (c as u64).min(u64::from(MAX_COLOR)) as u32 } else { 0 }
}

/// Carries out `command` on `s` if it only changes the state (turns,
/// width, colour, heading, scale); `false` for the others.
#[inline(always)]
fn change_state(s: &mut State, command: Command, params: &[f64], st: &Settings, turns: &[(f64, f64); 2]) -> bool {
    let arg = params.first().copied();
    match command {
        Command::Left => (s.h, s.l) = rotate(s.h, s.l, arg, 1.0, turns),
        Command::Right => (s.h, s.l) = rotate(s.h, s.l, arg, -1.0, turns),
        // Pitching down turns H towards −U.
        Command::Down => (s.h, s.u) = rotate(s.h, s.u, arg, -1.0, turns),
        Command::Up => (s.h, s.u) = rotate(s.h, s.u, arg, 1.0, turns),
        Command::RollRight => (s.l, s.u) = rotate(s.l, s.u, arg, 1.0, turns),
        Command::RollLeft => (s.l, s.u) = rotate(s.l, s.u, arg, -1.0, turns),
        Command::TurnAround => {
            s.h = -s.h;
            s.l = -s.l;
        }
        Command::RollHorizontal => {
            let l = DVec3::Y.cross(s.h);
            if l.length_squared() > 1e-12 {
                s.l = l.normalize();
                s.u = s.h.cross(s.l);
            }
        }
        Command::Width | Command::WidthUp => {
            let up = command == Command::WidthUp;
            s.width = match arg {
                Some(w) => (w * st.width_unit).max(0.0),
                None if up && st.width_factor > 0.0 => s.width / st.width_factor,
                None if up => s.width,
                None => s.width * st.width_factor,
            };
        }
        Command::Color | Command::ColorDown => {
            let down = command == Command::ColorDown;
            s.color = match arg {
                Some(c) => color_index(c),
                None if down => s.color.saturating_sub(1),
                None => (s.color + 1).min(MAX_COLOR),
            };
        }
        Command::SetHead => {
            // L-Py's defaults: H = +z, U = +x.
            let p = |i: usize, d: f64| params.get(i).copied().unwrap_or(d);
            let h = DVec3::new(p(0, 0.0), p(1, 0.0), p(2, 1.0));
            let u = DVec3::new(p(3, 1.0), p(4, 0.0), p(5, 0.0));
            // U is made perpendicular to H; a degenerate pair leaves
            // the frame as it was.
            let h = h.normalize_or_zero();
            let u = (u - h * u.dot(h)).normalize_or_zero();
            if h != DVec3::ZERO && u != DVec3::ZERO && h.is_finite() && u.is_finite() {
                s.h = h;
                s.u = u;
                s.l = u.cross(h);
            }
        }
        Command::SetScale | Command::MultScale | Command::DivScale => {
            let f = arg.unwrap_or(1.0);
            let next = match command {
                Command::SetScale => f,
                Command::MultScale => s.scale * f,
                _ => s.scale / f,
            };
            if next.is_finite() && next > 0.0 {
                s.scale = next;
            }
        }
        _ => return false,
    }
    true
}

/// `a` turned towards `b` by `sign` × the parameter in degrees (the file's
/// angle, whose sines and cosines are `turns`, without one), and `b`
/// turned along.
fn rotate(a: DVec3, b: DVec3, arg: Option<f64>, sign: f64, turns: &[(f64, f64); 2]) -> (DVec3, DVec3) {
    let (s, c) = match arg {
        Some(deg) => (sign * deg).to_radians().sin_cos(),
        None => turns[usize::from(sign < 0.0)],
    };
    (a * c + b * s, b * c - a * s)
}

impl Turtle<'_> {
    /// Draws a string without parameters (most plants), stopping when
    /// over the limit: the flat turtle (when `flat`) as far as it can, the
    /// rest here. The state lives in a local that nothing outside this
    /// loop sees, so that it stays in registers (see [`Turtle::apply`]).
    #[inline(never)]
    fn draw_plain(&mut self, syms: &[Sym], flat: bool) {
        let done = if flat { self.draw_flat(syms) } else { 0 };
        if self.over {
            return;
        }
        let mut st = self.state;
        for &sym in &syms[done..] {
            self.apply(&mut st, sym, &[]);
            if self.over {
                break;
            }
        }
        self.state = st;
    }

    /// Carries out module `sym` on the state `s` (the caller's copy of
    /// `self.state`), inlined into the reading loop: drawing, moving,
    /// branching, polygons and every command that only changes the state.
    /// The caller keeps `s` in a local: in `self`, whose address escapes
    /// into the out-of-line calls, every position and heading went through
    /// memory between modules. The other commands go to
    /// [`Turtle::apply_any`] with the state written back.
    #[inline(always)]
    fn apply(&mut self, s: &mut State, sym: Sym, params: &[f64]) {
        let command = self.commands[sym as usize];
        match command {
            Command::Draw => self.draw(s, params.first().copied()),
            Command::Move => {
                s.pos += s.h * params.first().copied().unwrap_or(self.sys.settings.step) * s.scale;
                self.open_line = None;
                self.vertex(s.pos);
                // A cylinder does not bridge a jump: the part before it is
                // closed and a new one starts here.
                if s.cylinder().is_some() {
                    self.state = *s;
                    self.start_cylinder();
                    *s = self.state;
                }
            }
            Command::Push => self.push(s),
            Command::Pop => self.pop(s),
            Command::PolygonStart => {
                self.polygons.push(Vec::new());
                self.vertex(s.pos);
            }
            Command::PolygonVertex => self.vertex(s.pos),
            Command::PolygonEnd => self.end_polygon(s.color),
            // A plant's non-turtle symbols (`X`); a `~name` surface keeps
            // the command `None` too.
            Command::None if self.sys.surface_of[sym as usize].is_none() => {}
            _ => {
                if !change_state(s, command, params, &self.sys.settings, &self.turns) {
                    self.state = *s;
                    self.apply_any(sym, params);
                    *s = self.state;
                }
            }
        }
    }

    /// Carries out module `sym` on `self.state`: cylinders, spheres,
    /// surfaces and cuts, the commands [`Turtle::apply`] sends here.
    #[inline(never)]
    fn apply_any(&mut self, sym: Sym, params: &[f64]) {
        let arg = params.first().copied();
        let s = &mut self.state;
        match self.commands[sym as usize] {
            Command::CylinderStart => self.start_cylinder(),
            Command::CylinderEnd => {
                if let Some(k) = s.take_cylinder() {
                    self.finish_cylinder(k);
                }
            }
            Command::Sphere => {
                let r = arg.unwrap_or(s.width * 0.5) * s.scale;
                if r > 0.0 && r.is_finite() && !self.dry {
                    let transform = Affine3A::from_scale_rotation_translation(
                        Vec3::splat(2.0 * r as f32),
                        glam::Quat::IDENTITY,
                        s.pos.as_vec3(),
                    );
                    let tag = self.tag(self.state.color);
                    self.scene.instances.push(Instance { transform, primitive: Primitive::Sphere, tag });
                    self.over |= self.primitives() > self.limit;
                }
            }
            // `~name` surfaces keep the command `None` (the public enum
            // stays as it is) and are found by symbol.
            Command::None if self.sys.surface_of[sym as usize].is_some() => {
                let size = arg.unwrap_or(1.0) * s.scale;
                let mesh = self.sys.surface_of[sym as usize].map(|k| &self.sys.surfaces[k as usize]);
                if let Some(mesh) = mesh.filter(|_| size > 0.0 && size.is_finite() && !self.dry) {
                    // Local +x → right (−L), +y → H, +z → U: a rotation.
                    let m = DMat3::from_cols(-s.l * size, s.h * size, s.u * size);
                    let transform = Affine3A::from_mat3_translation(m.as_mat3(), s.pos.as_vec3());
                    let tag = self.tag(self.state.color);
                    let id = self.scene.mesh(mesh);
                    self.scene.instances.push(Instance { transform, primitive: Primitive::Mesh(id), tag });
                    self.over |= self.primitives() > self.limit;
                }
            }
            Command::Cut | Command::None => {}
            // Drawing, branching and state changes: `apply` carries them
            // out and never sends them here.
            command => unreachable!("`apply` carries out {command:?}"),
        }
    }

    /// `F`: a segment of the parameter's length, or the file's step.
    #[inline(always)]
    fn draw(&mut self, s: &mut State, arg: Option<f64>) {
        let len = arg.unwrap_or(self.sys.settings.step) * s.scale;
        self.segment(s, len);
    }

    /// `[`: a branch starts with nothing drawn and no cylinder.
    #[inline(always)]
    fn push(&mut self, s: &mut State) {
        self.stack.push(*s);
        s.drawn = NOT_DRAWN;
        s.cylinder = NO_CYLINDER;
        self.open_line = None;
    }

    /// `]`: back to the state at the matching `[` (an unmatched `]` keeps
    /// the state).
    #[inline(always)]
    fn pop(&mut self, s: &mut State) {
        if let Some(prev) = self.stack.pop() {
            // A cylinder started in the branch ends with it.
            if let Some(k) = s.cylinder() {
                self.finish_cylinder(k);
            }
            *s = prev;
        }
        self.open_line = None;
    }

    /// `}`: the polygon being traced, closed, in colour `color` (fewer
    /// than three distinct points draw nothing).
    fn end_polygon(&mut self, color: u32) {
        if let Some(mut points) = self.polygons.pop().filter(|_| !self.dry) {
            if points.len() > 1 && points.first() == points.last() {
                points.pop();
            }
            if points.len() < 3 {
                return;
            }
            let tag = self.tag(color);
            self.scene.polygons.push(Polygon { points, tag });
            self.over |= self.primitives() > self.limit;
        }
    }

    /// Records `pos` as a vertex of the polygon being traced (the position
    /// at `{`, after each move inside it, and at `.`); repeated points are
    /// kept once.
    #[inline]
    fn vertex(&mut self, pos: DVec3) {
        if let Some(poly) = self.polygons.last_mut() {
            let p = pos.as_vec3();
            if poly.last() != Some(&p) {
                poly.push(p);
            }
        }
    }

    /// Moves state `s` by `len` along its heading, drawing a segment.
    #[inline(always)]
    fn segment(&mut self, s: &mut State, len: f64) {
        let st = &self.sys.settings;
        let from = s.pos;
        let to = from + s.h * len;
        let width = s.width * s.scale;
        let tag = self.tag(s.color);
        self.segments += 1;
        // Segments that extend one polyline add no primitive, yet each costs
        // memory and time: they count against the limit too.
        self.over |= self.segments > self.limit;
        if self.dry {
            // Only the state moves.
        } else if let (Some(k), View::Solid) = (s.cylinder(), st.view) {
            if len != 0.0
                && let Some(Some(c)) = self.cylinders.get_mut(k)
            {
                c.add(to, s.h, 0.5 * width);
                self.rings += 1;
                self.over |= self.primitives() > self.limit;
            }
            self.open_line = None;
        } else if st.view == View::Solid && width > 0.0 && len != 0.0 {
            let bottom = if s.drawn > width { s.drawn } else { width };
            // Unit frustum: axis along +y from y = −½ to ½, radius ½ at the
            // bottom; x → U, y → H, z → L keeps the transform a rotation.
            let axis = s.h * len;
            let m = DMat3::from_cols(s.u * bottom, axis, s.l * bottom);
            let mid = (from + to) * 0.5;
            let transform = Affine3A::from_mat3_translation(m.as_mat3(), mid.as_vec3());
            let top = (width / bottom) as f32;
            self.scene.instances.push(Instance { transform, primitive: Primitive::Frustum { top }, tag });
            self.over |= self.primitives() > self.limit;
            self.open_line = None;
        } else {
            let (p0, p1) = (from.as_vec3(), to.as_vec3());
            let w = width as f32;
            let lines = &mut self.scene.polylines;
            if self.open_line == Some((tag, w)) && lines.points().last() == Some(&p0) {
                lines.extend_last(p1);
            } else {
                lines.push(Polyline { points: &[p0, p1], width: w, tag });
                self.open_line = Some((tag, w));
                self.over |= self.primitives() > self.limit;
            }
        }
        s.pos = to;
        s.drawn = width;
        self.vertex(to);
        if st.tropism.is_some() {
            tropism(st, s);
        }
    }

    /// Starts a generalized cylinder at the turtle (closing the branch's
    /// open one first). Only the solid view sweeps cylinders; the flat view
    /// draws their segments as lines.
    fn start_cylinder(&mut self) {
        if let Some(k) = self.state.take_cylinder() {
            self.finish_cylinder(k);
        }
        if self.sys.settings.view != View::Solid || self.dry {
            return;
        }
        let s = self.state;
        let tag = self.tag(s.color);
        let radius = 0.5 * s.width * s.scale;
        self.cylinders.push(Some(Cylinder::start(s.pos, s.h, s.u, radius, tag)));
        self.state.cylinder = (self.cylinders.len() - 1) as u32;
    }

    /// Emits cylinder `k` (if still open) as a mesh asset placed by an
    /// identity instance; a cylinder with no segment emits nothing.
    fn finish_cylinder(&mut self, k: usize) {
        let Some(c) = self.cylinders.get_mut(k).and_then(Option::take) else { return };
        if let Some(mesh) = c.mesh() {
            let id = self.scene.mesh(&Arc::new(mesh));
            self.scene.instances.push(Instance {
                transform: Affine3A::IDENTITY,
                primitive: Primitive::Mesh(id),
                tag: c.tag,
            });
        }
        self.over |= self.primitives() > self.limit;
    }
}

#[cfg(test)]
mod tests {
    use super::cylinder::RING_SEGMENTS;
    use crate::compile::compile_text;
    use genform_core::Rng;
    use genform_core::scene::{Mesh, Primitive, Scene};
    use glam::DVec3;

    /// Draws the axiom of `text` (3D, width 0.4) with at most `limit` primitives.
    fn draw(text: &str, limit: usize) -> Result<Scene, super::TurtleError> {
        let (s, _) = compile_text(&format!("view: 3d\nwidth: 0.4\n{text}")).unwrap();
        let mut scene = Scene::new();
        s.interpret(&s.axiom, &mut Rng::from_seed(0), limit, &mut scene)?;
        Ok(scene)
    }

    /// The cylinder meshes, in the order their instances were placed.
    fn cylinders(scene: &Scene) -> Vec<&Mesh> {
        scene
            .instances
            .iter()
            .filter_map(|i| match i.primitive {
                Primitive::Mesh(id) => {
                    assert_eq!(i.transform, glam::Affine3A::IDENTITY);
                    Some(&*scene.meshes[id as usize])
                }
                _ => None,
            })
            .collect()
    }

    fn frusta(scene: &Scene) -> usize {
        scene.instances.iter().filter(|i| matches!(i.primitive, Primitive::Frustum { .. })).count()
    }

    /// The vertices of ring `k`.
    fn ring(m: &Mesh, k: usize) -> Vec<DVec3> {
        let n = RING_SEGMENTS as usize;
        m.positions[k * n..(k + 1) * n].iter().map(|p| p.as_dvec3()).collect()
    }

    fn centre(ring: &[DVec3]) -> DVec3 {
        ring.iter().sum::<DVec3>() / ring.len() as f64
    }

    #[test]
    fn a_straight_cylinder_has_one_ring_per_joint_on_the_axis() {
        let scene = draw("axiom: @Gc F F F @Ge\n", 1000).unwrap();
        assert_eq!(frusta(&scene), 0, "the segments are swept, not drawn as frusta");
        let meshes = cylinders(&scene);
        assert_eq!(meshes.len(), 1);
        let m = meshes[0];
        assert_eq!(m.positions.len(), 4 * RING_SEGMENTS as usize, "4 rings");
        for k in 0..4 {
            let r = ring(m, k);
            let c = centre(&r);
            assert!((c - DVec3::new(0.0, k as f64, 0.0)).length() < 1e-6, "ring {k} centre {c}");
            for v in &r {
                assert!(((*v - c).length() - 0.2).abs() < 1e-6, "radius = width / 2");
                assert!((v.y - k as f64).abs() < 1e-6, "ring {k} is perpendicular to the axis");
            }
        }
    }

    #[test]
    fn a_bent_cylinder_joint_lies_in_the_bisecting_plane() {
        let scene = draw("angle: 60\naxiom: @Gc F + F @Ge\n", 1000).unwrap();
        let m = cylinders(&scene)[0];
        let [c0, c1, c2] = [0, 1, 2].map(|k| centre(&ring(m, k)));
        let (h1, h2) = ((c1 - c0).normalize(), (c2 - c1).normalize());
        assert!((h1.dot(h2) - 0.5).abs() < 1e-6, "a 60° turn");
        let n = (h1 + h2).normalize();
        for v in ring(m, 1) {
            assert!((v - c1).dot(n).abs() < 1e-6, "the middle ring's normal is the bisector");
        }
        // The end rings are perpendicular to their segments.
        for v in ring(m, 2) {
            assert!((v - c2).dot(h2).abs() < 1e-6);
        }
    }

    #[test]
    fn a_branch_inside_a_cylinder_adds_no_rings_to_it() {
        let scene = draw("axiom: @Gc F [+F] F @Ge\n", 1000).unwrap();
        assert_eq!(frusta(&scene), 1, "the branch is drawn normally");
        assert_eq!(cylinders(&scene)[0].positions.len(), 3 * RING_SEGMENTS as usize);
        // A branch with its own `@Gc` sweeps its own cylinder, closed at `]`.
        let scene = draw("axiom: @Gc F [+@Gc F F] F @Ge\n", 1000).unwrap();
        let meshes = cylinders(&scene);
        assert_eq!(frusta(&scene), 0);
        assert_eq!(meshes.len(), 2);
        assert!(meshes.iter().all(|m| m.positions.len() == 3 * RING_SEGMENTS as usize));
    }

    #[test]
    fn an_unfinished_cylinder_is_closed_at_the_end_of_the_string() {
        let scene = draw("axiom: @Gc F F\n", 1000).unwrap();
        assert_eq!(cylinders(&scene)[0].positions.len(), 3 * RING_SEGMENTS as usize);
    }

    #[test]
    fn a_move_breaks_the_cylinder_and_an_empty_one_emits_nothing() {
        let scene = draw("axiom: @Gc F f F @Ge @Gc @Ge\n", 1000).unwrap();
        let meshes = cylinders(&scene);
        assert_eq!(meshes.len(), 2);
        assert!(meshes.iter().all(|m| m.positions.len() == 2 * RING_SEGMENTS as usize));
    }

    #[test]
    fn the_flat_view_draws_cylinder_segments_as_lines() {
        let (s, _) = compile_text("axiom: @Gc F F @Ge\n").unwrap();
        let mut scene = Scene::new();
        s.interpret(&s.axiom, &mut Rng::from_seed(0), 1000, &mut scene).unwrap();
        assert!(scene.meshes.is_empty());
        assert_eq!(scene.polylines.len(), 1);
    }

    #[test]
    fn cylinder_rings_count_towards_the_primitive_limit() {
        assert!(draw("axiom: @Gc F F F F @Ge\n", 3).is_err());
        assert!(draw("axiom: @Gc F F F F @Ge\n", 5).is_ok());
    }

    #[test]
    fn cylinder_commands_are_not_warned_about() {
        let (_, warnings) = compile_text("view: 3d\naxiom: @Gc F @Ge\n").unwrap();
        assert!(warnings.iter().all(|w| !w.message.contains("@G")), "{warnings:?}");
    }
}
