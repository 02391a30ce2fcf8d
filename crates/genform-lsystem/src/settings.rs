//! Header settings of an L-system: derivation length, turtle defaults,
//! view, tropism, colours and limits.

use glam::DVec3;

/// How the turtle's drawing goes into the Scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Lines: every drawn segment is part of a polyline (SVG, PNG).
    Flat,
    /// Solids: segments with a width become frusta (GLB, OBJ); zero-width
    /// segments stay lines.
    Solid,
}

/// The turtle's initial frame, named by its heading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Heading {
    /// Along +x (curves).
    PlusX,
    /// Along −x.
    MinusX,
    /// Along +y (plants).
    PlusY,
    /// Along −y.
    MinusY,
    /// Along +z.
    PlusZ,
    /// Along −z.
    MinusZ,
}

impl Heading {
    /// Reads `+x`, `-y`, `x` (= `+x`), ….
    pub fn parse(s: &str) -> Option<Heading> {
        Some(match s.trim() {
            "+x" | "x" => Heading::PlusX,
            "-x" => Heading::MinusX,
            "+y" | "y" => Heading::PlusY,
            "-y" => Heading::MinusY,
            "+z" | "z" => Heading::PlusZ,
            "-z" => Heading::MinusZ,
            _ => return None,
        })
    }

    /// The frame (H, L, U), right-handed (H × L = U). Headings in the xy
    /// plane keep U = +z, so `+` turns counter-clockwise seen from +z.
    pub fn frame(self) -> [DVec3; 3] {
        let (h, u) = match self {
            Heading::PlusX => (DVec3::X, DVec3::Z),
            Heading::MinusX => (DVec3::NEG_X, DVec3::Z),
            Heading::PlusY => (DVec3::Y, DVec3::Z),
            Heading::MinusY => (DVec3::NEG_Y, DVec3::Z),
            Heading::PlusZ => (DVec3::Z, DVec3::Y),
            Heading::MinusZ => (DVec3::NEG_Z, DVec3::Y),
        };
        [h, u.cross(h), u]
    }
}

/// Settings from the file's header (all have defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Display name (`name:`).
    pub name: String,
    /// Derivation length n (`derivation:`, default 1).
    pub derivation: u32,
    /// Default turning angle in degrees (`angle:`, default 90).
    pub angle: f64,
    /// Default step length (`step:`, default 1).
    pub step: f64,
    /// Initial width (`width:`, default 0: hairlines in 2D, lines in 3D).
    pub width: f64,
    /// What `!` without a parameter multiplies the width by
    /// (`width_factor:`, default 0.7).
    pub width_factor: f64,
    /// What every width given in the file (`width:`, `!(w)`, `_(w)`) is
    /// multiplied by (`width_unit:`, default 1); `0.01` reads pixel widths
    /// of ABOP/cpfg files drawn with steps of about 1 % of the figure.
    pub width_unit: f64,
    /// Initial heading (`heading:`, default +y).
    pub heading: Heading,
    /// Lines or solids (`view: 2d | 3d`, default 2d).
    pub view: View,
    /// Tropism vector T (`tropism: x, y, z`), if any.
    pub tropism: Option<[f64; 3]>,
    /// Susceptibility to tropism e (`elasticity:`, default 0).
    pub elasticity: f64,
    /// Colour table indexed by `'` (`colors: #rrggbb …`); indices past
    /// its end take the last colour.
    pub colors: Vec<[u8; 3]>,
    /// Probability that a module is rewritten when the system is a
    /// generator (`growth:`, default 1: every module, as in a plain
    /// derivation). Below 1, optimizers may prune and regrow branches.
    pub growth: f64,
    /// Longest string a derivation may produce (`max_modules:`, default
    /// 5,000,000).
    pub max_modules: usize,
    /// Where `max_modules:` sets it, so a door can name the setting when
    /// it refuses the value ([`crate::LSystem::location`]).
    pub max_modules_at: Option<genform_core::Span>,
    /// L-Py's meaning where it differs (set for `.lpy` files): `%` cuts its
    /// branch when the next step reads it, so the last step's cuts stay in
    /// the string (otherwise, as in cpfg, at the end of the step that
    /// writes it); queries (`?P`, `?H`, …) answer in L-Py's z-up axes.
    pub lpy: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_modules_at: None,
            name: String::new(),
            derivation: 1,
            angle: 90.0,
            step: 1.0,
            width: 0.0,
            width_factor: 0.7,
            width_unit: 1.0,
            heading: Heading::PlusY,
            view: View::Flat,
            tropism: None,
            elasticity: 0.0,
            colors: Vec::new(),
            growth: 1.0,
            max_modules: 5_000_000,
            lpy: false,
        }
    }
}
