//! Reversible-jump MCMC (Talton et al. 2011) on derivation-tree genomes,
//! run as the thesis frames it (§3.5.2): each chain is an individual, a
//! generation is one move per chain.
//!
//! Each chain `i` samples `π_i(x) ∝ prior(x) · exp(β_i f(x))` restricted to
//! the support (the length bounds and the derivation limits), where the
//! prior is the generator graph's: every link expressed with its slot
//! probability, every parameter from its distribution.
//!
//! **Moves** (module `moves`), with gene `v` picked uniformly or
//! level-biased (`P(v | x)`):
//! - *diffusion*: new parameters for `v` (redrawn, or a Gaussian drift of
//!   the continuous ones). Acceptance `min(1, exp(β Δf) · prior ratio of
//!   the drifted values)`; the choice probabilities cancel (same structure).
//! - *jump*: regrow everything below `v` from the prior, keeping the
//!   parameters of genes at unchanged places. The prior of the regrown
//!   part cancels against its proposal, so acceptance is
//!   `min(1, exp(β Δf) · P(v | y) / P(v | x))` — exact per chosen gene, the
//!   gene being identified by its path in both states.
//! - *delayed rejection* (Tierney & Mira 1999, Green & Mira 2001): when a
//!   jump to `y₁` is rejected, a second jump at the same `v` proposes `y₂`,
//!   accepted with
//!   `min(1, exp(β(f₂ − f)) · P(v|y₂)/P(v|x) · (1 − α(y₂→y₁)) / (1 − α(x→y₁)))`.
//!   The prior terms cancel only when every gene of `y₁` sits at a place
//!   that `x` and `y₂` both have or both lack; otherwise `y₁` shares drawn
//!   values with just one of them, the reverse path `y₂ → y₁ → x` has no
//!   matching density, and the second stage is rejected. (The χ² tests
//!   caught the asymmetric version of this rule.)
//! - *parallel tempering*: after the moves, adjacent chains (alternating
//!   even and odd pairs) propose to swap states, accepted with
//!   `min(1, exp((β_i − β_j)(f_j − f_i)))`.
//! - *annealing*: every `β_i` is multiplied by `anneal` after each
//!   generation.
//!
//! With a flat fitness and `β` fixed, every chain's stationary distribution
//! is the (truncated) prior; the χ² test in `tests` checks it.

pub(crate) mod moves;
#[cfg(test)]
mod tests;

use crate::config::{ConfigError, MhConfig, room};
use crate::evaluate::{Child, evaluate};
use crate::objective::Objective;
use crate::operators::{LengthBounds, initial};
use crate::optimizer::{Individual, Optimizer, length_capped, sort_population, update_best};
use crate::rescore::{Rescore, reevaluate, rescored_best};
use crate::stats::{GenerationStats, MoveCounts};
use genform_core::genome::GenePos;
use genform_core::{GeneratorGraph, Genome, Limits, Rng};
use moves::Eligible;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// Stream ids: chain `i` starts from `(seed, MH_INIT, i)`; its move in
/// generation `g` uses `(seed, MH_MOVE, g, i)`; the swaps of generation `g`
/// use `(seed, MH_SWAP, g)`.
pub const MH_INIT: u64 = 0x4d48_0001;
/// See [`MH_INIT`].
pub const MH_MOVE: u64 = 0x4d48_0002;
/// See [`MH_INIT`].
pub const MH_SWAP: u64 = 0x4d48_0003;

/// RJMCMC with parallel tempering over one generator graph.
#[derive(Clone, Debug)]
pub struct Mh {
    graph: GeneratorGraph,
    limits: Limits,
    config: MhConfig,
    seed: u64,
    /// Chain `i` runs at inverse temperature `betas[i]` (coldest first).
    chains: Vec<Individual>,
    betas: Vec<f64>,
    /// The chains sorted best first.
    sorted: Vec<Individual>,
    generation: usize,
    evaluations: u64,
    best: Option<Individual>,
}

impl Mh {
    /// Chains not yet started; the first step draws and evaluates them.
    pub fn new(graph: &GeneratorGraph, limits: &Limits, config: MhConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        // A probe: the chains drawn at the first step take this room's place.
        let chains = room(config.chains, "chains", "chains")?;
        Ok(Mh {
            graph: graph.clone(),
            limits: length_capped(limits, config.max_length),
            config,
            seed,
            chains,
            betas: Vec::new(),
            sorted: Vec::new(),
            generation: 0,
            evaluations: 0,
            best: None,
        })
    }

