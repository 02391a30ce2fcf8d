//! The settings of a scene that belong to its grammar's formalism rather
//! than to a scorer or an optimizer: the top-level keys `phenotype`,
//! `environment`, `steps` and `box`, the `[mapper]` table, and the
//! `[limits]` table. Every row of the formalism table says which of them
//! its scenes may set ([`crate::formalism::Formalism::scene_keys`],
//! [`crate::formalism::Formalism::limit_keys`]); the others are refused at
//! their position, naming the formalisms they apply to.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The language a GE grammar (`.bnf`) writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Phenotype {
    /// A HEMLS rewrite system (`.gr8`), grown into a surface.
    Gr8,
    /// An L-system (`.ls`), derived and drawn with the turtle.
    Ls,
}

impl Phenotype {
    /// The file ending of the phenotype, e.g. `gr8`.
    pub fn extension(self) -> &'static str {
        match self {
            Phenotype::Gr8 => "gr8",
            Phenotype::Ls => "ls",
        }
    }
}

/// The formalism's top-level keys of a scene and its `[mapper]` table.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(default)]
pub struct ModelSettings {
    /// `.bnf` grammars: the language the grammar writes.
    pub phenotype: Option<Phenotype>,
    /// `phenotype = "gr8"`: the growth environment (settings, charges,
    /// boundaries, limits), relative to the scene.
    pub environment: Option<PathBuf>,
    /// `phenotype = "gr8"`: growth steps (overrides the environment's);
    /// graph grammars: the derivation's step limit (overrides `steps:`).
    pub steps: Option<u32>,
    /// Box-split grammars: the box to derive in, two opposite corners
    /// (inclusive) `[x0, y0, z0, x1, y1, z1]`.
    #[serde(rename = "box")]
    pub box_corners: Option<[i32; 6]>,
    /// How codons are read.
    pub mapper: MapperConfig,
}

/// The top-level keys of [`ModelSettings`] (`mapper` is its table).
pub const MODEL_KEYS: [&str; 5] = ["phenotype", "environment", "steps", "box", "mapper"];

/// `[mapper]`: how codons are read.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MapperConfig {
    /// How often reading may wrap back to the first codon (GE default: 4
    /// with Genr8's extensions, else 2; box-split and graph grammars: 2).
    #[serde(default)]
    pub max_wraps: Option<u32>,
    /// GE only. With Genr8's extensions: the derivation-tree depth from
    /// which only productions without non-terminals are chosen (default 8);
    /// without them: the depth past which an individual is invalid
    /// (default none).
    #[serde(default)]
    pub max_depth: Option<u32>,
    /// GE only: Genr8's mapping extensions (`{ }` and `[ ]` decided by
    /// codons, Edge IDs, EdgeX/Y/Z binding, depth-limited choice, repair,
    /// spaced tokens). Default: on for `phenotype = "gr8"`, off for `"ls"`.
    #[serde(default)]
    pub genr8: Option<bool>,
    /// GE only: which codon each decision reads, `"sequential"` (standard
    /// GE, the default) or `"per-choice"` (one interleaved stream per
    /// non-terminal, group and edge IDs; [`genform_ge::CodonLayout`]).
    #[serde(default)]
    pub layout: Option<genform_ge::CodonLayout>,
}

/// `[limits]`: what one derivation may grow to, each replacing the
/// grammar's (or the formalism's) default when given. Derivation-tree
/// grammars read `genes`, `depth` and `primitives`; codon grammars the
/// limits of what they grow (their row's [`crate::formalism::Formalism::limit_keys`]).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneLimits {
    /// Most genes.
    #[serde(default)]
    pub genes: Option<usize>,
    /// Deepest gene.
    #[serde(default)]
    pub depth: Option<usize>,
    /// Most primitives (derivation trees: of the model; `.ls` phenotypes:
    /// drawn, default 20,000).
    #[serde(default)]
    pub primitives: Option<usize>,
    /// gr8: most surface vertices (default: the environment file's).
    #[serde(default)]
    pub vertices: Option<usize>,
    /// gr8: most surface edges (default: the environment file's).
    #[serde(default)]
    pub edges: Option<usize>,
    /// gr8: most surface faces (default: the environment file's).
    #[serde(default)]
    pub faces: Option<usize>,
    /// ls: longest module string (default 200,000).
    #[serde(default)]
    pub modules: Option<usize>,
    /// Graph grammars: most vertices + edges (default 20,000).
    #[serde(default)]
    pub elements: Option<usize>,
}

/// Bytes per drawn primitive of a scene (an affine transform, a primitive
/// id and a tag), with the voxelizer's share.
pub const PRIMITIVE_BYTES: u64 = 96;

/// Every `[limits]` key: bytes one item may take, and what the items are
/// (for the memory budget's refusals).
pub const LIMIT_KEYS: [(&str, u64, &str); 8] = [
    ("genes", crate::memory::GENE_BYTES, "genes"),
    ("depth", 0, "levels"),
    ("primitives", PRIMITIVE_BYTES, "primitives"),
    ("vertices", 64, "surface vertices"),
    ("edges", 64, "surface half-edge pairs"),
    ("faces", 32, "surface faces"),
    ("modules", 32, "L-system modules"),
    ("elements", 64, "graph vertices and edges"),
];

impl SceneLimits {
    /// The value of `key` (one of [`LIMIT_KEYS`]).
    pub fn get(&self, key: &str) -> Option<usize> {
        match key {
            "genes" => self.genes,
            "depth" => self.depth,
            "primitives" => self.primitives,
            "vertices" => self.vertices,
            "edges" => self.edges,
            "faces" => self.faces,
            "modules" => self.modules,
            "elements" => self.elements,
            _ => None,
        }
    }

    /// The keys given, in [`LIMIT_KEYS`] order.
    pub fn given(&self) -> Vec<&'static str> {
        LIMIT_KEYS.iter().map(|(k, _, _)| *k).filter(|k| self.get(k).is_some()).collect()
    }

    /// The derivation-tree limits as overrides of a grammar's.
    pub fn overrides(&self) -> LimitOverrides {
        LimitOverrides { max_genes: self.genes, max_depth: self.depth, max_primitives: self.primitives }
    }
}

/// Derivation-tree limits given on the command line or in a scene's
/// `[limits]`, each replacing the grammar's own when set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LimitOverrides {
    /// Most genes.
    pub max_genes: Option<usize>,
    /// Deepest gene.
    pub max_depth: Option<usize>,
    /// Most primitives.
    pub max_primitives: Option<usize>,
}

impl LimitOverrides {
    /// `base` with the set overrides applied.
    pub fn apply(&self, base: genform_core::Limits) -> genform_core::Limits {
        genform_core::Limits {
            max_genes: self.max_genes.unwrap_or(base.max_genes),
            max_depth: self.max_depth.unwrap_or(base.max_depth),
            max_primitives: self.max_primitives.unwrap_or(base.max_primitives),
        }
    }

    /// `self` where set, `other` elsewhere.
    pub fn or(self, other: LimitOverrides) -> LimitOverrides {
        LimitOverrides {
            max_genes: self.max_genes.or(other.max_genes),
            max_depth: self.max_depth.or(other.max_depth),
            max_primitives: self.max_primitives.or(other.max_primitives),
        }
    }
}
