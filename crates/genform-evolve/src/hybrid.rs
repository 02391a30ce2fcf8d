//! The hybrid the thesis proposes as future work (§5): SOSMC builds the
//! initial population, the GA evolves it, MH chains polish the best.
//!
//! - *Seed*: one SOSMC sweep (until every particle is complete). Its
//!   particles, closed links reopened, become the GA's generation 0.
//! - *Evolve*: the GA, until its best has not improved for
//!   [`HybridConfig::stagnation`] generations or [`HybridConfig::polish_after`]
//!   of the run's [`Horizon`] is used.
//! - *Polish*: MH chains started from the GA's best distinct individuals.
//!
//! Switching on stagnation or on a share of a generation or evaluation
//! horizon is deterministic; a share of a wall-clock budget is not (the
//! switch happens wherever the clock says).

use crate::config::{ConfigError, GaConfig, HybridConfig, MhConfig, SmcConfig};
use crate::ga::Ga;
use crate::mcmc::Mh;
use crate::objective::Objective;
use crate::optimizer::{Individual, Optimizer};
use crate::rescore::{Rescore, rescored_best};
use crate::smc::{Order, Smc, reopen};
use crate::stats::GenerationStats;
use genform_core::{GeneratorGraph, Limits};
use std::time::{Duration, Instant};

/// How long a run is meant to last, for optimizers that plan phases.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Horizon {
    /// Generations.
    pub generations: Option<usize>,
    /// Wall-clock time.
    pub budget: Option<Duration>,
    /// Objective evaluations.
    pub evaluations: Option<u64>,
}

impl Horizon {
    /// The largest share of any set horizon used so far (0 when none is set).
    pub fn used(&self, generation: usize, evaluations: u64, elapsed: Duration) -> f64 {
        let shares = [
            self.generations.map(|g| generation as f64 / g.max(1) as f64),
            self.budget.map(|b| elapsed.as_secs_f64() / b.as_secs_f64().max(1e-9)),
            self.evaluations.map(|e| evaluations as f64 / e.max(1) as f64),
        ];
        shares.into_iter().flatten().fold(0.0, f64::max)
    }
}

/// The phase the hybrid is in.
#[derive(Clone, Debug)]
pub enum Phase {
    /// SOSMC building the initial population.
    Seed(Smc),
    /// The GA.
    Evolve(Box<Ga>),
    /// MH chains polishing the GA's best.
    Polish(Mh),
}

impl Phase {
    /// Short name: "sosmc", "ga" or "mh".
    pub fn name(&self) -> &'static str {
        match self {
            Phase::Seed(_) => "sosmc",
            Phase::Evolve(_) => "ga",
            Phase::Polish(_) => "mh",
        }
    }

    fn optimizer(&self) -> &dyn Optimizer {
        match self {
            Phase::Seed(o) => o,
            Phase::Evolve(o) => o.as_ref(),
            Phase::Polish(o) => o,
        }
    }
}

/// SOSMC → GA → MH.
#[derive(Clone, Debug)]
pub struct Hybrid {
    graph: GeneratorGraph,
    limits: Limits,
    ga: GaConfig,
    mh: MhConfig,
    config: HybridConfig,
    seed: u64,
    horizon: Horizon,
    phase: Phase,
    started: Option<Instant>,
    generation: Option<usize>,
    /// Evaluations of finished phases.
    done_evaluations: u64,
    best: Option<Individual>,
    stagnant: usize,
    switches: Vec<(usize, &'static str)>,
}

impl Hybrid {
    /// A hybrid in its seeding phase; every configuration is checked now.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        graph: &GeneratorGraph,
        limits: &Limits,
        smc: SmcConfig,
        ga: GaConfig,
        mh: MhConfig,
        config: HybridConfig,
        seed: u64,
        horizon: Horizon,
    ) -> Result<Self, ConfigError> {
        config.validate()?;
        ga.validate()?;
        mh.validate()?;
        let smc = SmcConfig { max_length: smc.max_length.min(ga.max_length), ..smc };
        let seeder = Smc::new(graph, limits, smc, Order::Stochastic, seed)?;
        Ok(Hybrid {
            graph: graph.clone(),
            limits: *limits,
            ga,
            mh,
            config,
            seed,
            horizon,
            phase: Phase::Seed(seeder),
            started: None,
            generation: None,
            done_evaluations: 0,
            best: None,
            stagnant: 0,
            switches: vec![(0, "sosmc")],
        })
    }

    /// The current phase.
    pub fn phase(&self) -> &Phase {
        &self.phase
    }

    /// Where each phase began: (generation, phase name).
    pub fn switches(&self) -> &[(usize, &'static str)] {
        &self.switches
    }

    /// One generation of the current phase, then a phase switch if due.
    pub fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let started = *self.started.get_or_insert_with(Instant::now);
        let stats = match &mut self.phase {
            Phase::Seed(o) => o.step(objective),
            Phase::Evolve(o) => o.step(objective),
            Phase::Polish(o) => o.step(objective),
        };
        let generation = self.generation.map_or(0, |g| g + 1);
        self.generation = Some(generation);
        let improved = match (self.phase.optimizer().best(), &self.best) {
            (Some(b), Some(old)) => b.fitness > old.fitness,
            (Some(_), None) => true,
            _ => false,
        };
        if improved {
            self.best = self.phase.optimizer().best().cloned();
            self.stagnant = 0;
        } else {
            self.stagnant += 1;
        }
        let evaluations = self.done_evaluations + self.phase.optimizer().evaluations();
        self.switch(generation, evaluations, started.elapsed());
        GenerationStats { generation, total_evaluations: evaluations, ..stats }
    }