    /// Chains started from given states (e.g. the best individuals of
    /// another optimizer), one per state, with the fitness they carry.
    pub fn from_states(
        graph: &GeneratorGraph,
        limits: &Limits,
        config: MhConfig,
        seed: u64,
        states: Vec<Individual>,
    ) -> Result<Self, ConfigError> {
        let config = MhConfig { chains: states.len(), ..config };
        let mut mh = Mh::new(graph, limits, config, seed)?;
        mh.start(states, 0);
        Ok(mh)
    }

    /// The inverse temperature of each chain, coldest first.
    pub fn betas(&self) -> &[f64] {
        &self.betas
    }

    /// The chains' current states, coldest first.
    pub fn chains(&self) -> &[Individual] {
        &self.chains
    }

    fn start(&mut self, chains: Vec<Individual>, evaluations: u64) {
        let n = chains.len();
        let cold = match self.config.temperature {
            Some(t) => t,
            None => spread(&chains).map_or(1.0, |sd| sd / self.config.ladder),
        };
        self.betas = (0..n)
            .map(|i| {
                let rung = if n > 1 { i as f64 / (n - 1) as f64 } else { 0.0 };
                1.0 / (cold * self.config.ladder.powf(rung))
            })
            .collect();
        self.chains = chains;
        self.generation = 0;
        self.evaluations = evaluations;
        self.best = None;
        self.refresh();
    }

    fn refresh(&mut self) {
        self.sorted.clone_from(&self.chains);
        sort_population(&mut self.sorted);
        update_best(&mut self.best, &self.sorted);
    }

    fn initialize<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        let start = Instant::now();
        let (graph, limits, length, seed) = (&self.graph, &self.limits, self.config.initial_length, self.seed);
        let mut children: Vec<Child> = (0..self.config.chains)
            .into_par_iter()
            .map(|i| Child {
                genome: initial(graph, limits, length, &mut Rng::stream(seed, &[MH_INIT, i as u64])),
                fitness: None,
            })
            .collect();
        let reproduction_time = start.elapsed();
        let (evaluations, eval_time) = evaluate(objective, &mut children);
        let chains =
            children.into_iter().map(|c| Individual { genome: c.genome, fitness: c.fitness.expect("evaluated") });
        self.start(chains.collect(), evaluations);
        self.stats(evaluations, eval_time, reproduction_time, MoveCounts::default())
    }

    /// One move per chain, then swaps and annealing; the first call starts
    /// the chains.
    pub fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        if self.chains.is_empty() {
            return self.initialize(objective);
        }
        let generation = self.generation + 1;
        let start = Instant::now();
        let mover = Mover { graph: &self.graph, limits: &self.limits, config: &self.config };
        let seed = self.seed;
        let outcomes: Vec<(MoveCounts, u64)> = self
            .chains
            .par_iter_mut()
            .zip(self.betas.par_iter())
            .enumerate()
            .map_init(
                || objective.scratch(),
                |scratch, (i, (chain, &beta))| {
                    let mut rng = Rng::stream(seed, &[MH_MOVE, generation as u64, i as u64]);
                    mover.advance(chain, beta, objective, scratch, &mut rng)
                },
            )
            .collect();
        let eval_time = start.elapsed();
        let mut counts = MoveCounts::default();
        let mut evaluations = 0;
        for (c, e) in outcomes {
            counts += c;
            evaluations += e;
        }
        let swap_start = Instant::now();
        self.swap(generation, &mut counts);
        for b in &mut self.betas {
            *b *= self.config.anneal;
        }
        self.generation = generation;
        self.evaluations += evaluations;
        self.refresh();
        self.stats(evaluations, eval_time, swap_start.elapsed(), counts)
    }

    /// Parallel tempering: adjacent pairs, even pairs in even generations.
    fn swap(&mut self, generation: usize, counts: &mut MoveCounts) {
        let mut rng = Rng::stream(self.seed, &[MH_SWAP, generation as u64]);
        let mut i = generation % 2;
        while i + 1 < self.chains.len() {
            let (fi, fj) = (self.chains[i].fitness, self.chains[i + 1].fitness);
            let (bi, bj) = (self.betas[i], self.betas[i + 1]);
            counts.swaps_proposed += 1;
            let ln_alpha = if fi == fj || bi == bj {
                0.0
            } else if fi.is_finite() && fj.is_finite() {
                (bi - bj) * (fj - fi)
            } else {
                f64::NEG_INFINITY
            };
            if accept(ln_alpha, &mut rng) {
                self.chains.swap(i, i + 1);
                counts.swaps_accepted += 1;
            }
            i += 2;
        }
    }

    fn stats(&self, evaluations: u64, eval_time: Duration, other: Duration, moves: MoveCounts) -> GenerationStats {
        GenerationStats {
            evaluations,
            total_evaluations: self.evaluations,
            eval_time,
            reproduction_time: other,
            moves,
            ..GenerationStats::of_population(self.generation, &self.sorted)
        }
    }
}

