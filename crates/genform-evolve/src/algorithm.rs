//! Every optimizer behind one name, for drivers that pick the algorithm at
//! run time (`genform evolve --algorithm`, `genform compare`).

use crate::config::{ConfigError, GaConfig, HybridConfig, MhConfig, RandomConfig, SmcConfig};
use crate::ga::Ga;
use crate::hybrid::{Horizon, Hybrid};
use crate::map_elites::{MapElites, MapElitesConfig};
use crate::mcmc::Mh;
use crate::objective::Objective;
use crate::optimizer::{Individual, Optimizer};
use crate::random::RandomSearch;
use crate::rescore::Rescore;
use crate::smc::{Order, Smc};
use crate::stats::GenerationStats;
use genform_core::{GeneratorGraph, Limits};
use std::fmt;

/// The search algorithms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Algorithm {
    /// The ShapeGenetics genetic algorithm.
    Ga,
    /// Random search (fresh individuals, keep the best).
    Random,
    /// RJMCMC with parallel tempering.
    Mh,
    /// SMC, fixed growth order.
    Smc,
    /// SOSMC, stochastic growth order.
    Sosmc,
    /// SOSMC → GA → MH.
    Hybrid,
    /// MAP-Elites: the best individual per cell of a descriptor grid.
    MapElites,
}

impl Algorithm {
    /// Every algorithm, in the order reports list them.
    pub const ALL: [Algorithm; 7] = [
        Algorithm::Ga,
        Algorithm::Mh,
        Algorithm::Smc,
        Algorithm::Sosmc,
        Algorithm::Hybrid,
        Algorithm::MapElites,
        Algorithm::Random,
    ];

    /// Lower-case name, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Algorithm::Ga => "ga",
            Algorithm::Random => "random",
            Algorithm::Mh => "mh",
            Algorithm::Smc => "smc",
            Algorithm::Sosmc => "sosmc",
            Algorithm::Hybrid => "hybrid",
            Algorithm::MapElites => "map-elites",
        }
    }
}

impl fmt::Display for Algorithm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The settings of every algorithm (a scene's `[ga]`, `[mh]`, `[smc]`,
/// `[hybrid]` and `[map_elites]` sections); random search mirrors the GA's,
/// MAP-Elites takes its lengths and operators from the GA's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// GA (and random search).
    pub ga: GaConfig,
    /// MH.
    pub mh: MhConfig,
    /// SMC and SOSMC.
    pub smc: SmcConfig,
    /// The hybrid's switching rules.
    pub hybrid: HybridConfig,
    /// MAP-Elites' archive and batch sizes.
    pub map_elites: MapElitesConfig,
}

/// One of the optimizers, chosen at run time.
#[derive(Clone, Debug)]
pub enum AnyOptimizer {
    /// [`Ga`].
    Ga(Ga),
    /// [`RandomSearch`].
    Random(RandomSearch),
    /// [`Mh`].
    Mh(Mh),
    /// [`Smc`], either order.
    Smc(Smc),
    /// [`Hybrid`].
    Hybrid(Box<Hybrid>),
    /// [`MapElites`].
    MapElites(MapElites),
}

impl AnyOptimizer {
    /// Builds `algorithm` with its settings; `horizon` is what the run will
    /// be stopped by (only the hybrid plans with it).
    pub fn new(
        algorithm: Algorithm,
        graph: &GeneratorGraph,
        limits: &Limits,
        settings: &Settings,
        seed: u64,
        horizon: Horizon,
    ) -> Result<Self, ConfigError> {
        let s = settings;
        Ok(match algorithm {
            Algorithm::Ga => AnyOptimizer::Ga(Ga::new(graph, limits, s.ga.clone(), seed)?),
            Algorithm::Random => {
                AnyOptimizer::Random(RandomSearch::new(graph, limits, RandomConfig::like(&s.ga), seed)?)
            }
            Algorithm::Mh => AnyOptimizer::Mh(Mh::new(graph, limits, s.mh.clone(), seed)?),
            Algorithm::Smc => AnyOptimizer::Smc(Smc::new(graph, limits, s.smc.clone(), Order::Fixed, seed)?),
            Algorithm::Sosmc => AnyOptimizer::Smc(Smc::new(graph, limits, s.smc.clone(), Order::Stochastic, seed)?),
            Algorithm::Hybrid => AnyOptimizer::Hybrid(Box::new(Hybrid::new(
                graph,
                limits,
                s.smc.clone(),
                s.ga.clone(),
                s.mh.clone(),
                s.hybrid.clone(),
                seed,
                horizon,
            )?)),
            Algorithm::MapElites => {
                AnyOptimizer::MapElites(MapElites::new(graph, limits, &s.ga, s.map_elites.clone(), seed)?)
            }
        })
    }

