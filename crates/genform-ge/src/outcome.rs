//! What mapping a genome gives: the quick [`Outcome`] and the full
//! [`Mapping`] trace, whose JSON uses the field names of the golden traces
//! (`shared/reference/ge/*.jsonl`).

use serde::{Deserialize, Serialize};
use std::fmt;

/// Why an individual is invalid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Failure {
    /// A codon was needed after `max_wraps` wraps.
    WrapLimit,
    /// The derivation tree passed `max_tree_depth`.
    DepthLimit,
    /// The genome has no codons.
    EmptyGenome,
    /// Repair needed more than its `max_rules` rules.
    RepairLimit,
}

impl Failure {
    /// The name used in traces, e.g. `wrap_limit`.
    pub fn as_str(self) -> &'static str {
        match self {
            Failure::WrapLimit => "wrap_limit",
            Failure::DepthLimit => "depth_limit",
            Failure::EmptyGenome => "empty_genome",
            Failure::RepairLimit => "repair_limit",
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The result of [`crate::Mapper::map`]; the phenotype stays in the mapper
/// ([`crate::Mapper::phenotype`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// `None` when the individual is valid.
    pub fail: Option<Failure>,
    /// Codon reads, re-reads after wrapping included.
    pub used_codons: usize,
    /// Times reading went back to codon 0 (and then read one).
    pub wraps: u32,
    /// One past the furthest codon read: the codons that decide the
    /// phenotype are `genome[..extent]` (the whole genome once reading
    /// wrapped).
    pub extent: usize,
}

impl Outcome {
    /// Whether mapping finished with no non-terminal left.
    pub fn valid(&self) -> bool {
        self.fail.is_none()
    }
}

/// What a codon read decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StepKind {
    /// A non-terminal expansion: `choice = codon mod n`.
    Expand,
    /// Genr8's depth-limited expansion: `n` is the number of alternatives
    /// with no non-terminal, `choice` the index (in the full list) of the
    /// one `codon mod n` picked.
    Limited,
    /// A `{ }` decision with counter `c`: `n = c + constant`,
    /// `choice = codon mod n`; the group repeats iff `choice > c`.
    Repeat,
    /// A `[ ]` decision: `n = 2`, included iff `choice = 1`.
    Option,
    /// An edge ID: `nt` is the terminal (`Edge`, `EdgeX`…), `n = max_ID + 1`,
    /// `choice` the ID.
    Edge,
}

impl StepKind {
    /// Whether this is a plain expansion (the kind the traces leave out).
    pub fn is_expand(&self) -> bool {
        *self == StepKind::Expand
    }
}

/// One codon read.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Step {
    /// The non-terminal expanded (for group decisions: the rule the group
    /// belongs to; for edge IDs: the terminal).
    pub nt: String,
    /// The codon's index in the genome (0-based).
    pub pos: usize,
    /// The codon.
    pub codon: u32,
    /// The modulus the codon was reduced by.
    pub n: u32,
    /// What it chose (see [`StepKind`]).
    pub choice: u32,
    /// Depth of `nt` (root = 1; for groups, the depth of their items).
    pub depth: u32,
    /// Left out of the JSON for plain expansions.
    #[serde(default = "expand", skip_serializing_if = "StepKind::is_expand")]
    pub kind: StepKind,
}

fn expand() -> StepKind {
    StepKind::Expand
}

/// A full mapping trace, with the field names of the golden traces.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Mapping {
    /// `true` if mapping finished with no non-terminal left.
    pub valid: bool,
    /// Why not, when invalid.
    pub fail: Option<Failure>,
    /// The output text, or `None` when invalid.
    pub phenotype: Option<String>,
    /// Codon reads, re-reads after wrapping included (= `steps.len()`).
    pub used_codons: usize,
    /// Times reading went back to codon 0 (and then read one).
    pub wraps: u32,
    /// The `choice` of every step.
    pub choices: Vec<u32>,
    /// Every codon read in order.
    pub steps: Vec<Step>,
}

/// The codons one non-terminal expansion reads: its own choice and every
/// codon read below it in the derivation tree, `start..end` of the genome.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Subtree<'a> {
    /// The non-terminal expanded, e.g. `<Modifier>`.
    pub nt: &'a str,
    /// Genome index of the expansion's own codon.
    pub start: usize,
    /// One past the last codon of the subtree.
    pub end: usize,
}

impl Mapping {
    /// Every non-terminal expansion but the root's, in reading order, with
    /// the contiguous codons its subtree reads (the mapping reads depth
    /// first, so a subtree's codons are the steps from its expansion to the
    /// next step at its depth or above). Replacing those codons by the
    /// codons of another expansion of the same non-terminal changes that
    /// subtree and leaves the reading of what follows aligned: grammatical
    /// evolution's subtree operators. Empty when reading wrapped (positions
    /// then repeat) or the mapping failed.
    pub fn subtrees(&self) -> Vec<Subtree<'_>> {
        if !self.valid || self.wraps > 0 {
            return Vec::new();
        }
        let steps = &self.steps;
        let mut out = Vec::new();
        for (i, s) in steps.iter().enumerate() {
            if !matches!(s.kind, StepKind::Expand | StepKind::Limited) || s.depth <= 1 {
                continue;
            }
            let end = steps[i + 1..].iter().find(|t| t.depth <= s.depth).map_or(self.used_codons, |t| t.pos);
            out.push(Subtree { nt: &s.nt, start: s.pos, end });
        }
        out
    }
}
