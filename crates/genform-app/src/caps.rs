//! The caps on the counts a user sets that bound how long a command runs
//! (generations, evaluations, runs, derivation steps) and on scoring
//! weights. A count past its cap could not finish on any machine, so it is
//! refused where it was written instead of running until killed; docs/evolve.md
//! states them.

/// Most generations of one run: at a microsecond per generation of the
/// smallest population this is still a quarter of an hour.
pub const MAX_GENERATIONS: u64 = 1_000_000_000;

/// Most evaluations of one run (a million a second for eleven days).
pub const MAX_EVALUATIONS: u64 = 1_000_000_000_000;

/// Most runs of one `compare` or `sweep` (per algorithm or combination).
pub const MAX_RUNS: u64 = 10_000;

/// Most derivation steps of one sample (L-systems, graph grammars, HEMLS).
pub const MAX_STEPS: u64 = 1_000_000;

/// Largest magnitude of a scoring weight: weights are relative, and past
/// this a sum of weighted terms loses the precision of its small ones (and
/// a sum of a few of them leaves the floating-point range).
pub const MAX_WEIGHT: f64 = 1e9;

/// `None` when `value` lies in `1..=cap`, else why not (`what`: the setting
/// as the user wrote it, e.g. "[run] generations").
pub fn count(what: &str, value: u64, cap: u64) -> Option<String> {
    if value == 0 {
        Some(format!("{what} must be at least 1"))
    } else if value > cap {
        Some(format!("{what} = {value} is past the cap of {} (see docs/evolve.md, \"Caps\")", group(cap)))
    } else {
        None
    }
}

/// `None` when `generations` is at most [`MAX_GENERATIONS`] (0 is
/// allowed: the run scores its first population and stops).
pub fn generations(what: &str, generations: usize) -> Option<String> {
    (generations as u64 > MAX_GENERATIONS).then(|| {
        format!("{what} = {generations} is past the cap of {} (see docs/evolve.md, \"Caps\")", group(MAX_GENERATIONS))
    })
}

/// `None` when `weight` is finite and at most [`MAX_WEIGHT`] in magnitude.
pub fn weight(what: &str, weight: f64) -> Option<String> {
    if !weight.is_finite() {
        Some(format!("{what} must be a finite number, not {weight}"))
    } else if weight.abs() > MAX_WEIGHT {
        Some(format!(
            "{what} = {weight:e} is past ±{MAX_WEIGHT:e}: weights are relative, so scale them all down (past this \
             the fitness loses the precision of its small terms)"
        ))
    } else {
        None
    }
}

/// `n` with thousands separated by commas.
fn group(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_refused_at_zero_and_past_their_cap() {
        assert_eq!(count("x", 1, 5), None);
        assert_eq!(count("x", 5, 5), None);
        assert_eq!(count("[run] evaluations", 0, 5).unwrap(), "[run] evaluations must be at least 1");
        let past = count("--runs", u64::MAX, MAX_RUNS).unwrap();
        assert!(past.contains("is past the cap of 10,000"), "{past}");
    }

    #[test]
    fn weights_are_finite_and_bounded() {
        assert_eq!(weight("good", -1e9), None);
        assert!(weight("good", f64::NAN).unwrap().contains("finite"));
        assert!(weight("bad", -1e308).unwrap().contains("past ±1e9"));
    }
}