impl Optimizer for Mh {
    fn step<O: Objective>(&mut self, objective: &O) -> GenerationStats {
        Mh::step(self, objective)
    }

    fn population(&self) -> &[Individual] {
        &self.sorted
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

impl Rescore for Mh {
    /// Re-scores every chain's state and the best. With an automatic
    /// temperature (`temperature` unset) the inverse temperatures were set
    /// from the chains' fitness spread, so they are scaled by old spread /
    /// new spread: each chain keeps its temperature relative to the fitness
    /// scale, annealing so far included. A set temperature is in units the
    /// user chose and stays.
    fn rescore<O: Objective>(&mut self, objective: &O) -> u64 {
        if self.chains.is_empty() {
            return 0;
        }
        let before = spread(&self.chains);
        let mut evaluations = reevaluate(objective, &mut self.chains);
        if self.config.temperature.is_none()
            && let (Some(old), Some(new)) = (before, spread(&self.chains))
        {
            for b in &mut self.betas {
                *b *= old / new;
            }
        }
        self.sorted.clone_from(&self.chains);
        sort_population(&mut self.sorted);
        let (best, more) = rescored_best(objective, self.best.take(), &self.sorted);
        self.best = best;
        evaluations += more;
        self.evaluations += evaluations;
        evaluations
    }
}

/// Standard deviation of the valid fitness values; `None` when it is 0 or
/// fewer than two are valid.
fn spread(population: &[Individual]) -> Option<f64> {
    let valid: Vec<f64> = population.iter().map(|i| i.fitness).filter(|f| f.is_finite()).collect();
    crate::smc::resample::std_dev(&valid).filter(|sd| *sd > 0.0)
}

/// `β (new − old)`: the log likelihood ratio of a move. Leaving an invalid
/// state is always accepted, entering one never; between invalid states
/// the chain moves freely.
fn tempered(beta: f64, new: f64, old: f64) -> f64 {
    match (new.is_finite(), old.is_finite()) {
        (false, true) => f64::NEG_INFINITY,
        (true, false) => f64::INFINITY,
        (false, false) => 0.0,
        _ if new == old => 0.0,
        _ => beta * (new - old),
    }
}

/// Metropolis test: accept with probability `min(1, exp(ln_alpha))`.
fn accept(ln_alpha: f64, rng: &mut Rng) -> bool {
    ln_alpha >= 0.0 || rng.next_f64() < ln_alpha.exp()
}

/// `ln(1 − min(1, exp(ln_alpha)))`, accurate near 0.
fn ln_reject(ln_alpha: f64) -> f64 {
    if ln_alpha >= 0.0 { f64::NEG_INFINITY } else { (-ln_alpha.exp_m1()).ln() }
}

/// What one chain's move needs.
struct Mover<'a> {
    graph: &'a GeneratorGraph,
    limits: &'a Limits,
    config: &'a MhConfig,
}

/// One chain's move in progress: its temperature, the objective with the
/// worker's scratch, and what the move counted.
struct Move<'a, O: Objective> {
    beta: f64,
    objective: &'a O,
    scratch: &'a mut O::Scratch,
    counts: MoveCounts,
    evaluations: u64,
}

impl<O: Objective> Move<'_, O> {
    fn evaluate(&mut self, genome: &Genome) -> f64 {
        self.evaluations += 1;
        self.objective.evaluate(genome, self.scratch)
    }
}