    fn switch(&mut self, generation: usize, evaluations: u64, elapsed: Duration) {
        let next = match &self.phase {
            Phase::Seed(smc) if smc.is_complete() => {
                let individuals = smc
                    .population()
                    .iter()
                    .map(|p| Individual { genome: reopen(&p.genome), fitness: p.fitness })
                    .collect();
                // No GA restarts: a restart would throw the particles away,
                // and the hybrid hands a stalled GA to MH instead.
                let ga = GaConfig { restart_after: 0, ..self.ga.clone() };
                Ga::from_population(&self.graph, &self.limits, ga, self.seed, individuals)
                    .ok()
                    .map(|ga| Phase::Evolve(Box::new(ga)))
            }
            Phase::Evolve(ga)
                if self.stagnant >= self.config.stagnation
                    || self.horizon.used(generation, evaluations, elapsed) >= self.config.polish_after =>
            {
                let mut states: Vec<Individual> = Vec::new();
                for ind in ga.population() {
                    if states.len() == self.mh.chains {
                        break;
                    }
                    if !states.iter().any(|s| s.genome == ind.genome) {
                        states.push(ind.clone());
                    }
                }
                let bounds = self.mh.length_bounds();
                states.retain(|s| bounds.contains(s.genome.len()));
                (!states.is_empty())
                    .then(|| Mh::from_states(&self.graph, &self.limits, self.mh.clone(), self.seed, states).ok())
                    .flatten()
                    .map(Phase::Polish)
            }
            _ => None,
        };
        if let Some(next) = next {
            self.done_evaluations += self.phase.optimizer().evaluations();
            self.switches.push((generation + 1, next.name()));
            self.phase = next;
            self.stagnant = 0;
        }
    }
}

impl Optimizer for Hybrid {
    fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        Hybrid::step(self, objective)
    }

    fn population(&self) -> &[Individual] {
        self.phase.optimizer().population()
    }

    fn best(&self) -> Option<&Individual> {
        self.best.as_ref()
    }

    fn generation(&self) -> usize {
        self.generation.unwrap_or(0)
    }

    fn evaluations(&self) -> u64 {
        self.done_evaluations + self.phase.optimizer().evaluations()
    }

    fn is_initialized(&self) -> bool {
        self.generation.is_some()
    }
}

impl Rescore for Hybrid {
    /// Re-scores the current phase's optimizer, then the hybrid's best
    /// (which may come from an earlier phase) against the phase's; that
    /// evaluation counts with the finished phases'.
    fn rescore<O: Objective>(&mut self, objective: &O) -> u64 {
        if self.generation.is_none() {
            return 0;
        }
        let evaluations = match &mut self.phase {
            Phase::Seed(o) => o.rescore(objective),
            Phase::Evolve(o) => o.rescore(objective),
            Phase::Polish(o) => o.rescore(objective),
        };
        let phase_best: Vec<Individual> = self.phase.optimizer().best().cloned().into_iter().collect();
        let (best, more) = rescored_best(objective, self.best.take(), &phase_best);
        self.best = best;
        self.done_evaluations += more;
        evaluations + more
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{ShipToy, ship};

    fn hybrid(horizon: Horizon) -> Hybrid {
        let smc = SmcConfig { particles: 60, max_length: 40, ..SmcConfig::default() };
        let ga = GaConfig {
            population: 30,
            elitism: Some(6),
            initial_length: [10, 20],
            max_length: 40,
            ..GaConfig::default()
        };
        let mh = MhConfig { chains: 6, initial_length: [10, 20], max_length: 40, ..MhConfig::default() };
        let config = HybridConfig { stagnation: 15, polish_after: 0.7 };
        Hybrid::new(&ship(), &Limits::default(), smc, ga, mh, config, 3, horizon).unwrap()
    }

    #[test]
    fn runs_every_phase_in_order_and_keeps_the_best() {
        let mut h = hybrid(Horizon { generations: Some(150), ..Horizon::default() });
        let objective = ShipToy { target: 20 };
        let mut last_best = f64::NEG_INFINITY;
        let mut evaluations = 0;
        for g in 0..150 {
            let s = h.step(&objective);
            assert_eq!(s.generation, g);
            assert!(s.total_evaluations >= evaluations);
            evaluations = s.total_evaluations;
            let best = h.best().unwrap().fitness;
            assert!(best >= last_best);
            last_best = best;
        }
        let names: Vec<&str> = h.switches().iter().map(|(_, n)| *n).collect();
        assert_eq!(names, ["sosmc", "ga", "mh"], "{:?}", h.switches());
        assert!(matches!(h.phase(), Phase::Polish(_)));
        assert!(h.switches()[2].0 <= 106, "polish at 70 % of 150 generations at the latest: {:?}", h.switches());
        assert_eq!(h.evaluations(), evaluations);
    }

    #[test]
    fn is_deterministic_with_a_generation_horizon() {
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let mut h = hybrid(Horizon { evaluations: Some(20_000), ..Horizon::default() });
            pool.install(|| {
                for _ in 0..120 {
                    h.step(&ShipToy { target: 20 });
                }
            });
            (h.best().cloned(), h.switches().to_vec())
        };
        assert_eq!(run(1), run(2));
    }

    #[test]
    fn horizon_shares() {
        let h = Horizon { generations: Some(100), budget: Some(Duration::from_secs(10)), evaluations: None };
        assert_eq!(h.used(50, 0, Duration::from_secs(2)), 0.5);
        assert_eq!(h.used(10, 0, Duration::from_secs(8)), 0.8);
        assert_eq!(Horizon::default().used(10, 10, Duration::from_secs(1)), 0.0);
    }
}
