//! Driving an optimizer until a stop condition holds.

use crate::objective::Objective;
use crate::optimizer::Optimizer;
use crate::stats::GenerationStats;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// When [`run`] stops: whichever condition holds first. Conditions are
/// checked between generations, so a run may pass the budget or the
/// evaluation count by up to one generation.
#[derive(Clone, Copy, Debug)]
pub struct Stop<'a> {
    /// Stop once this generation index is reached (the initial population
    /// is generation 0, so `Some(130)` is the reference's 130 generations).
    pub generations: Option<usize>,
    /// Stop once this much wall time has passed since the run began.
    pub budget: Option<Duration>,
    /// Stop once the optimizer has made this many evaluations in all.
    pub evaluations: Option<u64>,
    /// Stop when set (e.g. by a Ctrl-C handler); polled between generations.
    pub cancel: &'a AtomicBool,
}

/// Why [`run`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// [`Stop::generations`] was reached.
    Generations,
    /// [`Stop::budget`] was used up.
    Budget,
    /// [`Stop::evaluations`] was reached.
    Evaluations,
    /// [`Stop::cancel`] was set.
    Cancelled,
}

/// What [`run`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunSummary {
    /// Why it stopped.
    pub reason: StopReason,
    /// Generations made in this run (the initial population counts as one).
    pub steps: usize,
    /// The optimizer's generation index at the end.
    pub generation: usize,
    /// The optimizer's evaluations at the end.
    pub evaluations: u64,
    /// Wall time of the run.
    pub elapsed: Duration,
}

/// A run without any limit: it could only end by cancellation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the run has no limit: set a number of generations, a time budget or a number of evaluations")]
pub struct Unbounded;

/// Steps `optimizer` until `stop` holds, calling `on_generation` after each
/// generation with its statistics and the optimizer (to read the population
/// or the best individual). An uninitialized optimizer first makes
/// generation 0; an already advanced one continues.
///
/// Works for any genome type `G` (inferred from the optimizer): tree
/// optimizers with a [`Genome`](genform_core::Genome) objective, codon
/// optimizers with a [`Codons`](crate::ge::Codons) one.
pub fn run<G, P: Optimizer<G>, O: Objective<G>>(
    optimizer: &mut P,
    objective: &O,
    stop: &Stop,
    mut on_generation: impl FnMut(&GenerationStats, &dyn Optimizer<G>),
) -> Result<RunSummary, Unbounded> {
    if stop.generations.is_none() && stop.budget.is_none() && stop.evaluations.is_none() {
        return Err(Unbounded);
    }
    let start = Instant::now();
    let mut steps = 0;
    let reason = loop {
        if let Some(reason) = reached(optimizer, stop, start) {
            break reason;
        }
        let stats = optimizer.step(objective);
        steps += 1;
        on_generation(&stats, &*optimizer);
    };
    Ok(RunSummary {
        reason,
        steps,
        generation: optimizer.generation(),
        evaluations: optimizer.evaluations(),
        elapsed: start.elapsed(),
    })
}

/// The first condition of `stop` that holds for `optimizer` in a run that
/// began at `start`, cancellation first: what [`run`] checks before each
/// generation, for drivers that step an optimizer themselves (e.g. to
/// change the objective between generations).
pub fn reached<G>(optimizer: &impl Optimizer<G>, stop: &Stop, start: Instant) -> Option<StopReason> {
    if stop.cancel.load(Ordering::Relaxed) {
        return Some(StopReason::Cancelled);
    }
    let initialized = optimizer.is_initialized();
    if initialized && stop.generations.is_some_and(|n| optimizer.generation() >= n) {
        return Some(StopReason::Generations);
    }
    if initialized && stop.evaluations.is_some_and(|n| optimizer.evaluations() >= n) {
        return Some(StopReason::Evaluations);
    }
    if stop.budget.is_some_and(|b| start.elapsed() >= b) {
        return Some(StopReason::Budget);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{ShipToy, ship};
    use crate::{Ga, GaConfig, RandomConfig, RandomSearch};
    use genform_core::Limits;

    fn ga() -> Ga {
        let config = GaConfig { population: 20, elitism: Some(4), initial_length: [5, 15], ..GaConfig::default() };
        Ga::new(&ship(), &Limits::default(), config, 1).unwrap()
    }

    fn stop(cancel: &AtomicBool) -> Stop<'_> {
        Stop { generations: None, budget: None, evaluations: None, cancel }
    }

    #[test]
    fn stops_after_the_requested_generations() {
        let cancel = AtomicBool::new(false);
        let mut seen = Vec::new();
        let mut opt = ga();
        let stop = Stop { generations: Some(5), ..stop(&cancel) };
        let summary = run(&mut opt, &ShipToy { target: 10 }, &stop, |s, o| {
            assert_eq!(s.generation, o.generation());
            seen.push(s.generation);
        })
        .unwrap();
        assert_eq!(seen, [0, 1, 2, 3, 4, 5]);
        assert_eq!((summary.reason, summary.steps, summary.generation), (StopReason::Generations, 6, 5));
        // Continuing an advanced optimizer counts from where it is.
        let stop = Stop { generations: Some(7), ..stop };
        let summary = run(&mut opt, &ShipToy { target: 10 }, &stop, |_, _| {}).unwrap();
        assert_eq!((summary.steps, summary.generation), (2, 7));
    }

    #[test]
    fn stops_on_evaluations_budget_or_cancel() {
        let cancel = AtomicBool::new(false);
        let objective = ShipToy { target: 10 };
        let mut opt =
            RandomSearch::new(&ship(), &Limits::default(), RandomConfig { population: 10, ..Default::default() }, 2)
                .unwrap();
        let stop_e = Stop { evaluations: Some(35), generations: Some(100), ..stop(&cancel) };
        let summary = run(&mut opt, &objective, &stop_e, |_, _| {}).unwrap();
        assert_eq!((summary.reason, summary.evaluations), (StopReason::Evaluations, 40));

        let stop_b = Stop { budget: Some(Duration::ZERO), ..stop(&cancel) };
        let summary = run(&mut ga(), &objective, &stop_b, |_, _| panic!("no generation fits a zero budget")).unwrap();
        assert_eq!((summary.reason, summary.steps), (StopReason::Budget, 0));

        let stop_c = Stop { generations: Some(1000), ..stop(&cancel) };
        let summary = run(&mut ga(), &objective, &stop_c, |s, _| {
            if s.generation == 3 {
                cancel.store(true, Ordering::Relaxed);
            }
        })
        .unwrap();
        assert_eq!((summary.reason, summary.generation), (StopReason::Cancelled, 3));
    }

    #[test]
    fn a_run_needs_a_limit() {
        let cancel = AtomicBool::new(false);
        let e = run(&mut ga(), &ShipToy { target: 10 }, &stop(&cancel), |_, _| {}).unwrap_err();
        assert!(e.to_string().contains("no limit"));
    }
}