impl Mover<'_> {
    fn bounds(&self) -> LengthBounds {
        self.config.length_bounds()
    }

    /// One move of one chain; returns its counts and evaluations.
    fn advance<O: Objective>(
        &self,
        chain: &mut Individual,
        beta: f64,
        objective: &O,
        scratch: &mut O::Scratch,
        rng: &mut Rng,
    ) -> (MoveCounts, u64) {
        let mut m = Move { beta, objective, scratch, counts: MoveCounts::default(), evaluations: 0 };
        let choice = self.config.gene_choice;
        let jump_at = if rng.bernoulli(self.config.jump) {
            moves::choose(&chain.genome, Eligible::Nonterminals, choice, rng)
        } else {
            None
        };
        match jump_at {
            Some(v) => self.jump(chain, v, &mut m, rng),
            None => self.diffusion(chain, &mut m, rng),
        }
        (m.counts, m.evaluations)
    }

    /// A jump at `v`, with a delayed-rejection second stage.
    fn jump<O: Objective>(&self, chain: &mut Individual, v: GenePos, m: &mut Move<'_, O>, rng: &mut Rng) {
        let choice = self.config.gene_choice;
        m.counts.jumps_proposed += 1;
        let x = &chain.genome;
        let ln_px = moves::ln_choice(x, Eligible::Nonterminals, choice, v);
        let Some(y1) = self.propose_jump(x, v, rng) else { return };
        let f1 = m.evaluate(&y1);
        let ln_p1 = moves::ln_choice(&y1, Eligible::Nonterminals, choice, v);
        let ln_a1 = tempered(m.beta, f1, chain.fitness) + ln_p1 - ln_px;
        if accept(ln_a1, rng) {
            m.counts.jumps_accepted += 1;
            *chain = Individual { genome: y1, fitness: f1 };
            return;
        }
        if !self.config.delayed_rejection {
            return;
        }
        m.counts.delayed_proposed += 1;
        let Some(y2) = self.propose_jump(x, v, rng) else { return };
        // The reverse path (y₂ → y₁ → x) must exist and the dimensions must
        // match: every gene of y₁ sits at a place both x and y₂ have or
        // neither has. Otherwise y₁ shares freshly drawn values with one of
        // them that the reverse proposal could not reproduce.
        let (a, c) = (moves::paths_below(x, v), moves::paths_below(&y2, v));
        if moves::paths_below(&y1, v).keys().any(|p| a.contains_key(p) != c.contains_key(p)) {
            return;
        }
        let f2 = m.evaluate(&y2);
        let ln_p2 = moves::ln_choice(&y2, Eligible::Nonterminals, choice, v);
        let ln_a21 = tempered(m.beta, f1, f2) + ln_p1 - ln_p2;
        let ln_a2 = tempered(m.beta, f2, chain.fitness) + ln_p2 - ln_px + ln_reject(ln_a21) - ln_reject(ln_a1);
        if accept(ln_a2, rng) {
            m.counts.delayed_accepted += 1;
            *chain = Individual { genome: y2, fitness: f2 };
        }
    }

    /// A jump proposal inside the support, or `None`.
    fn propose_jump(&self, x: &Genome, v: GenePos, rng: &mut Rng) -> Option<Genome> {
        moves::jump(x, v, self.graph, self.limits, rng).filter(|y| self.bounds().contains(y.len()))
    }

    /// New parameters for one gene.
    fn diffusion<O: Objective>(&self, chain: &mut Individual, m: &mut Move<'_, O>, rng: &mut Rng) {
        let Some(v) = moves::choose(&chain.genome, Eligible::Parameters, self.config.gene_choice, rng) else {
            return;
        };
        m.counts.diffusions_proposed += 1;
        let drift = rng.bernoulli(self.config.drift).then_some(self.config.drift_scale);
        let mut y = chain.genome.clone();
        let ln_prior = moves::diffuse(&mut y, v, self.graph, drift, rng);
        if ln_prior == f64::NEG_INFINITY {
            return;
        }
        let f = m.evaluate(&y);
        if accept(tempered(m.beta, f, chain.fitness) + ln_prior, rng) {
            m.counts.diffusions_accepted += 1;
            *chain = Individual { genome: y, fitness: f };
        }
    }
}
