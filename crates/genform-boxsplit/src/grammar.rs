//! The compiled grammar: rules with guarded, weighted alternatives over an
//! arena of operations, the blocks and materials they paint with, and the
//! block types observers look at.

use crate::formula::{Formula, Observer};
use crate::observe::BlockType;
use crate::split::Round;
use genform_core::BlockState;
use glam::IVec3;
use serde::{Deserialize, Serialize};

pub(crate) type RuleId = u32;
pub(crate) type OpId = u32;

/// Palette entry of the grammar's air block (`void`).
pub(crate) const AIR: u32 = 0;

/// What a `fill` paints with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Paint {
    /// One block (index into [`BoxGrammar::blocks`]).
    Block(u32),
    /// A weighted mix, drawn per cell (index into the materials).
    Material(u32),
}

/// An operation on a scope.
#[derive(Clone, Debug)]
pub(crate) enum Op {
    Split {
        /// Local axis.
        axis: u8,
        sizes: Vec<Formula>,
        /// The sizes when none depends on the scope.
        constant: Option<Vec<f64>>,
        repeat: bool,
        round: Round,
        children: Vec<OpId>,
    },
    Fill(Paint),
    Skip,
    /// Permute the local axes (new axis i = old axis `perm[i]`), then go on.
    Reorient([u8; 3], OpId),
    /// Apply a rule to the scope.
    Rule(RuleId),
}

/// When an alternative applies.
#[derive(Clone, Debug)]
pub(crate) enum Guard {
    Always,
    When(Formula),
    /// Only when no `Always`/`When` alternative applies.
    Else,
}

/// One alternative of a rule.
#[derive(Clone, Debug)]
pub(crate) struct Alternative {
    pub guard: Guard,
    pub weight: f64,
    pub op: OpId,
    /// 1-based source line, for traces.
    pub line: u32,
}

/// A non-terminal and its alternatives, in source order.
#[derive(Clone, Debug)]
pub(crate) struct Rule {
    pub name: String,
    pub alternatives: Vec<Alternative>,
}

/// A weighted block mix.
#[derive(Clone, Debug)]
pub(crate) struct Material {
    pub blocks: Vec<u32>,
    pub weights: Vec<f64>,
}

impl Material {
    /// The position in `blocks` of one draw by weight (a mix of one block
    /// draws nothing).
    pub fn pick<C: genform_core::Draws + ?Sized>(&self, choices: &mut C) -> usize {
        if self.blocks.len() == 1 { 0 } else { choices.choose(&self.weights).min(self.blocks.len() - 1) }
    }
}

/// Which neighbour a `support` declaration asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// A solid block (or another member) directly above: hanging blocks.
    Above,
    /// A solid block (or another member) directly below: standing blocks.
    Below,
    /// A solid block beside it (one of the four horizontal neighbours) that
    /// is not a member: linings and walls that must lean on something.
    Beside,
    /// Connected bodies of members (trees: logs and leaves) that a
    /// derivation cut are kept only while they still stand on the ground;
    /// a body left floating is removed whole, or, where it reaches beyond
    /// the box, spared (the derivation's changes to it are given back).
    Rooted,
}

/// `support SIDE members;`: blocks of `ty` are kept only where the side holds.
#[derive(Clone, Debug)]
pub(crate) struct Support {
    pub side: Side,
    pub ty: BlockType,
}

/// `site foundation = B, yard = N;`: a building set on the ground of a
/// world (see `site.rs`).
#[derive(Clone, Debug)]
pub(crate) struct Site {
    /// What the foundation and the yard's paving are made of.
    pub foundation: Paint,
    /// Columns of yard on every side of the plot.
    pub yard: i32,
}

/// Bounds on one derivation; reaching one ends it with an error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct DeriveLimits {
    /// Rule applications, counting re-applications after backtracking.
    pub applications: u64,
    /// Backtracks (jumps back to an earlier choice).
    pub backtracks: u64,
    /// Rule applications nested inside each other.
    pub depth: u32,
}

impl Default for DeriveLimits {
    fn default() -> Self {
        DeriveLimits { applications: 1_000_000, backtracks: 100_000, depth: 10_000 }
    }
}

/// A compiled box-split grammar. Immutable; derive as often as needed.
#[derive(Clone, Debug)]
pub struct BoxGrammar {
    pub(crate) name: String,
    pub(crate) axiom: RuleId,
    /// `Op::Rule(axiom)`, where derivations start.
    pub(crate) start: OpId,
    pub(crate) rules: Vec<Rule>,
    pub(crate) ops: Vec<Op>,
    /// Blocks painted; entry [`AIR`] is air.
    pub(crate) blocks: Vec<BlockState>,
    pub(crate) materials: Vec<Material>,
    pub(crate) types: Vec<BlockType>,
    /// Observer and block type of each observer slot.
    pub(crate) slots: Vec<(Observer, u32)>,
    pub(crate) limits: DeriveLimits,
    /// `box …;`: the default derivation box, `min..max_exclusive`.
    pub(crate) default_box: Option<(IVec3, IVec3)>,
    /// `world "…";`: the default world, as written.
    pub(crate) default_world: Option<String>,
    /// `support …;` declarations, in source order.
    pub(crate) supports: Vec<Support>,
    /// `site …;`: set on the ground of a world.
    pub(crate) site: Option<Site>,
}

impl BoxGrammar {
    /// The name from `grammar "…";` (empty when not given).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The start rule.
    pub fn axiom(&self) -> &str {
        &self.rules[self.axiom as usize].name
    }

    /// Rule names in source order.
    pub fn rule_names(&self) -> impl Iterator<Item = &str> + '_ {
        self.rules.iter().map(|r| r.name.as_str())
    }

    /// The limits the grammar declares (defaults where it declares none).
    pub fn limits(&self) -> DeriveLimits {
        self.limits
    }

    /// The box the grammar declares with `box x0, y0, z0, x1, y1, z1;`, as
    /// `(min, max_exclusive)` (the corners are inclusive and in any order),
    /// or `None`. A caller's own box takes precedence.
    pub fn default_box(&self) -> Option<(IVec3, IVec3)> {
        self.default_box
    }

    /// The world the grammar declares with `world "…";`, exactly as written
    /// (a path the caller resolves, relative to the grammar file), or `None`.
    pub fn default_world(&self) -> Option<&str> {
        self.default_world.as_deref()
    }

    /// Every block the grammar can place (air first).
    pub fn blocks(&self) -> &[BlockState] {
        &self.blocks
    }
}

#[cfg(test)]
mod tests {
    use genform_core::SourceFile;
    use glam::IVec3;

    fn compile(src: &str) -> super::BoxGrammar {
        crate::compile(&SourceFile::new("t.bsg", src)).unwrap().0
    }

    #[test]
    fn declared_box_is_normalized_to_min_and_max_exclusive() {
        let g = compile("box 9, -2, 5, 0, 3, -5;\nworld \"../terrain/r.0.0.mca\";\nA { fill stone }\n");
        assert_eq!(g.default_box(), Some((IVec3::new(0, -2, -5), IVec3::new(10, 4, 6))));
        assert_eq!(g.default_world(), Some("../terrain/r.0.0.mca"));
        let g = compile("A { fill stone }\n");
        assert_eq!((g.default_box(), g.default_world()), (None, None));
    }
}
