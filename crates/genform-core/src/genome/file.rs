//! The JSON file form of a genome: the serde types of a genome file, a flat
//! list of genes, parents before children, with symbols, slots and
//! parameters by name so files stay readable and survive grammar edits that
//! do not touch the symbols they use.
//!
//! ```json
//! { "format": "genform-genome", "version": 1, "generator": "spaceship",
//!   "genes": [
//!     { "symbol": "S" },
//!     { "symbol": "B", "parent": 0, "slot": "body", "index": 0,
//!       "params": { "size": [1.2, 0.9, 1.4] } } ] }
//! ```
//!
//! The conversion to and from a [`Genome`](super::Genome) is in `json`.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Value of the `format` field.
pub const FORMAT: &str = "genform-genome";
/// Current version of the file format.
pub const VERSION: u32 = 1;

/// A parameter value: a number for scalars, an array for vectors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum JsonValue {
    /// A scalar.
    Scalar(f64),
    /// A vector.
    Vector(Vec<f64>),
}

/// One gene in a genome file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JsonGene {
    /// Symbol name.
    pub symbol: String,
    /// Ordinal of the parent gene in `genes`; absent for the root.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parent: Option<usize>,
    /// Slot of the parent holding this gene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slot: Option<String>,
    /// Which of the slot's links (0 for single slots).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub index: u32,
    /// Parameter values by name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub params: BTreeMap<String, JsonValue>,
    /// Links marked never to be expressed, as `slot` or `slot#index`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub closed: Vec<String>,
}

fn is_zero(v: &u32) -> bool {
    *v == 0
}

/// A whole genome file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GenomeFile {
    /// Always `genform-genome`.
    pub format: String,
    /// File format version.
    pub version: u32,
    /// Name of the generator the genome was made for.
    pub generator: String,
    /// Genes in storage order.
    pub genes: Vec<JsonGene>,
}
