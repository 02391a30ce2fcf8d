//! Re-scoring the GA when the objective changes (see [`crate::rescore`]).

use super::Ga;
use super::epoch::Epoch;
use crate::objective::Objective;
use crate::rescore::{Rescore, reevaluate};

impl Rescore for Ga {
    /// Re-scores the population, the best so far and the champions of
    /// finished epochs (a champion may now beat the old best). The current
    /// epoch starts its stall counts again from the re-scored top, keeping
    /// its phase: progress measured on the old scale says nothing about
    /// the new one.
    fn rescore<O: Objective>(&mut self, objective: &O) -> u64 {
        if self.state.is_empty() {
            return 0;
        }
        let mut evaluations = self.state.rescore(objective);
        let champions = reevaluate(objective, &mut self.champions);
        self.state.count_evaluations(champions);
        self.state.consider_best(&self.champions);
        evaluations += champions;
        let tuning = self.epoch.tuning;
        self.epoch = Epoch::start(&self.config, self.epoch_top());
        self.epoch.tuning |= tuning;
        evaluations
    }
}
