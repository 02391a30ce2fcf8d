//! Ask/tell over any step-based optimizer, without touching the
//! optimizers: a generation is *replayed* against the scores told so far.
//!
//! `ask` runs the next generation on a copy of the optimizer with an
//! objective that knows no score: every genome it is asked about is
//! recorded (and gets NaN), and those genomes, first-seen order, duplicates
//! once, are the batch. `tell` stores the batch's scores and runs the
//! generation again, on another copy, with an objective that looks scores
//! up: if every genome is known, that copy becomes the optimizer (the
//! generation is exactly the one a direct `step` with the same fitness
//! would make, since optimizers are deterministic given seed and fitness
//! values); if the algorithm asked for genomes it had not asked before
//! (MH, SMC: later evaluations depend on earlier ones), those are the next
//! batch of the same generation. Steps run on a one-thread pool, so the
//! order genomes are asked in never depends on scheduling.

use crate::{AnyOptimizer, GenerationStats, Objective, Optimizer};
use genform_core::Genome;
use std::collections::{HashMap, HashSet};
use std::hash::Hash;
use std::sync::Mutex;

/// A fitness and the two behaviour descriptors (NaN when unknown).
pub type Score = (f64, [f64; 2]);

/// The most batches one generation may take before it is called stuck.
const MAX_ROUNDS: usize = 100_000;

/// An optimizer `P` over genomes `G` driven by ask/tell: by default any
/// tree optimizer ([`AnyOptimizer`]); codon optimizers work the same way
/// (`AskTell<Codons, AnyCodonOptimizer>`).
pub struct AskTell<G = Genome, P = AnyOptimizer> {
    opt: P,
    known: HashMap<G, Score>,
    pending: Vec<G>,
    pool: rayon::ThreadPool,
    rounds: usize,
    expressed: Option<Box<ExpressedFn<G>>>,
    phenotype_key: Option<Box<PhenotypeKeyFn<G>>>,
}

/// What a genome's decoding reads ([`Objective::expressed`]), for replays.
type ExpressedFn<G> = dyn Fn(&G) -> Option<usize> + Send + Sync;

/// What decides a genome's model ([`Objective::phenotype_key`]), for replays.
type PhenotypeKeyFn<G> = dyn Fn(&G) -> Option<u64> + Send + Sync;

/// The objective of a replayed generation: scores told so far; unknown
/// genomes are recorded.
struct Replay<'a, G> {
    known: &'a HashMap<G, Score>,
    missing: Mutex<Vec<G>>,
    expressed: Option<&'a ExpressedFn<G>>,
    phenotype_key: Option<&'a PhenotypeKeyFn<G>>,
}

impl<G: Clone + Eq + Hash> Replay<'_, G> {
    fn score(&self, genome: &G) -> Score {
        match self.known.get(genome) {
            Some(s) => *s,
            None => {
                self.missing.lock().expect("not poisoned").push(genome.clone());
                (f64::NAN, [f64::NAN; 2])
            }
        }
    }
}

impl<G: Clone + Eq + Hash + Send + Sync> Objective<G> for Replay<'_, G> {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, genome: &G, _: &mut ()) -> f64 {
        self.score(genome).0
    }

    fn evaluate_described(&self, genome: &G, _: &mut (), descriptors: &mut [f64; 2]) -> f64 {
        let (f, d) = self.score(genome);
        *descriptors = d;
        f
    }

    fn expressed(&self, genome: &G, _: &mut ()) -> Option<usize> {
        self.expressed.and_then(|f| f(genome))
    }

    fn phenotype_key(&self, genome: &G, _: &mut ()) -> Option<u64> {
        self.phenotype_key.and_then(|f| f(genome))
    }
}

