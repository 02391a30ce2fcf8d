//! Runs of an optimizer on a scene — the one run loop under every front
//! door (`genform evolve`, the studio's runs, `genform.evolve` in Python).
//!
//! A door fills an [`EvolveRequest`] and calls [`evolve`] with a
//! [`Control`]: a cancel flag (Ctrl-C, a stop button, Python's
//! KeyboardInterrupt), a replayed steering log and a [`Watch`] that sees
//! every generation (a progress bar, the studio's event stream, a Python
//! callable) and may pause and steer the run. The loop
//! ([`session::drive`]) writes the run folder — checkpoints every
//! [`CHECKPOINT_EVERY`], the whole folder at the end — and returns a
//! [`RunOutcome`]; it prints nothing: notes reach the watcher as text.
//!
//! What differs between derivation-tree and codon genomes is a
//! [`session::Session`] each ([`tree`], [`codon`]); the loop, the
//! statistics, the plot and `run.json`'s common keys are shared, and so is
//! `compare`'s race ([`compare`]).

use crate::units::parse_duration;
use anyhow::{Context, Result, bail};

use crate::memory::Reservation;
use crate::objective::OpenScene;
use crate::optimizers::{Kind, OPTIMIZERS, OptimizerRow, Searches};
use crate::scene::Scene as SceneFile;

pub mod breed;
pub mod codon;
pub mod compare;
pub mod control;
pub mod derive;
pub mod map;
mod session;
pub mod steering;
pub mod sweep;
pub mod tree;

use control::{Control, EvolveRequest, RunOutcome, ScoreRequest, algorithm, load_scene, stop_rules};

/// Runs `request` under `control`: a tree or codon scene, whichever the
/// scene file is. The run holds its scene's estimated memory in the
/// process's ledger while it goes ([`admit`]).
pub fn evolve(request: &EvolveRequest, control: Control) -> Result<RunOutcome> {
    admit(request)?.run(control)
}

/// A run admitted to the process's memory budget: its scene read and
/// checked, its algorithm and stop rules resolved, and the scene's
/// estimated bytes reserved ([`crate::memory::reserve`]) until it has run
/// (or is dropped unrun).
pub struct Admitted {
    request: EvolveRequest,
    scene: SceneFile,
    row: &'static OptimizerRow,
    horizon: genform_evolve::Horizon,
    memory: Reservation,
}

/// Admits `request`: everything [`evolve`] refuses before the first
/// generation, the per-scene memory check included, and then the
/// process-wide one — refused (an [`crate::memory::OverBudget`] error)
/// while other runs and sessions hold too much of the budget. A door that
/// must answer before the run starts (the studio) admits first and runs
/// the [`Admitted`] later.
pub fn admit(request: &EvolveRequest) -> Result<Admitted> {
    let scene = load_scene(&request.scene, &request.set, request.preset.as_deref())?;
    let row = algorithm(request.algorithm.as_deref(), &scene)?;
    let horizon = stop_rules(request, &scene.run)?;
    let memory = scene.reserve("run")?;
    Ok(Admitted { request: request.clone(), scene, row, horizon, memory })
}

impl Admitted {
    /// The scene, as the run will run it.
    pub fn scene(&self) -> &SceneFile {
        &self.scene
    }

    /// The algorithm's name.
    pub fn algorithm(&self) -> &'static str {
        self.row.name()
    }

    /// The bytes it holds of the memory budget.
    pub fn reserved(&self) -> u64 {
        self.memory.bytes()
    }

    /// Sets the run folder (`None`: nothing is written); admission does
    /// not depend on it.
    pub fn set_out(&mut self, out: Option<std::path::PathBuf>) {
        self.request.out = out;
    }

    /// Runs it under `control` (see [`evolve`]); its memory is given back
    /// when the run folder is written.
    pub fn run(self, control: Control) -> Result<RunOutcome> {
        let Admitted { request, scene, row, horizon, memory } = self;
        let _session = crate::gate::session();
        crate::gate::admit_read(&scene.path, "scene")?;
        let open = OpenScene::open(scene, request.limits)?;
        if let Some(out) = &request.out {
            crate::gate::refuse_folder("--out", out, writes_run_file)?;
        }
        let outcome = match row.kind {
            Kind::Tree(alg) => tree::evolve(&request, &open, alg, horizon, control),
            Kind::Codon(alg) => codon::evolve(&request, &open, alg, horizon, control),
        };
        drop(open);
        drop(memory);
        outcome
    }
}

