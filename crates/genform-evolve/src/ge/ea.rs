//! [`Ge`], the grammatical-evolution EA: its state, its generation loop
//! and its random streams (see the [`ge`](super) module documentation).
//! Kept apart from the module that gathers the codon optimizers, so
//! [`AnyCodonOptimizer`](super::AnyCodonOptimizer) can name [`Ge`] without
//! importing it.

use super::codons::Codons;
use super::config::{GeConfig, Init, NovelKey};
use super::operators;
use super::reproduce::{Context, reproduce_pair};
use crate::config::ConfigError;
use crate::objective::{Objective, SensiblePlan};
use crate::optimizer::{Individual, Optimizer};
use crate::population::{Population, breed};
use crate::selection::Selector;
use crate::stats::GenerationStats;
use genform_core::Rng;
use std::collections::{HashMap, HashSet};
use std::time::Instant;

/// Stream id of GE's initial genomes: `(seed, GE_INIT_STREAM, index)`.
pub const GE_INIT_STREAM: u64 = 0x4745_494e_4954; // "GEINIT"
/// Stream id of GE's reproduction: `(seed, GE_PAIR_STREAM, generation, pair)`.
pub const GE_PAIR_STREAM: u64 = 0x4745_5041_4952; // "GEPAIR"
/// Stream id of re-mutating a child whose expressed codons were already
/// evaluated: `(seed, GE_NOVEL_STREAM, generation, child)`.
pub const GE_NOVEL_STREAM: u64 = 0x4745_4e4f_5645; // "GENOVE"
/// Stream id of subtree mutation: `(seed, GE_SUBTREE_STREAM, generation, child)`.
pub const GE_SUBTREE_STREAM: u64 = 0x4745_5355_4254; // "GESUBT"
/// Stream id of a restart's fresh genomes: `(seed, GE_RESTART_STREAM, generation, index)`.
pub const GE_RESTART_STREAM: u64 = 0x4745_5253_5452; // "GERSTR"
/// Stream id of local search around the best: `(seed, GE_LOCAL_STREAM, generation, child)`.
pub const GE_LOCAL_STREAM: u64 = 0x4745_4c4f_4341; // "GELOCA"
/// Most codons one local-search child redraws (uniform in `1..=LOCAL_CODONS`).
const LOCAL_CODONS: usize = 3;
/// Point mutations tried on a child before it keeps the fitness its
/// expressed codons already had.
const NOVEL_TRIES: usize = 8;
/// Most codons the memory of evaluated prefixes holds (64 MiB of codons):
/// every evaluation adds a new prefix, so a long run would otherwise grow
/// it without bound. When full it starts afresh (at a point that depends
/// only on the run, so runs stay deterministic).
const SEEN_CODONS: usize = 1 << 24;

/// What identifies an evaluated individual for `novel_children`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum SeenKey {
    /// The objective's [`Objective::phenotype_key`].
    Phenotype(u64),
    /// The codons the mapping read.
    Codons(Codons),
}

impl SeenKey {
    /// What the key costs against [`SEEN_CODONS`].
    fn size(&self) -> usize {
        match self {
            SeenKey::Phenotype(_) => 1,
            SeenKey::Codons(c) => c.len(),
        }
    }
}

/// The grammatical-evolution EA (Genr8's loop with the recommended GE
/// operators; see the [module](super) documentation).
#[derive(Clone, Debug)]
pub struct Ge {
    config: GeConfig,
    seed: u64,
    state: Population<Codons>,
    /// Fitness of every phenotype key or expressed codon prefix evaluated
    /// so far (with `novel_children`; the objective must tell what it
    /// reads), at most [`SEEN_CODONS`] codons of them (a phenotype key
    /// counts as one).
    seen: HashMap<SeenKey, f64>,
    /// Codons held by `seen`'s keys.
    seen_codons: usize,
    /// Fitness of the best individual seen (−∞ before any valid one).
    record: f64,
    /// Generations since `record` last rose (for `restart_after`).
    stalled: usize,
    /// Restarts so far.
    restarts: usize,
}

