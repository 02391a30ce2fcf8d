//! Parallel evaluation of new individuals.

use crate::objective::Objective;
use genform_core::Genome;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// A new individual; `fitness` is already known when it is an unchanged copy.
pub(crate) struct Child<G = Genome> {
    pub genome: G,
    pub fitness: Option<f64>,
}

/// Evaluates the children without a fitness on the current rayon pool, one
/// scratch per worker task; returns how many were evaluated and the time.
/// Results land in the children's own slots, so the order never depends on
/// scheduling.
pub(crate) fn evaluate<G: Send + Sync, O: Objective<G>>(objective: &O, children: &mut [Child<G>]) -> (u64, Duration) {
    let start = Instant::now();
    let count = children.iter().filter(|c| c.fitness.is_none()).count() as u64;
    children.par_iter_mut().for_each_init(
        || objective.scratch(),
        |scratch, c| {
            if c.fitness.is_none() {
                c.fitness = Some(objective.evaluate(&c.genome, scratch));
            }
        },
    );
    (count, start.elapsed())
}
