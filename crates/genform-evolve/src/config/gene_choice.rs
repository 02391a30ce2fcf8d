//! How a move picks the gene it changes ([`GeneChoice`]): a setting of MH
//! ([`MhConfig::gene_choice`](super::MhConfig::gene_choice)) that the GA's
//! regrow mutation uses too. Kept apart from the other settings so the
//! operators can name it without importing the settings, which import the
//! operators.

use serde::{Deserialize, Serialize};

/// How an MCMC move picks the gene it changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GeneChoice {
    /// Uniformly among the eligible genes.
    Uniform,
    /// Talton et al.'s nonterminal selection as the reference implements
    /// it: a depth uniformly among the depths that hold eligible genes, then
    /// a gene uniformly at that depth, so shallow (structural) genes are
    /// changed as often as the many deep ones.
    Level,
}