impl Ge {
    /// A GE run with no population yet (see [`Ge::initialize`]).
    pub fn new(config: GeConfig, seed: u64) -> Result<Self, ConfigError> {
        config.validate()?;
        let state = Population::with_room(config.population, "population")?;
        Ok(Ge {
            config,
            seed,
            state,
            seen: HashMap::new(),
            seen_codons: 0,
            record: f64::NEG_INFINITY,
            stalled: 0,
            restarts: 0,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &GeConfig {
        &self.config
    }

    /// The current population, best first.
    pub fn population(&self) -> &[Individual<Codons>] {
        self.state.members()
    }

    /// The best valid individual seen so far (with elitism, the population's first).
    pub fn best(&self) -> Option<&Individual<Codons>> {
        self.state.best()
    }

    /// Index of the current generation (0 = the initial one).
    pub fn generation(&self) -> usize {
        self.state.generation()
    }

    /// Objective evaluations so far.
    pub fn evaluations(&self) -> u64 {
        self.state.evaluations()
    }

    /// Restarts so far (see [`GeConfig::restart_after`]).
    pub fn restarts(&self) -> usize {
        self.restarts
    }

    /// Records the generation just made: the best seen rose or not.
    fn observe(&mut self, stats: GenerationStats) -> GenerationStats {
        let best = self.state.best().map_or(f64::NEG_INFINITY, |b| b.fitness);
        if best > self.record {
            (self.record, self.stalled) = (best, 0);
        } else {
            self.stalled += 1;
        }
        stats
    }

    /// Builds and evaluates generation 0 (discarding any population):
    /// individual `i` is [`random_codons`](operators::random_codons) from
    /// stream `(seed, GE_INIT_STREAM, i)`.
    pub fn initialize<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        self.seen.clear();
        self.seen_codons = 0;
        (self.record, self.stalled, self.restarts) = (f64::NEG_INFINITY, 0, 0);
        let genomes = self.fresh(objective, self.config.population, |i| vec![GE_INIT_STREAM, i as u64]);
        let stats = self.state.initialize(objective, self.config.population, |i| genomes[i].clone());
        self.observe(stats)
    }

    /// `count` fresh genomes as `init` draws them, genome `i` from stream
    /// `(seed, ids(i)…)`. Random: [`random_codons`](operators::random_codons).
    /// Sensible: the objective's [`Objective::sensible_genome`], drawn
    /// again (up to [`NOVEL_TRIES`] times, from the same stream) while its
    /// phenotype key repeats an earlier genome's, so the batch starts with
    /// distinct phenotypes as PonyGE2's sensible initialisation does;
    /// random codons from that stream where the objective writes none.
    /// Sequential: the same at any thread count.
    fn fresh<O: Objective<Codons>>(&self, objective: &O, count: usize, ids: impl Fn(usize) -> Vec<u64>) -> Vec<Codons> {
        let (length, range, seed) = (self.config.initial_length, self.config.codon_range, self.seed);
        if self.config.init == Init::Random {
            return (0..count)
                .map(|i| operators::random_codons(length, range, &mut Rng::stream(seed, &ids(i))))
                .collect();
        }
        let plan =
            SensiblePlan { max_depth: self.config.init_depth, codon_range: range, max_length: self.config.max_length };
        let mut scratch = objective.scratch();
        let mut keys = HashSet::new();
        (0..count)
            .map(|i| {
                let mut rng = Rng::stream(seed, &ids(i));
                let mut repeat = None;
                for _ in 0..NOVEL_TRIES {
                    let Some(genome) = objective.sensible_genome(i, plan, &mut rng, &mut scratch) else { break };
                    match objective.phenotype_key(&genome, &mut scratch) {
                        Some(key) if !keys.insert(key) => {
                            repeat.get_or_insert(genome);
                        }
                        _ => return genome,
                    }
                }
                repeat.unwrap_or_else(|| operators::random_codons(length, range, &mut rng))
            })
            .collect()
    }

    /// A restart: the `elitism` best stay, the rest of generation
    /// `generation` is fresh random genomes, drawn as generation 0's are
    /// but from stream `(seed, GE_RESTART_STREAM, generation, i)`.
    fn restart<O: Objective<Codons>>(&mut self, objective: &O, generation: usize) -> GenerationStats {
        let started = Instant::now();
        let count = self.config.population - self.config.elitism;
        let children = self
            .fresh(objective, count, |i| vec![GE_RESTART_STREAM, generation as u64, i as u64])
            .into_iter()
            .map(|genome| crate::evaluate::Child { genome, fitness: None })
            .collect();
        self.restarts += 1;
        let stats = self.state.advance(objective, self.config.elitism, children, Default::default(), started);
        let stats = self.observe(stats);
        // A fresh start gets a full `restart_after` generations after it.
        self.stalled = 0;
        stats
    }

    /// Makes the next generation; initializes first if there is no population.
    pub fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        if self.state.is_empty() {
            return self.initialize(objective);
        }
        let generation = self.state.generation() + 1;
        if self.config.restart_after > 0 && self.stalled >= self.config.restart_after {
            return self.restart(objective, generation);
        }
        let started = Instant::now();
        let mut fitness = self.state.fitness();
        if self.config.distinct_parents {
            // Members are sorted best first, so the first of equal scores is kept.
            let mut seen = HashSet::with_capacity(fitness.len());
            for f in &mut fitness {
                if f.is_finite() && !seen.insert(f.to_bits()) {
                    *f = f64::NAN;
                }
            }
        }
        let wants_expressed = self.config.effective || self.config.novel_children;
        // Mapping only, once per member and child: cheap next to growth.
        let mut scratch = wants_expressed.then(|| objective.scratch());
        let expressed: Vec<usize> = match scratch.as_mut() {
            Some(scratch) => {
                let members = self.state.members();
                let mut e = Vec::with_capacity(members.len());
                for m in members {
                    match objective.expressed(&m.genome, scratch) {
                        Some(n) => e.push(n),
                        None => break,
                    }
                }
                if e.len() == members.len() { e } else { Vec::new() }
            }
            None => Vec::new(),
        };
        if self.config.novel_children {
            // Every member was evaluated (or reused a fitness that was).
            if let Some(scratch) = scratch.as_mut() {
                for (m, &e) in self.state.members().iter().zip(&expressed) {
                    let key = self.key(objective, &m.genome, e, scratch);
                    if !self.seen.contains_key(&key) {
                        if self.seen_codons + key.size() > SEEN_CODONS {
                            self.seen.clear();
                            self.seen_codons = 0;
                        }
                        self.seen_codons += key.size();
                        self.seen.insert(key, m.fitness);
                    }
                }
            }
        }
        let ctx = Context {
            config: &self.config,
            population: self.state.members(),
            selector: Selector::new(self.config.selection, &fitness),
            expressed: if self.config.effective { &expressed } else { &[] },
        };
        let seed = self.seed;
        let wanted = self.config.population - self.config.elitism;
        let local = ((self.config.local_search * wanted as f64).round() as usize).min(wanted);
        let (mut children, mut counts) = breed(wanted - local, |pair, need| {
            reproduce_pair(&ctx, need, &mut Rng::stream(seed, &[GE_PAIR_STREAM, generation as u64, pair as u64]))
        });
        if local > 0 {
            let reach = expressed.first().copied();
            self.local_children(local, reach, &mut children, &mut counts, generation);
        }
        if self.config.subtree_mutation > 0.0 {
            let scratch = scratch.get_or_insert_with(|| objective.scratch());
            self.subtree_mutate(objective, scratch, &mut children, &mut counts, generation);
        }
        if let (Some(scratch), false) = (scratch.as_mut(), expressed.is_empty() || !self.config.novel_children) {
            self.make_novel(objective, scratch, &mut children, &mut counts, generation);
        }
        let stats = self.state.advance(objective, self.config.elitism, children, counts, started);
        self.observe(stats)
    }

    /// Local search around the best: appends `count` children, each the
    /// population's first member with 1 to [`LOCAL_CODONS`] codons redrawn
    /// among the first `reach` (the codons its mapping reads; `None`: the
    /// whole genome), child `k` from stream `(seed, GE_LOCAL_STREAM,
    /// generation, k)`. The novelty pass that follows turns a child that
    /// reads what was read before into a new one.
    fn local_children(
        &self,
        count: usize,
        reach: Option<usize>,
        children: &mut Vec<crate::evaluate::Child<Codons>>,
        counts: &mut crate::stats::ReproductionCounts,
        generation: usize,
    ) {
        let Some(first) = self.state.members().first() else { return };
        let region = reach.map_or(first.genome.len(), |e| e.min(first.genome.len()));
        for k in 0..count {
            let mut genome = first.genome.clone();
            if region > 0 {
                let mut rng = Rng::stream(self.seed, &[GE_LOCAL_STREAM, generation as u64, k as u64]);
                for _ in 0..1 + rng.index(LOCAL_CODONS) {
                    let i = rng.index(region);
                    genome[i] = rng.below(self.config.codon_range as u64) as u32;
                }
            }
            let same = genome == first.genome;
            counts.mutations.alter += u64::from(!same);
            counts.copies += u64::from(same);
            let fitness = same.then_some(first.fitness);
            children.push(crate::evaluate::Child { genome, fitness });
        }
    }

    /// Phenotype-level duplicate removal: a child whose expressed codons
    /// were evaluated before (by a member, an earlier generation or an
    /// earlier child of this one) gets up to [`NOVEL_TRIES`] point
    /// mutations inside its expressed region until it reads something new;
    /// failing that it keeps the known fitness and costs no evaluation.
    /// Sequential and from per-child streams: the same at any thread count.
    fn make_novel<O: Objective<Codons>>(
        &self,
        objective: &O,
        scratch: &mut O::Scratch,
        children: &mut [crate::evaluate::Child<Codons>],
        counts: &mut crate::stats::ReproductionCounts,
        generation: usize,
    ) {
        let mut batch: HashSet<SeenKey> = HashSet::new();
        for (k, child) in children.iter_mut().enumerate() {
            let mut rng = None;
            let mut tries = 0;
            loop {
                let Some(e) = objective.expressed(&child.genome, scratch) else { return };
                let e = e.min(child.genome.len());
                let key = self.key(objective, &child.genome, e, scratch);
                let known = self.seen.get(&key).copied();
                if known.is_none() && !batch.contains(&key) {
                    if tries > 0 {
                        counts.duplicates_replaced += 1;
                    }
                    batch.insert(key);
                    break;
                }
                if tries == 0 {
                    counts.duplicates += 1;
                }
                if tries == NOVEL_TRIES || e == 0 {
                    // Known: reuse the fitness (a duplicate within the batch
                    // is evaluated again, which is deterministic).
                    child.fitness = known.or(child.fitness);
                    break;
                }
                let rng =
                    rng.get_or_insert_with(|| Rng::stream(self.seed, &[GE_NOVEL_STREAM, generation as u64, k as u64]));
                let i = rng.index(e);
                child.genome[i] = rng.below(self.config.codon_range as u64) as u32;
                // A changed genome is no longer a parent's copy.
                child.fitness = None;
                tries += 1;
            }
        }
    }
}

impl Ge {
    /// Subtree mutation: each child, with probability `subtree_mutation`,
    /// has one derivation subtree (uniform over
    /// [`Objective::subtrees`]) regrown. Fresh codons (twice the subtree's
    /// plus 32) replace the subtree's; the child is mapped with them, and
    /// only the fresh codons the regrown subtree read are kept, so the
    /// codons after it are read where they were. Sequential, from
    /// per-child streams: the same at any thread count.
    fn subtree_mutate<O: Objective<Codons>>(
        &self,
        objective: &O,
        scratch: &mut O::Scratch,
        children: &mut [crate::evaluate::Child<Codons>],
        counts: &mut crate::stats::ReproductionCounts,
        generation: usize,
    ) {
        let (mut spans, mut after) = (Vec::new(), Vec::new());
        for (k, child) in children.iter_mut().enumerate() {
            let mut rng = Rng::stream(self.seed, &[GE_SUBTREE_STREAM, generation as u64, k as u64]);
            if !rng.bernoulli(self.config.subtree_mutation) {
                continue;
            }
            objective.subtrees(&child.genome, scratch, &mut spans);
            if spans.is_empty() {
                continue;
            }
            let span = spans[rng.index(spans.len())];
            let (genome, range) = (&child.genome, self.config.codon_range as u64);
            let fresh: Codons = (0..2 * (span.end - span.start) + 32).map(|_| rng.below(range) as u32).collect();
            let mut candidate = Vec::with_capacity(genome.len() + fresh.len());
            candidate.extend_from_slice(&genome[..span.start]);
            candidate.extend_from_slice(&fresh);
            candidate.extend_from_slice(&genome[span.end..]);
            objective.subtrees(&candidate, scratch, &mut after);
            // The codons before the subtree are unchanged, so its expansion
            // is the one that starts where it did.
            if let Some(regrown) = after.iter().find(|t| t.start == span.start) {
                let read = regrown.end - span.start;
                if read <= fresh.len() {
                    candidate.drain(span.start + read..span.start + fresh.len());
                }
            }
            candidate.truncate(self.config.max_length);
            if candidate != child.genome {
                child.genome = candidate;
                child.fitness = None;
                counts.mutations.regrow += 1;
            }
        }
    }

