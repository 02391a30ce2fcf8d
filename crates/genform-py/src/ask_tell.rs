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

use genform_core::Genome;
use genform_evolve::{AnyOptimizer, GenerationStats, Objective, Optimizer};
use std::collections::{HashMap, HashSet};
use std::sync::Mutex;

/// A fitness and the two behaviour descriptors (NaN when unknown).
pub type Score = (f64, [f64; 2]);

/// The most batches one generation may take before it is called stuck.
const MAX_ROUNDS: usize = 100_000;

/// An optimizer driven by ask/tell.
pub struct AskTell {
    opt: AnyOptimizer,
    known: HashMap<Genome, Score>,
    pending: Vec<Genome>,
    pool: rayon::ThreadPool,
    rounds: usize,
}

/// The objective of a replayed generation: scores told so far; unknown
/// genomes are recorded.
struct Replay<'a> {
    known: &'a HashMap<Genome, Score>,
    missing: Mutex<Vec<Genome>>,
}

impl Replay<'_> {
    fn score(&self, genome: &Genome) -> Score {
        match self.known.get(genome) {
            Some(s) => *s,
            None => {
                self.missing.lock().expect("not poisoned").push(genome.clone());
                (f64::NAN, [f64::NAN; 2])
            }
        }
    }
}

impl Objective for Replay<'_> {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, genome: &Genome, _: &mut ()) -> f64 {
        self.score(genome).0
    }

    fn evaluate_described(&self, genome: &Genome, _: &mut (), descriptors: &mut [f64; 2]) -> f64 {
        let (f, d) = self.score(genome);
        *descriptors = d;
        f
    }
}

impl AskTell {
    /// Drives `opt` by ask/tell.
    pub fn new(opt: AnyOptimizer) -> Result<Self, String> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().map_err(|e| e.to_string())?;
        Ok(AskTell { opt, known: HashMap::new(), pending: Vec::new(), pool, rounds: 0 })
    }

    /// The optimizer as of the last completed generation.
    pub fn optimizer(&self) -> &AnyOptimizer {
        &self.opt
    }

    /// The genomes to score next (the same until [`AskTell::tell`]), and
    /// the statistics of generations that completed without needing any
    /// new score on the way.
    pub fn ask(&mut self) -> Result<(&[Genome], Vec<GenerationStats>), String> {
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
        let replay = Replay { known: &self.known, missing: Mutex::new(Vec::new()) };
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
