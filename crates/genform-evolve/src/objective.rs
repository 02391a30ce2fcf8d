//! What optimizers maximize: a fitness per genome.

use genform_core::Genome;

/// A fitness function over genomes of type `G`; larger is better.
///
/// `G` is the representation the optimizer searches: the packed
/// derivation tree [`Genome`] (the default, used by the GA, MH, SMC and
/// random search) or a codon string [`Codons`](crate::ge::Codons) (grammatical
/// evolution). An objective for codons typically maps them through a
/// grammar and scores the result; an optimizer never knows which.
///
/// Optimizers evaluate many genomes in parallel, each worker with its own
/// [`Objective::Scratch`] (voxel grids, scenes, buffers), so `evaluate` can
/// run allocation-free after warm-up. It must be deterministic: the same
/// genome gives the same value, whatever thread evaluates it, because
/// optimizers cache fitness (elites are never re-evaluated, unless the
/// objective itself changes: see [`Rescore`](crate::rescore::Rescore)) and
/// promise identical results at any thread count.
///
/// A non-finite result (NaN or ±∞, e.g. the genome could not be expressed)
/// marks the individual *invalid*: it gets weight 0 in roulette selection,
/// loses every tournament, sorts last, and is counted apart in statistics.
pub trait Objective<G = Genome>: Sync {
    /// Per-worker reusable state.
    type Scratch: Send;

    /// A fresh scratch for one worker.
    fn scratch(&self) -> Self::Scratch;

    /// The fitness of `genome`.
    fn evaluate(&self, genome: &G, scratch: &mut Self::Scratch) -> f64;

    /// The fitness of `genome` and its two behaviour descriptors (what
    /// quality-diversity search such as [`MapElites`](crate::map_elites::MapElites)
    /// spreads its archive over), written into `descriptors`.
    ///
    /// Descriptors that need the derived model (a bounding box, a
    /// primitive count) can only come from the objective: optimizers never
    /// see models. The default knows no descriptors: it writes NaN, which
    /// MAP-Elites files under each axis' lowest bin, so every individual
    /// shares one cell. Like [`Objective::evaluate`], it must be
    /// deterministic.
    fn evaluate_described(&self, genome: &G, scratch: &mut Self::Scratch, descriptors: &mut [f64; 2]) -> f64 {
        *descriptors = [f64::NAN; 2];
        self.evaluate(genome, scratch)
    }

    /// How many leading genes of `genome` decoding reads (a GE mapper's
    /// codons read; the whole genome when reading wrapped), or `None` when
    /// the objective cannot tell. Grammatical evolution crosses over and
    /// mutates inside this region, as PonyGE2's effective operators do: a
    /// change in the unread tail gives the parent's phenotype again. It
    /// must be cheap (mapping, no growth or scoring) and deterministic.
    fn expressed(&self, genome: &G, scratch: &mut Self::Scratch) -> Option<usize> {
        let _ = (genome, scratch);
        None
    }

    /// A hash of what decides `genome`'s model (a GE mapper's phenotype
    /// text), or `None` when the objective cannot tell. Genomes with equal
    /// keys must get the same fitness: grammatical evolution's
    /// `novel_children` with `novel_key = "phenotype"` never evaluates a
    /// key twice, and reuses the fitness it knows for it. Different codons
    /// often write the same phenotype (a codon is read modulo a small
    /// choice count), so this catches duplicates the read codons miss. It
    /// must be cheap (mapping, no growth or scoring) and deterministic.
    fn phenotype_key(&self, genome: &G, scratch: &mut Self::Scratch) -> Option<u64> {
        let _ = (genome, scratch);
        None
    }

    /// The derivation subtrees of `genome` (a GE mapping's non-terminal
    /// expansions, each with the contiguous codons it reads), written into
    /// `out` in reading order; none when the objective cannot tell (the
    /// default) or the mapping wrapped or failed. Grammatical evolution's
    /// subtree mutation (`subtree_mutation`) replaces one subtree's codons
    /// by fresh ones and keeps what the mapping reads after it aligned. It
    /// must be cheap (mapping only) and deterministic.
    fn subtrees(&self, genome: &G, scratch: &mut Self::Scratch, out: &mut Vec<CodonSpan>) {
        let _ = (genome, scratch);
        out.clear();
    }

    /// Initial genome `index` of a sensible (ramped half-and-half)
    /// initialisation, drawn from `rng`: a GE mapper's random derivation
    /// tree under a depth limit ramped up to `plan.max_depth`, unmapped
    /// into codons, plus a random tail; `None` when the objective cannot
    /// write one (the default), and then grammatical evolution draws
    /// random codons. Only the objective knows the grammar. It must be
    /// deterministic in `index` and the state of `rng`.
    fn sensible_genome(
        &self,
        index: usize,
        plan: SensiblePlan,
        rng: &mut genform_core::Rng,
        scratch: &mut Self::Scratch,
    ) -> Option<G> {
        let _ = (index, plan, rng, scratch);
        None
    }
}

/// The limits of one sensible initial genome ([`Objective::sensible_genome`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SensiblePlan {
    /// Deepest derivation-tree limit of the ramp (root = 1).
    pub max_depth: u32,
    /// Codons lie in `0..codon_range`.
    pub codon_range: u32,
    /// Most codons, tail included.
    pub max_length: usize,
}

/// The codons one derivation subtree reads ([`Objective::subtrees`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CodonSpan {
    /// Genome index of the subtree's first codon (its own expansion).
    pub start: usize,
    /// One past its last codon.
    pub end: usize,
}

/// An [`Objective`] from a plain function (no scratch), for tests and small
/// experiments; the closure's argument type picks the genome type, e.g.
/// `FnObjective(|g: &Genome| …)` or `FnObjective(|c: &Codons| …)`.
#[derive(Clone, Copy, Debug)]
pub struct FnObjective<F>(pub F);

impl<G, F: Fn(&G) -> f64 + Sync> Objective<G> for FnObjective<F> {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, genome: &G, _: &mut ()) -> f64 {
        (self.0)(genome)
    }
}