    /// The `novel_children` identity of `genome`, whose mapping reads its
    /// first `expressed` codons.
    fn key<O: Objective<Codons>>(
        &self,
        objective: &O,
        genome: &Codons,
        expressed: usize,
        scratch: &mut O::Scratch,
    ) -> SeenKey {
        let phenotype = match self.config.novel_key {
            NovelKey::Phenotype => objective.phenotype_key(genome, scratch),
            NovelKey::Codons => None,
        };
        match phenotype {
            Some(h) => SeenKey::Phenotype(h),
            None => SeenKey::Codons(genome[..expressed.min(genome.len())].to_vec()),
        }
    }
}

impl Optimizer<Codons> for Ge {
    fn step<O: Objective<Codons>>(&mut self, objective: &O) -> GenerationStats {
        Ge::step(self, objective)
    }

    fn population(&self) -> &[Individual<Codons>] {
        Ge::population(self)
    }

    fn best(&self) -> Option<&Individual<Codons>> {
        Ge::best(self)
    }

    fn generation(&self) -> usize {
        Ge::generation(self)
    }

    fn evaluations(&self) -> u64 {
        Ge::evaluations(self)
    }
}

impl crate::rescore::Rescore<Codons> for Ge {
    /// Re-scores the population and the best.
    fn rescore<O: Objective<Codons>>(&mut self, objective: &O) -> u64 {
        self.state.rescore(objective)
    }
}