    fn inner(&self) -> &dyn Optimizer {
        match self {
            AnyOptimizer::Ga(o) => o,
            AnyOptimizer::Random(o) => o,
            AnyOptimizer::Mh(o) => o,
            AnyOptimizer::Smc(o) => o,
            AnyOptimizer::Hybrid(o) => o.as_ref(),
            AnyOptimizer::MapElites(o) => o,
        }
    }
}

impl Optimizer for AnyOptimizer {
    fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        match self {
            AnyOptimizer::Ga(o) => o.step(objective),
            AnyOptimizer::Random(o) => o.step(objective),
            AnyOptimizer::Mh(o) => o.step(objective),
            AnyOptimizer::Smc(o) => o.step(objective),
            AnyOptimizer::Hybrid(o) => o.step(objective),
            AnyOptimizer::MapElites(o) => o.step(objective),
        }
    }

    fn population(&self) -> &[Individual] {
        self.inner().population()
    }

    fn champions(&self) -> &[Individual] {
        self.inner().champions()
    }

    fn best(&self) -> Option<&Individual> {
        self.inner().best()
    }

    fn generation(&self) -> usize {
        self.inner().generation()
    }

    fn evaluations(&self) -> u64 {
        self.inner().evaluations()
    }

    fn is_initialized(&self) -> bool {
        self.inner().is_initialized()
    }
}

impl Rescore for AnyOptimizer {
    fn rescore<O: Objective>(&mut self, objective: &O) -> u64 {
        match self {
            AnyOptimizer::Ga(o) => o.rescore(objective),
            AnyOptimizer::Random(o) => o.rescore(objective),
            AnyOptimizer::Mh(o) => o.rescore(objective),
            AnyOptimizer::Smc(o) => o.rescore(objective),
            AnyOptimizer::Hybrid(o) => o.rescore(objective),
            AnyOptimizer::MapElites(o) => o.rescore(objective),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{ShipToy, ship};
    use crate::run::{Stop, run};
    use std::sync::atomic::AtomicBool;

    #[test]
    fn every_algorithm_runs_through_the_driver() {
        let settings = Settings {
            ga: GaConfig {
                population: 20,
                elitism: Some(4),
                initial_length: [5, 15],
                max_length: 40,
                ..GaConfig::default()
            },
            mh: MhConfig { chains: 8, initial_length: [5, 15], max_length: 40, ..MhConfig::default() },
            smc: SmcConfig { particles: 30, max_length: 40, ..SmcConfig::default() },
            hybrid: HybridConfig::default(),
            map_elites: MapElitesConfig {
                initial: 20,
                batch: 16,
                descriptors: [
                    crate::map_elites::DescriptorAxis::new("length", 6, [0.0, 40.0]),
                    crate::map_elites::DescriptorAxis::new("wings", 4, [0.0, 8.0]),
                ],
                ..MapElitesConfig::default()
            },
        };
        let cancel = AtomicBool::new(false);
        let stop = Stop { generations: None, budget: None, evaluations: Some(3000), cancel: &cancel };
        for algorithm in Algorithm::ALL {
            let horizon = Horizon { evaluations: stop.evaluations, ..Horizon::default() };
            let mut opt = AnyOptimizer::new(algorithm, &ship(), &Limits::default(), &settings, 1, horizon).unwrap();
            let summary = run(&mut opt, &ShipToy { target: 15 }, &stop, |_, _| {}).unwrap();
            assert!(summary.evaluations >= 3000, "{algorithm}");
            assert!(opt.best().is_some_and(|b| b.fitness.is_finite()), "{algorithm}");
            assert!(!opt.population().is_empty());
        }
    }

    /// A restarting GA behind `AnyOptimizer` hands out its earlier epochs'
    /// champions (the gallery's candidates besides the population).
    #[test]
    fn champions_pass_through() {
        let settings = Settings {
            ga: GaConfig {
                population: 12,
                elitism: Some(2),
                initial_length: [5, 15],
                max_length: 40,
                restart_after: 2,
                ..GaConfig::default()
            },
            ..Settings::default()
        };
        let horizon = Horizon::default();
        let mut opt = AnyOptimizer::new(Algorithm::Ga, &ship(), &Limits::default(), &settings, 3, horizon).unwrap();
        // A flat objective stalls every epoch.
        let flat = crate::objective::FnObjective(|_: &genform_core::Genome| 0.0);
        for _ in 0..12 {
            opt.step(&flat);
        }
        let AnyOptimizer::Ga(ga) = &opt else { unreachable!() };
        assert!(!ga.champions().is_empty());
        assert_eq!(Optimizer::champions(&opt).len(), ga.champions().len());
    }
}