impl<G: Clone + Eq + Hash + Send + Sync, P: Optimizer<G> + Clone + Send> AskTell<G, P> {
    /// Drives `opt` by ask/tell.
    pub fn new(opt: P) -> Result<Self, String> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().map_err(|e| e.to_string())?;
        Ok(AskTell {
            opt,
            known: HashMap::new(),
            pending: Vec::new(),
            pool,
            rounds: 0,
            expressed: None,
            phenotype_key: None,
        })
    }

    /// Tells replays what each genome's decoding reads (the objective's
    /// [`Objective::expressed`]), so that GE's effective operators and
    /// novel children act as in a direct run.
    pub fn with_expressed(mut self, f: impl Fn(&G) -> Option<usize> + Send + Sync + 'static) -> Self {
        self.expressed = Some(Box::new(f));
        self
    }

    /// Tells replays what decides each genome's model (the objective's
    /// [`Objective::phenotype_key`]), so that GE's novel children by
    /// phenotype act as in a direct run.
    pub fn with_phenotype_key(mut self, f: impl Fn(&G) -> Option<u64> + Send + Sync + 'static) -> Self {
        self.phenotype_key = Some(Box::new(f));
        self
    }

    /// The optimizer as of the last completed generation.
    pub fn optimizer(&self) -> &P {
        &self.opt
    }

    /// The genomes to score next (the same until [`AskTell::tell`]), and
    /// the statistics of generations that completed without needing any
    /// new score on the way.
    pub fn ask(&mut self) -> Result<(&[G], Vec<GenerationStats>), String> {
        let mut completed = Vec::new();
        while self.pending.is_empty() {
            if let Some(stats) = self.replay()? {
                completed.push(stats);
            }
        }
        Ok((&self.pending, completed))
    }

    /// Scores for the genomes of the last [`AskTell::ask`], in order: the
    /// generation's statistics once it completed, `None` when the
    /// algorithm needs another batch for it.
    pub fn tell(&mut self, scores: &[Score]) -> Result<Option<GenerationStats>, String> {
        if self.pending.is_empty() {
            return Err("tell() without ask(): ask for the models to score first".into());
        }
        if scores.len() != self.pending.len() {
            return Err(format!("tell() got {} scores for the {} models of ask()", scores.len(), self.pending.len()));
        }
        for (g, s) in std::mem::take(&mut self.pending).into_iter().zip(scores) {
            self.known.insert(g, *s);
        }
        self.replay()
    }

    /// Runs the next generation on a copy against the known scores: commits
    /// it when nothing was missing, else makes the missing genomes the batch.
    fn replay(&mut self) -> Result<Option<GenerationStats>, String> {
        self.rounds += 1;
        if self.rounds > MAX_ROUNDS {
            return Err(format!("the optimizer asked for new genomes {MAX_ROUNDS} times in one generation"));
        }
        let mut trial = self.opt.clone();
        let replay = Replay {
            known: &self.known,
            missing: Mutex::new(Vec::new()),
            expressed: self.expressed.as_deref(),
            phenotype_key: self.phenotype_key.as_deref(),
        };
        let stats = self.pool.install(|| trial.step(&replay));
        let missing = replay.missing.into_inner().expect("not poisoned");
        if missing.is_empty() {
            self.opt = trial;
            self.known.clear();
            self.rounds = 0;
            return Ok(Some(stats));
        }
        let mut seen = HashSet::new();
        self.pending = missing.into_iter().filter(|g| seen.insert(g.clone())).collect();
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{ShipToy, ship};
    use crate::{GaConfig, Horizon, Settings};
    use genform_core::Limits;

    fn ga() -> AnyOptimizer {
        let ga = GaConfig { population: 12, elitism: Some(2), initial_length: [4, 10], ..GaConfig::default() };
        let settings = Settings { ga, ..Settings::default() };
        AnyOptimizer::new(crate::Algorithm::Ga, &ship(), &Limits::default(), &settings, 7, Horizon::default()).unwrap()
    }

    #[test]
    fn ask_tell_makes_the_generations_a_direct_run_makes() {
        let objective = ShipToy { target: 8 };
        let mut direct = ga();
        let mut driven = AskTell::new(ga()).unwrap();
        for _ in 0..4 {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
            pool.install(|| direct.step(&objective));
            loop {
                let (batch, _) = driven.ask().unwrap();
                let scores: Vec<Score> =
                    batch.iter().map(|g| (objective.evaluate(g, &mut ()), [f64::NAN; 2])).collect();
                if driven.tell(&scores).unwrap().is_some() {
                    break;
                }
            }
            assert_eq!(driven.optimizer().population(), direct.population());
        }
        assert!(driven.tell(&[]).unwrap_err().contains("without ask"));
    }

    #[test]
    fn ge_with_effective_operators_replays_like_a_direct_run() {
        use crate::fixtures::PrefixToy;
        use crate::ge::{Codons, Ge, GeConfig};
        let config = GeConfig { population: 16, mutation_rate: 0.05, ..GeConfig::default() };
        let mut direct = Ge::new(config.clone(), 11).unwrap();
        let mut driven = AskTell::new(Ge::new(config, 11).unwrap())
            .unwrap()
            .with_expressed(|c: &Codons| PrefixToy.expressed(c, &mut ()));
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        for _ in 0..6 {
            pool.install(|| direct.step(&PrefixToy));
            loop {
                let (batch, _) = driven.ask().unwrap();
                let scores: Vec<Score> =
                    batch.iter().map(|g| (PrefixToy.evaluate(g, &mut ()), [f64::NAN; 2])).collect();
                if driven.tell(&scores).unwrap().is_some() {
                    break;
                }
            }
            let key = |p: &[crate::Individual<Codons>]| {
                p.iter().map(|i| (i.genome.clone(), i.fitness.to_bits())).collect::<Vec<_>>()
            };
            assert_eq!(key(driven.optimizer().population()), key(direct.population()));
        }
    }

    #[test]
    fn ge_with_novel_children_by_phenotype_replays_like_a_direct_run() {
        use crate::fixtures::PrefixToy;
        use crate::ge::{Codons, Ge, GeConfig, NovelKey};
        // The phenotype: the read codons mod 3 (many codon strings share one).
        fn key(c: &Codons) -> Option<u64> {
            let e = PrefixToy.expressed(c, &mut ())?;
            Some(c[..e].iter().fold(7u64, |h, x| h.wrapping_mul(31).wrapping_add(u64::from(x % 3))))
        }
        struct Keyed;
        impl Objective<Codons> for Keyed {
            type Scratch = ();
            fn scratch(&self) {}
            fn evaluate(&self, c: &Codons, s: &mut ()) -> f64 {
                PrefixToy.evaluate(c, s)
            }
            fn expressed(&self, c: &Codons, s: &mut ()) -> Option<usize> {
                PrefixToy.expressed(c, s)
            }
            fn phenotype_key(&self, c: &Codons, _: &mut ()) -> Option<u64> {
                key(c)
            }
        }
        let config =
            GeConfig { population: 16, mutation_rate: 0.05, novel_key: NovelKey::Phenotype, ..GeConfig::default() };
        let mut direct = Ge::new(config.clone(), 11).unwrap();
        let mut driven = AskTell::new(Ge::new(config, 11).unwrap())
            .unwrap()
            .with_expressed(|c: &Codons| PrefixToy.expressed(c, &mut ()))
            .with_phenotype_key(key);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        for _ in 0..6 {
            pool.install(|| direct.step(&Keyed));
            loop {
                let (batch, _) = driven.ask().unwrap();
                let scores: Vec<Score> = batch.iter().map(|g| (Keyed.evaluate(g, &mut ()), [f64::NAN; 2])).collect();
                if driven.tell(&scores).unwrap().is_some() {
                    break;
                }
            }
            let key = |p: &[crate::Individual<Codons>]| {
                p.iter().map(|i| (i.genome.clone(), i.fitness.to_bits())).collect::<Vec<_>>()
            };
            assert_eq!(key(driven.optimizer().population()), key(direct.population()));
        }
    }
}
