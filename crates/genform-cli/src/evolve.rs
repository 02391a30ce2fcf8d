//! `genform evolve`, `score` and `compare`: arguments into requests of the
//! application's run loop ([`genform_app::evolve`]), a progress bar, Ctrl-C
//! and what the runs have to say on stderr and stdout.

use anyhow::Result;
use genform_app::{Control, Start, SteerSet, Tick, Watch};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use crate::args::{CompareArgs, EvolveArgs, ScoreArgs};

/// Runs `genform evolve`: Ctrl-C stops the run (its results are written),
/// `--steering` replays an earlier run's steering.
pub fn evolve(a: EvolveArgs) -> Result<()> {
    let schedule = match &a.steering {
        Some(path) => genform_app::read_steering_log(path)?,
        None => Vec::new(),
    };
    let mut watch = Progress::new(a.quiet);
    let control = Control { cancel: cancel_on_ctrl_c(), schedule, watch: Some(&mut watch) };
    let outcome = genform_app::evolve(&a.request(), control)?;
    drop(watch);
    eprintln!("{}", outcome.summary());
    Ok(())
}

/// Runs `genform score`: one genome's fitness and its parts on stdout.
pub fn score(a: ScoreArgs) -> Result<()> {
    for line in genform_app::score(&a.request())? {
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
    let outcome = genform_app::compare(&request, control)?;
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

/// Seconds between progress lines when stderr is no terminal (a pipe, a
/// log file), unless `GENFORM_PROGRESS_EVERY` gives others (0: every
/// generation).
pub const PROGRESS_EVERY: Duration = Duration::from_secs(5);

/// The interval of progress lines: [`PROGRESS_EVERY`] or the seconds in
/// `GENFORM_PROGRESS_EVERY`.
fn progress_every() -> Duration {
    std::env::var("GENFORM_PROGRESS_EVERY")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s >= 0.0 && *s < 1e9)
        .map_or(PROGRESS_EVERY, Duration::from_secs_f64)
}

/// The command line's watcher: a progress bar on a terminal (one line,
/// cut to the terminal's width); without one, a progress line every
/// [`PROGRESS_EVERY`] and the runs' log lines; notes on stderr.
struct Progress {
    bar: ProgressBar,
    quiet: bool,
    /// Whether generations bound the run (the bar counts them, else
    /// milliseconds of the budget).
    by_generation: bool,
    /// The generation limit, for progress lines.
    generations: Option<usize>,
    /// When the last progress line was printed (no bar), or the run started.
    last_line: Instant,
    every: Duration,
    /// Whether stderr is no terminal (progress lines instead of a bar).
    piped: bool,
    /// The terminal's width when the run started (the bar's line is cut to
    /// one column less, so it never wraps and is not padded).
    width: usize,
}

impl Progress {
    fn new(quiet: bool) -> Progress {
        let bar = ProgressBar::new(0);
        let target = if quiet { ProgressDrawTarget::hidden() } else { ProgressDrawTarget::stderr() };
        let width = console::Term::stderr().size_checked().map_or(80, |(_, w)| usize::from(w));
        bar.set_draw_target(target);
        bar.set_style(style("{elapsed_precise} {msg}"));
        let piped = !std::io::stderr().is_terminal();
        Progress {
            bar,
            quiet,
            by_generation: false,
            generations: None,
            last_line: Instant::now(),
            every: progress_every(),
            piped,
            width,
        }
    }
}

/// A bar style of `template`.
fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template).expect("valid template").progress_chars("=> ")
}

impl Watch for Progress {
    fn started(&mut self, start: &Start) {
        let h = start.horizon;
        self.by_generation = h.generations.is_some();
        self.bar.set_length(match h.generations {
            Some(g) => g as u64,
            None => h.budget.map_or(0, |b| b.as_millis() as u64),
        });
        self.generations = h.generations;
        self.last_line = Instant::now();
        let template = if self.by_generation {
            "{elapsed_precise} [{bar:20}] gen {pos}/{len} {msg}"
        } else {
            "{elapsed_precise} [{bar:20}] {msg}"
        };
        self.bar.set_style(style(template));
    }