/// Whether a run, `compare` or `sweep` writes a file called `name` into
/// its output folder (so that an input there by that name is refused
/// before the run; [`crate::gate::check_write`] stays the net under every
/// write).
fn writes_run_file(name: &str) -> bool {
    name.starts_with("best")
        || [
            "stats.csv",
            "fitness.svg",
            "gallery.png",
            "evolution.png",
            "archive.csv",
            "archive.png",
            "run.json",
            "comparison.csv",
            "comparison.svg",
            "summary.md",
            "sweep.csv",
            "sweep.svg",
        ]
        .contains(&name)
}

/// The score of one genome, as lines of text (the first the total).
pub fn score(request: &ScoreRequest) -> Result<Vec<String>> {
    let mut scene = load_scene(&request.scene, &request.set, None)?;
    if request.form.is_some() && !scene.scoring.counts() {
        bail!("--form chooses how volume and image targets count; {} scores a surface", request.scene.display());
    }
    scene.scoring.fitness.override_form(request.form.as_deref())?;
    let open = OpenScene::open(scene, request.limits)?;
    match open.scene.searches {
        Searches::Trees => tree::score(request, &open),
        Searches::Codons => codon::score(request, &open),
    }
}

/// Runs `request` on a tree or codon scene; each finished run's line and
/// any interruption reach `control`'s watcher as notes.
pub fn compare(request: &compare::CompareRequest, control: Control) -> Result<compare::CompareOutcome> {
    let _session = crate::gate::session();
    let scene = load_scene(&request.scene, &request.set, request.preset.as_deref())?;
    let budget = parse_duration(&request.budget).context("--budget")?;
    if let Some(why) = crate::caps::count("--runs", request.runs as u64, crate::caps::MAX_RUNS) {
        bail!(why);
    }
    let mut rows = Vec::new();
    if request.algorithms.is_empty() {
        rows.extend(OPTIMIZERS.iter().filter(|r| r.compare && r.searches() == scene.searches));
    }
    for name in &request.algorithms {
        let row = algorithm(Some(name), &scene)?;
        if !rows.iter().any(|r| std::ptr::eq(*r, row)) {
            rows.push(row);
        }
    }
    // The runs race one after another: one scene's worth of memory at a time.
    let _memory = scene.reserve("comparison")?;
    let open = OpenScene::open(scene, request.limits)?;
    crate::gate::refuse_folder("--out", &request.out, writes_run_file)?;
    let (mut trees, mut codons) = (Vec::new(), Vec::new());
    for row in rows {
        match row.kind {
            Kind::Tree(a) => trees.push(a),
            Kind::Codon(a) => codons.push(a),
        }
    }
    if codons.is_empty() {
        tree::compare(request, &open, &trees, budget, control)
    } else {
        codon::compare(request, &open, &codons, budget, control)
    }
}

/// Keyword settings (Python's `population=20`, `mh={…}`) for a run of
/// `algorithm` (`None`: the scene's default) on the scene at `scene`, as
/// a settings patch: bare keys belong to the algorithm's table.
pub fn settings_patch(
    scene: &std::path::Path,
    algorithm: Option<&str>,
    keywords: &serde_json::Map<String, serde_json::Value>,
) -> Result<Vec<String>> {
    let codons = SceneFile::summary(scene).is_some_and(|s| s.codons);
    let searches = if codons { Searches::Codons } else { Searches::Trees };
    let row = match algorithm {
        Some(name) => crate::optimizers::find(name, searches, scene)?,
        None => crate::optimizers::default_for(searches),
    };
    crate::scene::patch::patch_from_json(row.section, keywords)
}
