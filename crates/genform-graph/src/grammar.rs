//! The compiled grammar: productions with their mother patterns, search
//! plans and daughter options, ready to run.

use crate::graph::{Graph, Value};
use crate::mother::{MEdge, MVertex, PairVector, SpatialPair};
use crate::plan::Plan;
use crate::template::Template;
use genform_core::expr::Program;

/// A compiled graph grammar: the host graph (axiom) and the productions.
#[derive(Clone, Debug)]
pub struct GraphGrammar {
    pub(crate) name: String,
    pub(crate) host: Graph,
    pub(crate) steps: Option<usize>,
    /// Wall-clock time one derivation may take (`time_limit:`, else
    /// [`DEFAULT_TIME_LIMIT`](crate::derive::DEFAULT_TIME_LIMIT)).
    pub(crate) time_limit: std::time::Duration,
    /// Priority groups, lowest priority value first.
    pub(crate) groups: Vec<Group>,
    pub(crate) productions: Vec<Production>,
    /// Global formulas evaluated once per run, in file order.
    pub(crate) globals: Vec<Program>,
    /// The most vertices and edges one application adds (over every
    /// option): what a derivation of n steps reserves room for.
    pub(crate) new_per_step: [usize; 2],
    /// The file it was compiled from, to locate run-time errors.
    pub(crate) source: genform_core::SourceFile,
}

impl GraphGrammar {
    /// The grammar's name (`name:`, else the file name without `.gg.yaml`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The host graph (the axiom).
    pub fn host(&self) -> &Graph {
        &self.host
    }

    /// The global step limit (`steps:`).
    pub fn step_limit(&self) -> Option<usize> {
        self.steps
    }

    /// The wall-clock time one derivation may take (`time_limit:` in
    /// seconds, else [`DEFAULT_TIME_LIMIT`](crate::derive::DEFAULT_TIME_LIMIT)).
    pub fn time_limit(&self) -> std::time::Duration {
        self.time_limit
    }

    /// Replaces the time limit of each derivation (e.g. a caller's own guard).
    pub fn set_time_limit(&mut self, limit: std::time::Duration) {
        self.time_limit = limit;
    }

    /// The productions' names, in file order.
    pub fn production_names(&self) -> impl Iterator<Item = &str> {
        self.productions.iter().map(|p| p.name.as_str())
    }
}

/// Productions of one priority.
#[derive(Clone, Debug)]
pub(crate) struct Group {
    /// Most applications of this group in one derivation.
    pub(crate) cap: Option<usize>,
    pub(crate) members: Vec<usize>,
}

#[derive(Clone, Debug)]
pub(crate) struct Production {
    pub(crate) name: String,
    pub(crate) oldest: bool,
    pub(crate) mv: Vec<MVertex>,
    pub(crate) me: Vec<MEdge>,
    pub(crate) env_len: usize,
    /// Globals this production reads: (slot, global index).
    pub(crate) global_slots: Vec<(u32, usize)>,
    /// Per-run variables: evaluated once at the start of a derivation.
    pub(crate) run_vars: Vec<(u32, Program)>,
    /// Production-level per-application variables.
    pub(crate) app_vars: Vec<(u32, Program)>,
    /// Conditions that read no matched element, checked before searching.
    pub(crate) pre_checks: Vec<Program>,
    pub(crate) conditions: Vec<Program>,
    pub(crate) vectors: Vec<PairVector>,
    pub(crate) spatial: Vec<SpatialPair>,
    /// One search plan per anchor element (vertices, then edges).
    pub(crate) plans: Vec<Plan>,
    pub(crate) options: Vec<Daughter>,
    pub(crate) weights: Vec<f64>,
}

/// How a vertex coordinate is set.
#[derive(Clone, Debug)]
pub(crate) enum Coord {
    /// Unchanged (kept vertices without a layout position).
    Keep,
    /// Automatic placement from the layout position.
    Auto,
    /// A formula.
    Formula(Program),
}

/// How an attribute is set.
#[derive(Clone, Debug)]
pub(crate) enum AttrSpec {
    Value(Value),
    /// A template; one number hole alone gives a number.
    Template(Template),
}

/// How a label is set.
#[derive(Clone, Debug)]
pub(crate) enum LabelSpec {
    Fixed(u32),
    Template(Template),
}

#[derive(Clone, Debug)]
pub(crate) struct DVertex {
    /// The kept mother vertex, or `None` for a new one.
    pub(crate) mother: Option<usize>,
    pub(crate) label: Option<LabelSpec>,
    pub(crate) pos: [Coord; 2],
    /// Where each coordinate's formula is written (`pos:`, `x:`, `y:`), to
    /// locate a non-finite result.
    pub(crate) pos_spans: [Option<genform_core::diag::Span>; 2],
    pub(crate) at: Option<[f64; 2]>,
    pub(crate) attrs: Vec<(u32, AttrSpec)>,
    /// This element's number among all new daughter elements of the
    /// grammar: where a derivation caches the set of its attribute list
    /// when that is all constants.
    pub(crate) list_key: u32,
}

/// An end of a daughter edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum End {
    /// The host vertex matched by mother vertex `i`.
    Mother(usize),
    /// New daughter vertex `i` (index into the daughter's new vertices).
    New(usize),
}

#[derive(Clone, Debug)]
pub(crate) struct DEdge {
    /// The kept mother edge, or `None` for a new one.
    pub(crate) mother: Option<usize>,
    pub(crate) from: End,
    pub(crate) to: End,
    /// `None`: keep the matched edge's (kept edges only).
    pub(crate) directed: Option<bool>,
    pub(crate) label: Option<LabelSpec>,
    pub(crate) attrs: Vec<(u32, AttrSpec)>,
    /// As [`DVertex::list_key`].
    pub(crate) list_key: u32,
}

/// One right-hand side of a production.
#[derive(Clone, Debug)]
pub(crate) struct Daughter {
    pub(crate) vars: Vec<(u32, Program)>,
    pub(crate) delete_vertices: Vec<usize>,
    pub(crate) delete_edges: Vec<usize>,
    pub(crate) kept_vertices: Vec<DVertex>,
    pub(crate) kept_edges: Vec<DEdge>,
    pub(crate) new_vertices: Vec<DVertex>,
    pub(crate) new_edges: Vec<DEdge>,
    /// Whether any vertex is placed automatically.
    pub(crate) placement: bool,
}