    fn generation(&mut self, tick: &Tick) -> Option<SteerSet> {
        let rate = tick.stats.total_evaluations as f64 / tick.seconds.max(1e-9);
        let msg = format!("best {:.4} · {rate:.0} evals/s{}", tick.best.unwrap_or(f64::NAN), tick.tail);
        if self.by_generation {
            self.bar.set_position(tick.stats.generation as u64);
            // `00:00:00 [bar] gen 12/130 `: 32 columns, `gen /` and a space, the numbers.
            let prefix = 32 + 6 + digits(tick.stats.generation) + digits(self.generations.unwrap_or(0));
            self.bar.set_message(cut(&format!("· {msg}"), self.width.saturating_sub(prefix + 1)));
        } else {
            self.bar.set_position((tick.seconds * 1000.0) as u64);
            let msg = format!("gen {} · {msg}", tick.stats.generation);
            self.bar.set_message(cut(&msg, self.width.saturating_sub(32 + 1)));
        }
        if !self.quiet && self.bar.is_hidden() {
            if let Some(line) = &tick.log {
                eprintln!("{line}");
            }
            if self.piped && self.last_line.elapsed() >= self.every {
                self.last_line = Instant::now();
                let of = self.generations.map_or(String::new(), |g| format!("/{g}"));
                eprintln!(
                    "{:.1} s · gen {}{of} · {} evaluations · best {:.4} · {rate:.0} evals/s{}",
                    tick.seconds,
                    tick.stats.generation,
                    tick.stats.total_evaluations,
                    tick.best.unwrap_or(f64::NAN),
                    tick.tail
                );
            }
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

/// Decimal digits of `n`.
fn digits(n: usize) -> usize {
    n.to_string().len()
}

/// `text` cut to `columns` characters (the last one `…` when cut).
fn cut(text: &str, columns: usize) -> String {
    if text.chars().count() <= columns {
        return text.to_string();
    }
    let mut out: String = text.chars().take(columns.saturating_sub(1)).collect();
    if columns > 0 {
        out.push('…');
    }
    out
}

/// Ctrl-Cs received so far.
static INTERRUPTS: AtomicUsize = AtomicUsize::new(0);

/// A flag set by Ctrl-C. The run stops after its current generation and
/// writes its results, and the process then ends as interrupted
/// ([`end_as_interrupted`]), so a calling shell stops its loop or `set -e`
/// script. A second Ctrl-C (often a key held or pressed twice) does not
/// cut the writing short; a third quits at once (every file is written
/// whole or not at all).
pub(crate) fn cancel_on_ctrl_c() -> Arc<AtomicBool> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let _ = ctrlc::set_handler(move || {
        flag.store(true, Ordering::SeqCst);
        match INTERRUPTS.fetch_add(1, Ordering::SeqCst) + 1 {
            1 => eprintln!("\ninterrupted: stopping after this generation and saving the results"),
            2 => eprintln!("\nsaving the results first; Ctrl-C once more quits without them"),
            _ => std::process::exit(130),
        }
    });
    cancel
}

/// Whether Ctrl-C came during the command.
pub(crate) fn interrupted() -> bool {
    INTERRUPTS.load(Ordering::SeqCst) >= 1
}

/// Ends the process as a Ctrl-C would have, once the results are written:
/// the default SIGINT action is restored and the signal raised, so the
/// parent sees a process killed by SIGINT (a shell's `$?` is 130, and
/// `while`/`for` loops and `set -e` scripts stop) rather than a success.
pub(crate) fn end_as_interrupted() -> ! {
    use std::io::Write as _;
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    #[cfg(unix)]
    // SAFETY: `signal` and `raise` are async-signal-safe and take plain
    // integers; nothing runs after them but the exit below if SIGINT is
    // somehow ignored.
    unsafe {
        libc::signal(libc::SIGINT, libc::SIG_DFL);
        libc::raise(libc::SIGINT);
    }
    std::process::exit(130)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_messages_are_cut_to_the_columns_left() {
        assert_eq!(cut("best 1.2 · 900 evals/s", 40), "best 1.2 · 900 evals/s");
        assert_eq!(cut("best 1.2 · 900 evals/s", 8), "best 1.…");
        assert_eq!(cut("abc", 0), "");
        assert_eq!((digits(0), digits(9), digits(130)), (1, 1, 3));
    }
}
