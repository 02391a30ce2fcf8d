//! What optimizers maximize: a fitness per genome.

use genform_core::Genome;

/// A fitness function over genomes; larger is better.
///
/// Optimizers evaluate many genomes in parallel, each worker with its own
/// [`Objective::Scratch`] (voxel grids, scenes, buffers), so `evaluate` can
/// run allocation-free after warm-up. It must be deterministic: the same
/// genome gives the same value, whatever thread evaluates it, because
/// optimizers cache fitness (elites are never re-evaluated) and promise
/// identical results at any thread count.
///
/// A non-finite result (NaN or ±∞, e.g. the genome could not be expressed)
/// marks the individual *invalid*: it gets weight 0 in roulette selection,
/// loses every tournament, sorts last, and is counted apart in statistics.
pub trait Objective: Sync {
    /// Per-worker reusable state.
    type Scratch: Send;

    /// A fresh scratch for one worker.
    fn scratch(&self) -> Self::Scratch;

    /// The fitness of `genome`.
    fn evaluate(&self, genome: &Genome, scratch: &mut Self::Scratch) -> f64;
}

/// An [`Objective`] from a plain function (no scratch), for tests and small
/// experiments.
#[derive(Clone, Copy, Debug)]
pub struct FnObjective<F>(pub F);

impl<F: Fn(&Genome) -> f64 + Sync> Objective for FnObjective<F> {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, genome: &Genome, _: &mut ()) -> f64 {
        (self.0)(genome)
    }
}
