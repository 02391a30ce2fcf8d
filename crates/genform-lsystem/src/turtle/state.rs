//! The turtle's state and the drawing turtle around it, with tropism's
//! bend of the heading: what the general turtle, the flat turtle and the
//! query filler all start from, kept below them so the flat turtle can
//! share it without calling back up into the general one.

use super::cylinder::Cylinder;
use crate::alphabet::Command;
use crate::compile::LSystem;
use crate::settings::Settings;
use genform_core::scene::{Scene, TagId};
use glam::{DMat3, DVec3, Vec3};

/// Colours used when the file gives no `colors:` table: near-black lines,
/// then green, red, yellow, brown.
const DEFAULT_COLORS: [[u8; 3]; 5] =
    [[0x22, 0x22, 0x22], [0x2e, 0x7d, 0x32], [0xc6, 0x28, 0x28], [0xf9, 0xa8, 0x25], [0x6d, 0x4c, 0x41]];

/// The largest colour index (keeps the tag table small).
pub(super) const MAX_COLOR: u32 = 1 << 16;

/// The turtle's state, copied at every `[` and `]`: kept to 128 bytes,
/// which the compiler copies inline (at 152 bytes each copy was a call to
/// `memmove`, a third of drawing a bracketed plant).
#[derive(Clone, Copy, Debug)]
pub(super) struct State {
    pub(super) pos: DVec3,
    pub(super) h: DVec3,
    pub(super) l: DVec3,
    pub(super) u: DVec3,
    pub(super) width: f64,
    /// Width the last segment of this branch ended with (for taper);
    /// [`NOT_DRAWN`] before the branch's first segment.
    pub(super) drawn: f64,
    /// L-Py's turtle scale (`@D`): multiplies move lengths, drawn widths
    /// and sphere radii.
    pub(super) scale: f64,
    /// At most [`MAX_COLOR`].
    pub(super) color: u32,
    /// The generalized cylinder this branch is tracing, by index into
    /// `Turtle::cylinders`; [`NO_CYLINDER`] for none (`[` starts a branch
    /// without one).
    pub(super) cylinder: u32,
}

const _: () = assert!(std::mem::size_of::<State>() == 128, "see State");

/// `State::drawn` of a branch that has drawn nothing: compares below every
/// width.
pub(super) const NOT_DRAWN: f64 = f64::NEG_INFINITY;

/// `State::cylinder` of a branch tracing none.
pub(super) const NO_CYLINDER: u32 = u32::MAX;

impl State {
    /// The cylinder this branch is tracing.
    pub(super) fn cylinder(&self) -> Option<usize> {
        (self.cylinder != NO_CYLINDER).then_some(self.cylinder as usize)
    }

    /// The cylinder this branch is tracing, which it stops tracing.
    pub(super) fn take_cylinder(&mut self) -> Option<usize> {
        let k = self.cylinder();
        self.cylinder = NO_CYLINDER;
        k
    }
}

pub(super) struct Turtle<'a> {
    pub(super) sys: &'a LSystem,
    pub(super) scene: &'a mut Scene,
    pub(super) state: State,
    pub(super) stack: Vec<State>,
    pub(super) polygons: Vec<Vec<Vec3>>,
    /// The tag and width of the scene's last polyline when it is the one
    /// this branch is drawing (a segment of that style continuing it from
    /// its last point extends it).
    pub(super) open_line: Option<(TagId, f32)>,
    pub(super) tags: Vec<Option<TagId>>,
    /// Generalized cylinders being traced (`None` once emitted).
    pub(super) cylinders: Vec<Option<Cylinder>>,
    /// Rings added to cylinders by `F`: each counts as a primitive, like
    /// the frustum it replaces (the cylinder's instance counts once more).
    pub(super) rings: usize,
    pub(super) segments: usize,
    pub(super) limit: usize,
    pub(super) over: bool,
    /// Only the turtle state matters (filling query modules): nothing is
    /// drawn.
    pub(super) dry: bool,
    /// Each symbol's command (read once per module: a table of its own
    /// keeps the dispatch to one byte load).
    pub(super) commands: Vec<Command>,
    /// Sine and cosine of the file's angle and of its negative: turns
    /// without a parameter are most modules of a plant, and `sin_cos` was
    /// an eighth of drawing one.
    pub(super) turns: [(f64, f64); 2],
}

impl<'a> Turtle<'a> {
    /// A turtle at the origin in the file's initial frame.
    pub(super) fn new(sys: &'a LSystem, scene: &'a mut Scene, limit: usize, dry: bool) -> Turtle<'a> {
        let [h, l, u] = sys.settings.heading.frame();
        let st = &sys.settings;
        Turtle {
            sys,
            scene,
            state: State {
                pos: DVec3::ZERO,
                h,
                l,
                u,
                width: st.width * st.width_unit,
                drawn: NOT_DRAWN,
                color: 0,
                scale: 1.0,
                cylinder: NO_CYLINDER,
            },
            stack: Vec::new(),
            polygons: Vec::new(),
            open_line: None,
            tags: Vec::new(),
            cylinders: Vec::new(),
            rings: 0,
            segments: 0,
            limit,
            over: false,
            dry,
            commands: sys.alphabet.symbols.iter().map(|s| s.command).collect(),
            turns: [st.angle.to_radians().sin_cos(), (-st.angle).to_radians().sin_cos()],
        }
    }
}

impl Turtle<'_> {
    pub(super) fn primitives(&self) -> usize {
        self.scene.instances.len() + self.scene.polylines.len() + self.scene.polygons.len() + self.rings
    }

    /// The tag of colour `color` (interned on first use).
    #[inline]
    pub(super) fn tag(&mut self, color: u32) -> TagId {
        match self.tags.get(color as usize) {
            Some(Some(t)) => *t,
            _ => self.new_tag(color as usize),
        }
    }

    #[cold]
    fn new_tag(&mut self, color: usize) -> TagId {
        let table: &[[u8; 3]] =
            if self.sys.settings.colors.is_empty() { &DEFAULT_COLORS } else { &self.sys.settings.colors };
        // Indices past the table keep its last colour.
        let [r, g, b] = table[color.min(table.len() - 1)];
        let id = self.scene.tag(&format!("color{color}#{r:02x}{g:02x}{b:02x}"));
        if self.tags.len() <= color {
            self.tags.resize(color + 1, None);
        }
        self.tags[color] = Some(id);
        id
    }
}

/// Bends H towards T about H × T by e·|H × T| (ABOP p. 58).
// Beside `Turtle` rather than with the drawing loop that calls it: rustc
// compiles a type's methods with the code of the type's module, and the
// loop keeps its register use (and speed) only when this lands there too.
pub(super) fn tropism(st: &Settings, s: &mut State) {
    let Some(t) = st.tropism else { return };
    if st.elasticity == 0.0 {
        return;
    }
    let axis = s.h.cross(DVec3::from_array(t));
    let n = axis.length();
    if n < 1e-12 {
        return;
    }
    let rot = DMat3::from_axis_angle(axis / n, st.elasticity * n);
    s.h = (rot * s.h).normalize();
    s.l = (rot * s.l).normalize();
    s.u = s.h.cross(s.l);
}
