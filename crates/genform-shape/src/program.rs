//! The compiled form of a rule: a flat list of operations per symbol.
//!
//! Bodies are flattened (jumps instead of nested blocks) so the interpreter
//! keeps all its state in explicit stacks and never recurses on the Rust
//! stack, however deep a derivation goes.

use crate::ast::CompKind;
use crate::builtins::ENV_SX;
use crate::fast_expr::Fast;
use genform_core::Span;
use genform_core::expr::Program;

/// A compiled expression with the slots whose `has(slot)` it reads.
#[derive(Clone, Debug)]
pub(crate) struct Expr {
    pub prog: Program,
    /// How the interpreter evaluates it: directly, or by running `prog`.
    pub fast: Fast,
    /// Whether the program is run and reads the scope size (`sx`, `sy`,
    /// `sz`), which the interpreter then copies into the env first.
    pub needs_size: bool,
    /// `(env index, local slot)` pairs to fill before evaluating.
    pub has: Vec<(u32, u32)>,
    /// Occlusion queries to answer into the env before evaluating.
    pub queries: Vec<(u32, Query)>,
    /// Where it is written (for runtime error messages).
    pub span: Span,
}

impl Expr {
    /// Wraps a compiled program, classifying it for the interpreter.
    pub fn new(prog: Program, has: Vec<(u32, u32)>, span: Span) -> Expr {
        Expr::with_queries(prog, has, Vec::new(), span)
    }

    /// [`Expr::new`] for a program that also reads occlusion queries.
    pub fn with_queries(prog: Program, has: Vec<(u32, u32)>, queries: Vec<(u32, Query)>, span: Span) -> Expr {
        let fast = if has.is_empty() && queries.is_empty() { Fast::of(&prog) } else { Fast::Run };
        let size = ENV_SX as u32..ENV_SX as u32 + 3;
        let needs_size = matches!(fast, Fast::Run) && prog.loads().any(|i| size.contains(&i));
        Expr { prog, fast, needs_size, has, queries, span }
    }
}

/// What an occlusion query asks of the scope's box (see
/// `interp::occlusion`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum QueryKind {
    /// `inside()`: within one placed box.
    Inside,
    /// `overlaps()`: sharing volume with one.
    Overlaps,
    /// `touches()`: overlapping or touching one.
    Touches,
}

impl QueryKind {
    /// The query a function name asks.
    pub(crate) fn from_name(name: &str) -> Option<QueryKind> {
        Some(match name {
            "inside" => QueryKind::Inside,
            "overlaps" => QueryKind::Overlaps,
            "touches" => QueryKind::Touches,
            _ => return None,
        })
    }
}

/// An occlusion query: its kind, and the tag occluders must have (any
/// when `None`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Query {
    pub kind: QueryKind,
    pub tag: Option<u32>,
}

/// A primitive to emit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Prim {
    Box,
    Cylinder,
    Cone,
    Sphere,
    /// Top-radius ratio expression.
    Frustum(u32),
    /// Top-face ratio expression.
    Taper(u32),
    /// Index into the grammar's meshes.
    Mesh(u32),
}

/// Face classes of `comp(f)`, by the face's outward normal in the scope.
pub(crate) const FACE_FRONT: u8 = 1;
pub(crate) const FACE_BACK: u8 = 2;
pub(crate) const FACE_LEFT: u8 = 4;
pub(crate) const FACE_RIGHT: u8 = 8;
pub(crate) const FACE_TOP: u8 = 16;
pub(crate) const FACE_BOTTOM: u8 = 32;

/// The pieces other than faces and edges: `inside` of `offset`,
/// `remainder` of `setback` and `shapeL/U/O`, a roof's flush walls.
pub(crate) const PIECE_REST: u8 = 64;
/// The `shape` of `shapeL/U/O`, a roof's other vertical faces (`verge`).
pub(crate) const PIECE_SHAPE: u8 = 128;
/// Every wall or edge class.
pub(crate) const SIDE: u8 = FACE_FRONT | FACE_BACK | FACE_LEFT | FACE_RIGHT;

