//! SMC and SOSMC (Ritchie et al. 2015) on derivation-tree genomes, as the
//! thesis frames them (§3.5.1): each particle is an individual whose genome
//! grows one decision at a time.
//!
//! A particle starts as the root gene. Growing it repeatedly takes an
//! *open* link (not yet decided), expresses it with its slot's probability
//! (a new gene with parameters drawn from their distributions) or marks it
//! [`Link::Closed`] (never expressed), until a gene that emits geometry
//! appears or no link is open. Links that would pass the depth or length
//! limit are closed. [`Order::Fixed`] (SMC) takes the first open link of the
//! most recently added gene that has one — depth-first program order, the
//! reference's and Ritchie's "eager" futures; [`Order::Stochastic`] (SOSMC)
//! takes an open link uniformly at random.
//!
//! After every growth step the particles are evaluated and resampled
//! systematically by weight ([`resample::weights`]: `exp(f / T)` or
//! shifted fitness). When every particle is complete the sweep is over and
//! the next step starts a fresh one, so budgets larger than one sweep keep
//! searching; the best individual ever evaluated is kept throughout.

pub mod resample;
#[cfg(test)]
mod tests;

use crate::config::{ConfigError, SmcConfig, room};
use crate::evaluate::{Child, evaluate};
use crate::objective::Objective;
use crate::operators::{Connection, grow_one};
use crate::optimizer::{Individual, Optimizer, length_capped, sort_population, update_best};
use crate::rescore::Rescore;
use crate::stats::GenerationStats;
use genform_core::genome::{GenePos, Link};
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use rayon::prelude::*;
use std::time::Instant;

/// Stream ids: particle `i` of sweep `s` at step `t` grows from
/// `(seed, SMC_GROW, s, t, i)`; the resampling after that step uses
/// `(seed, SMC_RESAMPLE, s, t)`.
pub const SMC_GROW: u64 = 0x534d_0001;
/// See [`SMC_GROW`].
pub const SMC_RESAMPLE: u64 = 0x534d_0002;

/// Which open link a particle grows next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// SMC: depth-first program order.
    Fixed,
    /// SOSMC: uniformly among the open links.
    Stochastic,
}

/// SMC or SOSMC over one generator graph.
#[derive(Clone, Debug)]
pub struct Smc {
    graph: GeneratorGraph,
    limits: Limits,
    config: SmcConfig,
    order: Order,
    seed: u64,
    /// Particles, best first after each step.
    particles: Vec<Individual>,
    sweep: usize,
    /// Growth steps made in the current sweep.
    steps: usize,
    generation: usize,
    evaluations: u64,
    best: Option<Individual>,
}

impl Smc {
    /// A sampler with no particles yet.
    pub fn new(
        graph: &GeneratorGraph,
        limits: &Limits,
        config: SmcConfig,
        order: Order,
        seed: u64,
    ) -> Result<Self, ConfigError> {
        config.validate()?;
        let particles = room(config.particles, "particles", "particles")?;
        Ok(Smc {
            graph: graph.clone(),
            limits: length_capped(limits, config.max_length),
            config,
            order,
            seed,
            particles,
            sweep: 0,
            steps: 0,
            generation: 0,
            evaluations: 0,
            best: None,
        })
    }

    /// Completed sweeps plus the current one.
    pub fn sweeps(&self) -> usize {
        self.sweep + usize::from(!self.particles.is_empty())
    }

    /// Whether every particle is complete (no open link).
    pub fn is_complete(&self) -> bool {
        !self.particles.is_empty() && self.particles.iter().all(|p| is_complete(&p.genome))
    }

    /// One growth step of every particle, evaluation and resampling; starts
    /// a new sweep when there are no particles or all are complete.
    pub fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let fresh = self.particles.is_empty() || self.is_complete();
        if fresh {
            if !self.particles.is_empty() {
                self.sweep += 1;
            }
            self.steps = 0;
            // In the room allocated when the sampler was made (see `room`).
            self.particles.clear();
            self.particles.resize(self.config.particles, Individual { genome: Genome::new(), fitness: f64::NAN });
        }
        let start = Instant::now();
        let (graph, limits, order) = (&self.graph, &self.limits, self.order);
        let (seed, sweep, steps) = (self.seed, self.sweep as u64, self.steps as u64);
        let mut children: Vec<Child> = self
            .particles
            .par_iter()
            .enumerate()
            .map(|(i, p)| {
                let mut rng = Rng::stream(seed, &[SMC_GROW, sweep, steps, i as u64]);
                let mut genome = if fresh {
                    let mut params = Vec::new();
                    graph.draw_params(graph.root, &mut rng, &mut params);
                    Genome::with_root(graph, graph.root, &params)
                } else {
                    p.genome.clone()
                };
                let changed = advance(&mut genome, graph, limits, order, &mut rng);
                Child { genome, fitness: (!changed && !fresh).then_some(p.fitness) }
            })
            .collect();
        let reproduction_time = start.elapsed();
        let (evaluations, eval_time) = evaluate(objective, &mut children);
        self.particles = children
            .into_iter()
            .map(|c| Individual { genome: c.genome, fitness: c.fitness.expect("evaluated") })
            .collect();
        sort_population(&mut self.particles);
        update_best(&mut self.best, &self.particles);
        self.generation = if fresh && self.sweep == 0 { 0 } else { self.generation + 1 };
        self.evaluations += evaluations;
        let stats = GenerationStats::of_population(self.generation, &self.particles);

