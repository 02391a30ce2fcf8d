//! `genform evolve`, `score` and `compare`: arguments into requests of
//! [`genform_app::run`], a progress bar, Ctrl-C and what the runs have to
//! say on stderr and stdout.

use anyhow::Result;
use genform_app::run::{self, Control, Start, Tick, Watch};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use crate::args::{CompareArgs, EvolveArgs, ScoreArgs};

/// Runs `genform evolve`: Ctrl-C stops the run (its results are written),
/// `--steering` replays an earlier run's steering.
pub fn evolve(a: EvolveArgs) -> Result<()> {
    let schedule = match &a.steering {
        Some(path) => run::steering::read_log(path)?,
        None => Vec::new(),
    };
    let mut watch = Progress::new(a.quiet);
    let control = Control { cancel: cancel_on_ctrl_c(), schedule, watch: Some(&mut watch) };
    let outcome = run::evolve(&a.request(), control)?;
    drop(watch);
    eprintln!("{}", outcome.summary());
    Ok(())
}

/// Runs `genform score`: one genome's fitness and its parts on stdout.
pub fn score(a: ScoreArgs) -> Result<()> {
    for line in run::score(&a.request())? {
        println!("{line}");
    }
    Ok(())
}

/// Runs `genform compare`: every algorithm `--runs` times with the same
/// wall-clock budget.
pub fn compare(a: CompareArgs) -> Result<()> {
    let request = a.request();
    let mut watch = Progress::new(a.quiet);
    watch.bar.set_draw_target(ProgressDrawTarget::hidden());
    let control = Control { cancel: cancel_on_ctrl_c(), schedule: Vec::new(), watch: Some(&mut watch) };
    let outcome = run::compare(&request, control)?;
    print!("{}", outcome.summary);
    eprintln!(
        "{} runs of {} s each on {} → {}",
        outcome.runs,
        outcome.budget.as_secs_f64(),
        request.scene.display(),
        request.out.display()
    );
    Ok(())
}

/// The command line's watcher: a progress bar on a terminal, per-generation
/// log lines when no bar shows, notes on stderr.
struct Progress {
    bar: ProgressBar,
    quiet: bool,
    /// Whether generations bound the run (the bar counts them, else
    /// milliseconds of the budget).
    by_generation: bool,
}

impl Progress {
    fn new(quiet: bool) -> Progress {
        let bar = ProgressBar::new(0);
        if quiet {
            bar.set_draw_target(ProgressDrawTarget::hidden());
        }
        Progress { bar, quiet, by_generation: false }
    }
}

impl Watch for Progress {
    fn started(&mut self, start: &Start) {
        let h = start.horizon;
        self.by_generation = h.generations.is_some();
        self.bar.set_length(match h.generations {
            Some(g) => g as u64,
            None => h.budget.map_or(0, |b| b.as_millis() as u64),
        });
        let template = if self.by_generation {
            "{elapsed_precise} [{bar:30}] gen {pos}/{len} · {msg}"
        } else {
            "{elapsed_precise} [{bar:30}] {msg}"
        };
        self.bar.set_style(ProgressStyle::with_template(template).expect("valid template").progress_chars("=> "));
    }

    fn generation(&mut self, tick: &Tick) -> Option<run::SteerSet> {
        let rate = tick.stats.total_evaluations as f64 / tick.seconds.max(1e-9);
        let msg = format!("best {:.4} · {rate:.0} evals/s{}", tick.best.unwrap_or(f64::NAN), tick.tail);
        if self.by_generation {
            self.bar.set_position(tick.stats.generation as u64);
            self.bar.set_message(msg);
        } else {
            self.bar.set_position((tick.seconds * 1000.0) as u64);
            self.bar.set_message(format!("gen {} · {msg}", tick.stats.generation));
        }
        if let Some(line) = &tick.log
            && !self.quiet
            && self.bar.is_hidden()
        {
            eprintln!("{line}");
        }
        None
    }

    fn line(&mut self, text: &str) {
        if !self.quiet {
            self.bar.suspend(|| eprintln!("{text}"));
        }
    }

    fn note(&mut self, text: &str) {
        self.bar.suspend(|| eprintln!("{text}"));
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// Ctrl-Cs received so far.
static INTERRUPTS: AtomicUsize = AtomicUsize::new(0);

/// A flag set by Ctrl-C. The run stops and writes its results; a second
/// Ctrl-C (often a key held or pressed twice) does not cut that short but
/// makes the process exit with 130 once they are written; a third quits at
/// once.
pub(crate) fn cancel_on_ctrl_c() -> Arc<AtomicBool> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let _ = ctrlc::set_handler(move || {
        flag.store(true, Ordering::SeqCst);
        match INTERRUPTS.fetch_add(1, Ordering::SeqCst) + 1 {
            1 => {}
            2 => eprintln!("\nsaving the results first; Ctrl-C once more quits without them"),
            _ => std::process::exit(130),
        }
    });
    cancel
}

/// Whether Ctrl-C came at least twice (the command then exits with 130).
pub(crate) fn interrupted_twice() -> bool {
    INTERRUPTS.load(Ordering::SeqCst) >= 2
}