/// The classes a selector names in a component split of `kind`, and the
/// selectors it knows (for the hint).
pub(crate) fn selector(kind: CompKind, name: &str) -> Result<u8, &'static str> {
    let edge = |name: &str| match name {
        "front" => Some(FACE_FRONT),
        "back" => Some(FACE_BACK),
        "left" => Some(FACE_LEFT),
        "right" => Some(FACE_RIGHT),
        "side" | "all" => Some(SIDE),
        _ => None,
    };
    let (found, known) = match kind {
        CompKind::Faces => {
            (face_selector(name), "front, back, left, right, top, bottom, side, vertical, horizontal, all")
        }
        CompKind::Edges | CompKind::Vertices => (edge(name), "front, back, left, right, side, all"),
        CompKind::Offset => (
            match name {
                "inside" => Some(PIECE_REST),
                "border" => Some(SIDE),
                _ => edge(name).filter(|_| name != "all" && name != "side"),
            },
            "inside, border (or the border's front, back, left, right)",
        ),
        CompKind::Setback => (
            if name == "remainder" { Some(PIECE_REST) } else { edge(name) },
            "front, back, left, right, side, all, remainder",
        ),
        CompKind::Solid => (
            match name {
                "top" => Some(FACE_TOP | SIDE),
                "side" => Some(PIECE_REST),
                "verge" => Some(PIECE_SHAPE),
                "vertical" => Some(PIECE_REST | PIECE_SHAPE),
                "bottom" => Some(FACE_BOTTOM),
                "all" => Some(u8::MAX),
                _ => edge_side(name),
            },
            "top (every face that looks up: slopes and flat tops), side (gable walls flush with the façade), verge (other vertical faces: gable ends beyond the wall, ends of overhanging eaves), vertical (side and verge), bottom, all, and front, back, left, right (the slopes that face that way)",
        ),
        CompKind::ShapeL | CompKind::ShapeU | CompKind::ShapeO => (
            match name {
                "shape" => Some(PIECE_SHAPE),
                "remainder" => Some(PIECE_REST),
                _ => None,
            },
            "shape, remainder",
        ),
    };
    found.ok_or(known)
}

/// The bit of [`Op::SplitBegin`]'s axis that makes it a `splitArea`: the
/// piece sizes are areas of the scope's polygon.
pub(crate) const SPLIT_AREA: u8 = 0x80;

/// `ridge` of [`Op::Roof`] given as an edge index (else 0, along the
/// longer side, or a side's class bit).
pub(crate) const RIDGE_INDEX: u8 = 0x80;

/// The class bit of an edge side `front`, `back`, `left` or `right`.
pub(crate) fn edge_side(name: &str) -> Option<u8> {
    match name {
        "front" => Some(FACE_FRONT),
        "back" => Some(FACE_BACK),
        "left" => Some(FACE_LEFT),
        "right" => Some(FACE_RIGHT),
        _ => None,
    }
}

/// The face classes a `comp(f)` selector names.
pub(crate) fn face_selector(name: &str) -> Option<u8> {
    let side = SIDE;
    Some(match name {
        "front" => FACE_FRONT,
        "back" => FACE_BACK,
        "left" => FACE_LEFT,
        "right" => FACE_RIGHT,
        "top" => FACE_TOP,
        "bottom" => FACE_BOTTOM,
        "side" | "vertical" => side,
        "horizontal" => FACE_TOP | FACE_BOTTOM,
        "all" => side | FACE_TOP | FACE_BOTTOM,
        _ => return None,
    })
}

/// A split piece's kind of size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SizeKind {
    Absolute,
    /// `1r`: a weight of what the absolute sizes leave.
    Relative,
    /// `~2`: stretched with the other floating sizes to fill the scope.
    Floating,
}