        let fitness: Vec<f64> = self.particles.iter().map(|p| p.fitness).collect();
        let w = resample::weights(&fitness, self.config.weight, self.config.temperature);
        let ess = resample::effective_size(&w);
        let mut rng = Rng::stream(self.seed, &[SMC_RESAMPLE, sweep, steps]);
        let picks = resample::systematic(&w, self.config.particles, &mut rng);
        // Picks are increasing, so the particles stay sorted best first.
        self.particles = picks.into_iter().map(|i| self.particles[i].clone()).collect();
        self.steps += 1;
        GenerationStats {
            evaluations,
            total_evaluations: self.evaluations,
            eval_time,
            reproduction_time,
            ess: Some(ess),
            ..stats
        }
    }
}

impl Optimizer for Smc {
    fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        Smc::step(self, objective)
    }

    fn population(&self) -> &[Individual] {
        &self.particles
    }

    fn best(&self) -> Option<&Individual> {
        self.best.as_ref()
    }

    fn generation(&self) -> usize {
        self.generation
    }

    fn evaluations(&self) -> u64 {
        self.evaluations
    }
}

impl Rescore for Smc {
    /// Re-scores the particles (best first again) and the best. Weights are
    /// computed from the particles' fitness at each resampling, so the next
    /// one weighs them by the new values; copies made by the last
    /// resampling are evaluated once.
    fn rescore<O: Objective>(&mut self, objective: &O) -> u64 {
        crate::rescore::rescore_population(objective, &mut self.particles, &mut self.best, &mut self.evaluations)
    }
}

/// Whether `genome` has no open (undecided) link.
pub fn is_complete(genome: &Genome) -> bool {
    genome.iter().all(|g| g.links().all(|l| l != Link::Empty))
}

/// The open links of `genome` as `(gene, link)`, in storage order.
pub fn open_links(genome: &Genome) -> Vec<(GenePos, usize)> {
    links_in(genome, Link::Empty)
}

/// The links of `genome` in `state` (empty or closed), in storage order.
fn links_in(genome: &Genome, state: Link) -> Vec<(GenePos, usize)> {
    let mut out = Vec::new();
    for g in genome.iter() {
        out.extend(g.links().enumerate().filter(|(_, l)| *l == state).map(|(i, _)| (g.pos, i)));
    }
    out
}

/// The link `order` grows next, `None` when the genome is complete.
pub fn next_open(genome: &Genome, order: Order, rng: &mut Rng) -> Option<(GenePos, usize)> {
    match order {
        Order::Fixed => {
            // Genes are stored in creation order: the last one with an open
            // link is the most recent, as in a depth-first derivation.
            let mut last = None;
            for g in genome.iter() {
                if let Some(i) = g.links().position(|l| l == Link::Empty) {
                    last = Some((g.pos, i));
                }
            }
            last
        }
        Order::Stochastic => {
            let open = open_links(genome);
            (!open.is_empty()).then(|| open[rng.index(open.len())])
        }
    }
}

/// Grows `genome` until a gene that emits geometry is added or no link is
/// open; returns whether anything was decided.
pub fn advance(genome: &mut Genome, graph: &GeneratorGraph, limits: &Limits, order: Order, rng: &mut Rng) -> bool {
    let mut changed = false;
    let mut params = Vec::new();
    while let Some((pos, link)) = next_open(genome, order, rng) {
        changed = true;
        let spec = graph.symbol(genome.gene(pos).symbol());
        let (slot, _) = spec.slot_of_link(link).expect("link of its symbol");
        let slot = &spec.slots[slot];
        let fits = genome.depth(pos) < limits.max_depth && genome.len() < limits.max_genes;
        if !(rng.bernoulli(slot.prob) && fits) {
            genome.set_closed(pos, link, true);
            continue;
        }
        let target = slot.target;
        grow_one(genome, graph, Connection { parent: pos, link }, target, rng, &mut params);
        if graph.symbol(target).emits_geometry {
            break;
        }
    }
    changed
}

/// `genome` with every closed link reopened, so other optimizers (which
/// grow into empty links) can continue from an SMC particle.
pub fn reopen(genome: &Genome) -> Genome {
    let mut g = genome.clone();
    for (pos, link) in links_in(genome, Link::Closed) {
        g.set_closed(pos, link, false);
    }
    g
}
