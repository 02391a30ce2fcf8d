//! Syntax tree of a `.sg` file, as written (before templates are expanded
//! and names resolved).

use genform_core::Span;
use genform_core::expr::Ast;

/// An embedded expression with where it starts in the file (its own spans
/// are relative to that offset).
#[derive(Clone, Debug)]
pub(crate) struct ExprSrc {
    pub ast: Ast,
    /// Byte offset of the expression text in the file.
    pub offset: usize,
    /// The name, when the expression is one bare identifier (axes, mesh
    /// names and vector parameters are written that way).
    pub bare: Option<String>,
}

impl ExprSrc {
    /// The expression's span in the file.
    pub fn span(&self) -> Span {
        self.ast.span.shift(self.offset)
    }
}

/// A distribution argument: one expression (broadcast to every component)
/// or a vector literal `[a, b, c]` with one expression per component.
#[derive(Clone, Debug)]
pub(crate) enum Value {
    Scalar(ExprSrc),
    Vector(Vec<ExprSrc>, Span),
}

impl Value {
    pub fn span(&self) -> Span {
        match self {
            Value::Scalar(e) => e.span(),
            Value::Vector(_, s) => *s,
        }
    }
}

/// A reference to a rule, with a template index when it has one:
/// `Wing` or `Body<i + 1>`.
#[derive(Clone, Debug)]
pub(crate) struct SymRef {
    pub name: String,
    pub span: Span,
    pub index: Option<ExprSrc>,
}

/// `param name: type dist(args) in [lo, hi];`
#[derive(Clone, Debug)]
pub(crate) struct ParamDecl {
    pub name: String,
    pub span: Span,
    /// Declared dimension (`vec2` = 2, `vec3` = 3), `None` when omitted.
    pub dim: Option<usize>,
    pub dist: String,
    pub dist_span: Span,
    pub args: Vec<DistArg>,
    /// Call span (for arity errors).
    pub args_span: Span,
    /// `in [lo, hi]` bounds (normal only).
    pub bounds: Option<(Value, Value)>,
}

/// One argument of a distribution: a value, or `value: weight` in `choice`.
#[derive(Clone, Debug)]
pub(crate) struct DistArg {
    pub value: Value,
    pub weight: Option<ExprSrc>,
}

/// `slot name: Target p prob x count;`
#[derive(Clone, Debug)]
pub(crate) struct SlotDecl {
    pub name: String,
    pub span: Span,
    pub target: SymRef,
    pub prob: Option<ExprSrc>,
    pub count: Option<ExprSrc>,
}

/// An argument of an operation or invocation.
#[derive(Clone, Debug)]
pub(crate) enum Arg {
    Expr(ExprSrc),
    Str(String, Span),
    /// `name = value` (only roofs take them): the name and its span, the
    /// value (an expression or a string; several for a list `[a, b, …]`)
    /// and whether it was written as a list.
    Named {
        name: String,
        span: Span,
        value: Vec<Arg>,
        list: bool,
    },
}

impl Arg {
    pub fn span(&self) -> Span {
        match self {
            Arg::Expr(e) => e.span(),
            Arg::Str(_, s) => *s,
            Arg::Named { span, .. } => *span,
        }
    }
}

/// One piece of a `split`: `2: A` or `1r: { ... }`.
#[derive(Clone, Debug)]
pub(crate) struct Piece {
    pub size: ExprSrc,
    pub relative: bool,
    /// `~2`: a floating size, stretched with the other floating pieces so
    /// the split fills the scope.
    pub floating: bool,
    pub body: Vec<Stmt>,
}

/// What a component split (`comp`, `offset`, `setback`, `shapeL/U/O`)
/// divides its scope into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CompKind {
    /// `comp(f)`: the faces of a mass.
    Faces,
    /// `comp(e)`: the edges of a polygon.
    Edges,
    /// `offset(d)`: the inset (or grown) polygon and the border between.
    Offset,
    /// `setback(d)`: strips along the selected edges and the remainder.
    Setback,
    /// `shapeL(front, left)`: an L along the front and left and the remainder.
    ShapeL,
    /// `shapeU(front, left, right)`.
    ShapeU,
    /// `shapeO(front, right, back, left)`: a ring of four bands and the courtyard.
    ShapeO,
    /// `comp(v)`: the corners of a polygon.
    Vertices,
    /// `roof_hip(30) { top: A | side: B }`, `taper(h) { … }`: the planar
    /// faces of the solid the operation builds on a polygon.
    Solid,
}

impl CompKind {
    /// Every kind, indexed by `kind as usize`.
    pub const ALL: [CompKind; 9] = [
        CompKind::Faces,
        CompKind::Edges,
        CompKind::Offset,
        CompKind::Setback,
        CompKind::ShapeL,
        CompKind::ShapeU,
        CompKind::ShapeO,
        CompKind::Vertices,
        CompKind::Solid,
    ];