/// One operation. Expression operands are indices into [`RuleCode::exprs`];
/// vector operands use three consecutive expressions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Op {
    /// Saves the scope (`[`).
    Push,
    /// Restores the last saved scope (`]`).
    Pop,
    Translate(u32),
    Rotate(u8, u32),
    Size(u32),
    Scale(u32),
    Tag(u32),
    /// `color("#rrggbb")`: the current tag with that colour (index into
    /// the grammar's colours; see `ShapeGrammar::color_tags`).
    Color(u32),
    /// `texture("file", w, h)`: the current tag with that texture (index
    /// into the grammar's textures; see `ShapeGrammar::texture_tags`).
    Texture(u32),
    /// Stores an expression's value in an env slot.
    Let(u32, u32),
    Emit(Prim),
    /// Runs a child of the slot with `args` consecutive expressions from
    /// `args`: the child in link `site` of an implicit slot (one link per
    /// place the rule is invoked, re-expressed each time that place runs),
    /// or, for a declared slot ([`COUNTED`]), the next link, cycling
    /// through the slot's links once all are used.
    Invoke {
        slot: u32,
        args: u32,
        nargs: u32,
        site: u32,
    },
    /// Jumps to the target when the expression is false.
    JumpUnless(u32, u32),
    Jump(u32),
    /// Jumps to `tables[table][gene value]` (a weighted alternative).
    Alt {
        env: u32,
        table: u32,
    },
    /// Saves the scope and slot counters; the body follows.
    MirrorBegin(u8),
    /// After the first pass: restores, reflects and jumps back to the body
    /// start; after the second: restores the scope and goes on.
    MirrorEnd(u32),
    /// Computes `n` pieces from `pieces[first..first + n]` (`axis` with
    /// [`SPLIT_AREA`] set: `splitArea`).
    SplitBegin {
        axis: u8,
        first: u32,
        n: u32,
        /// Indexes [`RuleCode::spans`].
        span: u32,
    },
    /// Saves the scope and enters piece `k` (its body ends with `Pop`).
    Piece(u32),
    /// `lot(w, d)` (`n` = 2) or `lot(x0, z0, x1, z1, …)`: `n` consecutive
    /// expressions from `args`; `span` indexes [`RuleCode::spans`].
    Lot {
        args: u32,
        n: u32,
        span: u32,
    },
    /// `extrude(h)`: polygon scope → mass.
    Extrude(u32),
    /// `taper(h, s)`: the pyramid (`s` = 0) or frustum of height `h` over a
    /// polygon scope, its top the polygon scaled by `s` about its centroid;
    /// `s` at `height + 1` (zero when not written). `faces`: the solid is
    /// kept for the [`CompKind::Solid`] split that follows, not emitted.
    Taper {
        height: u32,
        span: u32,
        faces: bool,
    },
    /// `shape;`: emits the scope's geometry (`span` for errors).
    Shape(u32),
    /// `roof_*(angle, overhang, …)`: angle, overhang, ridge edge index and
    /// gable-end overhang at `args` to `args + 3`, then `n` per-edge
    /// overhangs. `ridge`: 0 along the longer side, a side's class bit, or
    /// `RIDGE_INDEX` (the edge index expression); `ends`: whether the
    /// gable-end overhang is given; `gables`: the tag of the gable walls
    /// (`u32::MAX`: they stay roof). `faces`: the roof is kept for the
    /// [`CompKind::Solid`] split that follows, not emitted.
    Roof {
        kind: u8,
        ridge: u8,
        ends: bool,
        faces: bool,
        args: u32,
        n: u32,
        span: u32,
        gables: u32,
    },
    /// Computes the pieces of a component split (`CompKind as u8`; its
    /// arguments are the expressions from `args`) and the arm of each,
    /// from the arm masks `comps[first..first + n]`.
    CompBegin {
        kind: u8,
        args: u32,
        first: u32,
        n: u32,
        span: u32,
    },
    /// Enters the first face of arm `arm`, or jumps to `end` when it has none.
    CompArm {
        arm: u32,
        end: u32,
    },
    /// Leaves the face; enters the next face of `arm` (jumping to `body`)
    /// or goes on.
    CompNext {
        arm: u32,
        body: u32,
    },
    CompEnd,
    SplitEnd,
    /// Computes the tile count and enters the first tile.
    RepeatBegin {
        axis: u8,
        tile: u32,
    },
    /// Leaves the tile; enters the next one (jumping to the body) or ends.
    RepeatNext(u32),
}

/// The `site` of an [`Op::Invoke`] of a declared slot: its invocations
/// take the slot's links in turn.
pub(crate) const COUNTED: u32 = u32::MAX;

/// What the interpreter needs about one slot of the symbol.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SlotCode {
    /// First link of the slot in the gene.
    pub link: u32,
    /// Links of the slot.
    pub max: u32,
    /// Child symbol.
    pub target: u32,
    /// Expression probability (sampling).
    pub prob: f64,
}

/// A compiled symbol (one rule, or one instance of a template rule).
#[derive(Clone, Debug)]
pub(crate) struct RuleCode {
    pub code: Vec<Op>,
    pub exprs: Vec<Expr>,
    /// `exprs[i].fast`, densely packed for the interpreter's hot path.
    pub fast: Vec<Fast>,
    /// Jump tables of `alt`s.
    pub tables: Vec<Vec<u32>>,
    /// `(size expression, kind)` of split pieces.
    pub pieces: Vec<(u32, SizeKind)>,
    /// Face-class masks and piece-index bits of `comp` arms.
    pub comps: Vec<(u8, u64)>,
    /// Where operations that can fail at run time are written.
    pub spans: Vec<Span>,
    /// Initial env: built-ins, constants and the template index filled in.
    pub env_init: Vec<f64>,
    /// Env index of the first inherited argument.
    pub arg_base: u32,
    pub n_args: u32,
    /// Env index of the first gene parameter value.
    pub param_base: u32,
    /// Slots in graph order.
    pub slots: Vec<SlotCode>,
    /// Tag of emissions until `tag(...)` changes it.
    pub tag: u32,
}
