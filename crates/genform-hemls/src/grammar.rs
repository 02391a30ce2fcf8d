//! The compiled HEMLS rewrite system: what the `.gr8` front end produces and
//! the growth engine reads. Plain data; [`std::fmt::Display`] writes it back
//! as `.gr8` text that loads unchanged.

use genform_core::Span;

/// A turtle command. Genr8's `+` turns **right** (ABOP's turns left).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Turn {
    /// `+`: turn right by Angle (clockwise seen from the surface normal).
    Right,
    /// `-`: turn left by Angle.
    Left,
    /// `&`: pitch down by Angle.
    PitchDown,
    /// `^`: pitch up by Angle.
    PitchUp,
    /// `\`: roll left by Angle.
    RollLeft,
    /// `/`: roll right by Angle.
    RollRight,
}

/// How a successor edge's age follows the predecessor's (timed HEMLS).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Age {
    /// A plain `EdgeN`: age 0.
    Zero,
    /// `EdgeN_i`: the predecessor's age.
    Same,
    /// `EdgeN_i+1`.
    Plus1,
    /// `EdgeN_i-1` (never below 0).
    Minus1,
}

/// An edge symbol in a successor or the axiom.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EdgeSym {
    /// The type `N` of `EdgeN`.
    pub kind: u32,
    /// Preceded by `~`: the new edge's start and end are swapped for later
    /// rewriting; the turtle's heading does not change.
    pub reversed: bool,
    /// Age of the new edge.
    pub age: Age,
}

/// A branch: turns from the turtle state where the bracket opens, then one
/// edge drawn from that point with no end vertex (a half-edge to be joined
/// or removed). Nested brackets flatten into sibling branches, all opening
/// from the same pushed state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Branch {
    /// Turns applied after the push.
    pub turns: Vec<Turn>,
    /// The branch's edge.
    pub edge: EdgeSym,
}

/// One item of a successor, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Item {
    /// A turn of the main line.
    Turn(Turn),
    /// An edge of the main line.
    Edge(EdgeSym),
    /// A branch from the current main-line point.
    Branch(Branch),
}

/// One successor of a rule, with its weight (stochastic rules).
#[derive(Clone, Debug, PartialEq)]
pub struct Successor {
    /// Items in order.
    pub items: Vec<Item>,
    /// Relative weight (default 1); weights of a rule are normalised.
    pub weight: f64,
}

/// Comparison of a timed rule's condition `If i < c`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cmp {
    /// `<`
    Less,
    /// `=`
    Equal,
    /// `>`
    Greater,
}

/// `If i <op> value`: the rule applies only to edges whose age satisfies it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Condition {
    /// The comparison.
    pub cmp: Cmp,
    /// The constant.
    pub value: i64,
}

impl Condition {
    /// Whether an edge of `age` satisfies the condition.
    pub fn holds(&self, age: u32) -> bool {
        let a = age as i64;
        match self.cmp {
            Cmp::Less => a < self.value,
            Cmp::Equal => a == self.value,
            Cmp::Greater => a > self.value,
        }
    }
}

/// A rule's predecessor: `E`, `L < E`, `E > R` or `L < E > R`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Predecessor {
    /// The strict edge's type.
    pub kind: u32,
    /// Written as `EdgeN_i` (binds the age for successors and conditions).
    pub timed: bool,
    /// Left context: some other edge at the start vertex has this type.
    pub left: Option<u32>,
    /// Right context: some other edge at the end vertex has this type.
    pub right: Option<u32>,
}

/// A rewrite rule.
#[derive(Clone, Debug, PartialEq)]
pub struct Rule {
    /// What it rewrites.
    pub pred: Predecessor,
    /// Optional age condition.
    pub condition: Option<Condition>,
    /// One successor, or several drawn by weight each time the rule applies.
    pub successors: Vec<Successor>,
    /// Where the rule stands in its file (default for built grammars).
    pub span: Span,
}

/// One side of the axiom polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AxiomSide {
    /// Edge type.
    pub kind: u32,
    /// Written `~ EdgeN`.
    pub reversed: bool,
}

/// A complete HEMLS rewrite system.
#[derive(Clone, Debug, PartialEq)]
pub struct Hemls {
    /// Display name (the file stem).
    pub name: String,
    /// The seed polygon's sides, in order (at least 3).
    pub axiom: Vec<AxiomSide>,
    /// Rules in file order.
    pub rules: Vec<Rule>,
    /// Turn/pitch/roll angle in degrees.
    pub angle: f64,
    /// `Sync`: join branches once after all rules (else after each rule).
    pub sync: bool,
    /// `BranchAngle` in degrees when the file gives one (it wins over the
    /// settings' `branch_angle`).
    pub branch_angle: Option<f64>,
}
