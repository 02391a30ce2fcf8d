//! Mapper settings: the standard GE ones and Genr8's extensions.

use serde::{Deserialize, Serialize};

/// How a genome is mapped.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapOptions {
    /// How many times reading may go back to the genome's start (0: running
    /// out of codons makes the individual invalid).
    pub max_wraps: u32,
    /// Derivation-tree depth limit (root = 1, terminal leaves count): a
    /// symbol deeper than this, or a non-terminal at this depth or deeper,
    /// makes the individual invalid (`depth_limit`). `None`: no limit.
    pub max_tree_depth: Option<u32>,
    /// Separate terminals on a line by one space instead of concatenating
    /// them: no space after a terminal that ends with a newline, none before
    /// one that starts with a newline, empty terminals skipped. For
    /// token-based languages such as `.gr8`.
    pub spaced: bool,
    /// Genr8's extensions; `None` for standard GE. Groups (`{ }`, `[ ]`)
    /// always use Genr8's gene rules (with [`Genr8Options::default`]'s
    /// repetition constant when this is `None`).
    pub genr8: Option<Genr8Options>,
    /// Which codon each decision reads: the next in the genome
    /// ([`CodonLayout::Sequential`], standard GE) or the next of its own
    /// interleaved stream ([`CodonLayout::PerChoice`]).
    #[serde(default)]
    pub layout: CodonLayout,
}

/// Where the mapper finds the codon for its next decision.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CodonLayout {
    /// Standard GE: decisions read the genome left to right, wrapping to
    /// its start.
    #[default]
    Sequential,
    /// One interleaved stream per kind of decision, in the manner of
    /// structured GE (Lourenço et al. 2016): with `K` kinds (each
    /// non-terminal, each `{ }` and `[ ]` group, and edge IDs), the `i`-th
    /// decision of kind `k` reads codon `p mod len` with `p = i·K + k`,
    /// and `p ≥ (max_wraps + 1)·len` makes the individual invalid. A codon
    /// then keeps its meaning when an earlier decision of another kind
    /// changes, which standard GE's ripple effect does not allow; the read
    /// codons are still a prefix (up to the furthest `p`), so effective
    /// operators and prefix memories work unchanged.
    PerChoice,
}

impl Default for MapOptions {
    /// Standard GE: no wrapping, no depth limit, terminals concatenated.
    fn default() -> Self {
        MapOptions { max_wraps: 0, max_tree_depth: None, spaced: false, genr8: None, layout: CodonLayout::Sequential }
    }
}

impl MapOptions {
    /// Standard GE with `max_wraps` and an optional depth limit (the
    /// settings of the golden traces).
    pub fn standard(max_wraps: u32, max_tree_depth: Option<u32>) -> Self {
        MapOptions { max_wraps, max_tree_depth, ..MapOptions::default() }
    }

    /// The settings for Genr8's EA grammars (`examples/ge/genr8*.bnf`):
    /// spaced tokens, every extension on, repair on, 4 wraps, no tree-depth
    /// failure (Genr8's depth rule restricts choices instead).
    pub fn genr8() -> Self {
        MapOptions {
            max_wraps: 4,
            max_tree_depth: None,
            spaced: true,
            genr8: Some(Genr8Options { repair: Some(RepairOptions::default()), ..Genr8Options::default() }),
            layout: CodonLayout::Sequential,
        }
    }
}

/// Genr8's GE extensions (Hemberg & O'Reilly §5; `genr8.md` §6).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Genr8Options {
    /// Edge IDs: the terminal `"Edge"` reads a gene and becomes `EdgeN`
    /// with `N = gene mod (max_ID + 1)`; `"EdgeX"`, `"EdgeY"`, `"EdgeZ"`
    /// are bound once per production instance (the first one reads the
    /// gene, the others reuse its ID).
    pub edge_ids: bool,
    /// `max_ID` at the start of every genome (the number of edge IDs in
    /// use; Genr8 starts with IDs 0 and 1, so 2). It grows by one whenever
    /// a read draws `N = max_ID`.
    pub initial_max_id: u32,
    /// The constant of the `{ }` test: with counter `c`, a gene `g` stops
    /// the repetition when `g mod (c + repeat_constant) ≤ c`. At least 1.
    pub repeat_constant: u32,
    /// Depth-limited choice: a non-terminal at depth ≥ `max_depth` (root =
    /// 1, the depth convention of the traces) chooses only among its
    /// alternatives that contain no non-terminal, `gene mod` their count;
    /// a non-terminal with no such alternative stays unrestricted.
    /// `None`: no restriction.
    pub max_depth: Option<u32>,
    /// Genr8's repair post-pass; `None` leaves it off.
    pub repair: Option<RepairOptions>,
}

impl Default for Genr8Options {
    /// Edge IDs on, `max_ID` 2, constant 2, `max_depth` 8, no repair.
    fn default() -> Self {
        Genr8Options { edge_ids: true, initial_max_id: 2, repeat_constant: 2, max_depth: Some(8), repair: None }
    }
}

/// Genr8's repair: after mapping, every edge type that occurs in the
/// phenotype but has no rule gets one.
///
/// Specific to grammars shaped like `examples/ge/genr8.bnf`: the missing
/// types are handled in increasing order; each gets an expansion of the
/// `rule` non-terminal in which the first `predecessor` non-terminal is
/// replaced by `EdgeN` (no gene), reading the genes that follow (wrapping
/// as usual, counted against `max_wraps`). The new rules go right after
/// the terminal that follows the last `rule` expansion of the main
/// mapping (the line end), each followed by a copy of it. A type "has a
/// rule" when it is the strict edge of some predecessor: the edge after
/// `<` if there is one, else the first edge. New types that repaired rules
/// introduce are repaired in turn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RepairOptions {
    /// The rewrite-rule non-terminal.
    pub rule: String,
    /// The predecessor non-terminal inside it.
    pub predecessor: String,
    /// At most this many added rules; more makes the individual invalid
    /// (`repair_limit`).
    pub max_rules: u32,
}

impl Default for RepairOptions {
    /// `<RewriteRule>`, `<Predecessor>`, at most 64 rules.
    fn default() -> Self {
        RepairOptions { rule: "<RewriteRule>".into(), predecessor: "<Predecessor>".into(), max_rules: 64 }
    }
}

/// Options that cannot work with a grammar.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MapError {
    /// A non-terminal named by the repair options is not in the grammar.
    #[error("repair needs the non-terminal `{0}`, which the grammar does not define")]
    UnknownRule(String),
    /// Repair without edge IDs has no edge types to repair.
    #[error("repair needs edge IDs (`edge_ids: true`)")]
    RepairNeedsEdgeIds,
    /// A repetition constant of 0 would divide by zero.
    #[error("the repetition constant must be at least 1")]
    ZeroRepeatConstant,
}