    /// The operation as written, and the arguments it takes.
    pub fn name(self) -> (&'static str, usize) {
        match self {
            CompKind::Faces => ("comp(f)", 0),
            CompKind::Edges => ("comp(e)", 0),
            CompKind::Offset => ("offset", 1),
            // The distance, then the front, back, left and right edges'
            // (the parser fills in the distance where a side is not named),
            // then how many per-edge distances follow (`edges = […]`).
            CompKind::Setback => ("setback", 6),
            CompKind::ShapeL => ("shapeL", 2),
            CompKind::ShapeU => ("shapeU", 3),
            CompKind::ShapeO => ("shapeO", 4),
            CompKind::Vertices => ("comp(v)", 0),
            // The roof's (or taper's) own arguments are the operation's.
            CompKind::Solid => ("roof", 0),
        }
    }

    /// The operation a statement name starts, other than `comp`.
    pub fn of_name(name: &str) -> Option<CompKind> {
        Some(match name {
            "offset" => CompKind::Offset,
            "setback" => CompKind::Setback,
            "shapeL" => CompKind::ShapeL,
            "shapeU" => CompKind::ShapeU,
            "shapeO" => CompKind::ShapeO,
            _ => return None,
        })
    }
}

/// One arm of `comp(f)`: `front: A` or `left, right: { ... }`.
#[derive(Clone, Debug)]
pub(crate) struct CompArm {
    /// The face classes it takes (bits of `FACE_*` in `program`).
    pub mask: u8,
    /// The pieces it takes by index (bit `i`: piece `i` of the split's
    /// list), besides those of its classes.
    pub indices: u64,
    pub body: Vec<Stmt>,
}

/// A statement of a rule body.
#[derive(Clone, Debug)]
pub(crate) enum Stmt {
    Param(ParamDecl),
    Slot(SlotDecl),
    Let {
        name: String,
        span: Span,
        value: ExprSrc,
    },
    If {
        cond: ExprSrc,
        then: Vec<Stmt>,
        els: Vec<Stmt>,
    },
    Alt {
        span: Span,
        arms: Vec<(ExprSrc, Vec<Stmt>)>,
    },
    Mirror {
        axis: Axis,
        body: Vec<Stmt>,
    },
    Split {
        axis: Axis,
        pieces: Vec<Piece>,
        /// `splitArea`: the sizes are areas of the polygon, not lengths.
        area: bool,
        /// The `split` / `splitArea` word.
        span: Span,
    },
    Repeat {
        axis: Axis,
        tile: ExprSrc,
        body: Vec<Stmt>,
    },
    /// `comp(f) { front: A | side: B | top: C }`: the faces of the mass;
    /// likewise `comp(e)`, `offset(d)`, `setback(d)` and `shapeL/U/O(…)`
    /// with their arguments.
    Comp {
        span: Span,
        kind: CompKind,
        args: Vec<ExprSrc>,
        arms: Vec<CompArm>,
        /// The roof or taper whose faces a [`CompKind::Solid`] split takes:
        /// the operation and its arguments.
        solid: Option<Box<(SymRef, Vec<Arg>)>>,
    },
    /// `[ ... ]`: the scope is saved before and restored after.
    Scoped(Vec<Stmt>),
    /// An operation (`translate(...)`, `box`, …) or an invocation (`Wing`,
    /// `next(x)`, `Body<i + 1>`); told apart when names are resolved.
    Call {
        target: SymRef,
        args: Option<Vec<Arg>>,
    },
}

/// A local axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
}

/// `<i: 0..8>` of a template rule (end exclusive).
#[derive(Clone, Debug)]
pub(crate) struct Template {
    pub var: String,
    pub var_span: Span,
    pub lo: Bound,
    pub hi: Bound,
}

/// A template bound: an integer literal or a `const` name.
#[derive(Clone, Debug)]
pub(crate) enum Bound {
    Int(f64, Span),
    Const(String, Span),
}

/// A rule: `Name<i: 0..8>(a, b) { ... }`.
#[derive(Clone, Debug)]
pub(crate) struct Rule {
    pub name: String,
    pub span: Span,
    pub template: Option<Template>,
    pub args: Vec<(String, Span)>,
    pub body: Vec<Stmt>,
}

/// A top-level item.
#[derive(Clone, Debug)]
pub(crate) enum Item {
    Grammar(String, Span),
    Axiom(SymRef),
    Limits(Vec<(String, Span, ExprSrc)>),
    Const(String, Span, ExprSrc),
    Mesh(String, Span, String, Span),
    /// `footprints "path";`: the path and its span.
    Footprints(String, Span),
    /// `context "path";`: a mesh of what stands around, for occlusion
    /// queries.
    Context(String, Span),
    Rule(Rule),
}
