//! `genform sweep`: the command-line side of [`genform_app::sweep`]
//! (arguments, Ctrl-C, progress lines, the summary on stdout).

use anyhow::Result;
use genform_app::{RunDone, SweepRequest};
use std::sync::atomic::Ordering;

use crate::args::SweepArgs;

/// Runs `genform sweep`. Ctrl-C stops the runs under way; the finished
/// ones are written.
pub fn sweep(a: SweepArgs) -> Result<()> {
    let axes = a.set.iter().map(|s| genform_app::parse_set(s)).collect::<Result<Vec<_>>>()?;
    let req = SweepRequest {
        scene: a.scene.clone(),
        axes,
        runs: a.runs,
        seed: a.seed,
        generations: a.generations,
        budget: a.budget.clone(),
        evaluations: a.evaluations,
        algorithm: a.algorithm.clone(),
        threads: a.threads,
        out: a.out.clone(),
    };
    let cancel = crate::evolve::cancel_on_ctrl_c();
    let quiet = a.quiet;
    let progress = move |d: RunDone| {
        if !quiet {
            let last = d.trace.points.last();
            eprintln!(
                "[{}/{}] {} run {}: best {:.6} after {} generations ({:.1} s)",
                d.done,
                d.total,
                d.label,
                d.trace.run + 1,
                last.map_or(f64::NAN, |p| p.best),
                last.map_or(0, |p| p.generation),
                d.trace.seconds
            );
        }
    };
    let result = genform_app::sweep(&req, &cancel, &progress)?;
    let interrupted = cancel.load(Ordering::SeqCst);
    if interrupted {
        eprintln!("interrupted: writing the {} finished runs; unfinished ones are left out", result.runs.len());
    }
    genform_app::write_sweep(&result, &req.scene, &req.out)?;
    print!("{}", result.summary());
    eprintln!(
        "{} runs of {} combinations on {} → {}",
        result.runs.len(),
        result.combinations.len(),
        req.scene.display(),
        req.out.display()
    );
    Ok(())
}
