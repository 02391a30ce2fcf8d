//! What a sweep writes: every generation of every run (`sweep.csv`), the
//! mean ± sd of the best fitness per generation, one line per value
//! combination (`sweep.svg`, as the paper's Figures 4–9), and a summary
//! table of the final best fitness (`summary.md`).

use genform_export::plot::{Chart, charts_svg};
use std::fmt::Write as _;

use super::comparison::{mean_sd, mean_sd_series, palette};

/// One generation of one run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GenPoint {
    /// Generation index (0 = the initial population).
    pub generation: usize,
    /// Objective evaluations so far.
    pub evaluations: u64,
    /// Best fitness so far (NaN while no individual is valid).
    pub best: f64,
    /// Best fitness of this generation's population.
    pub max: f64,
    /// Mean fitness of this generation's population.
    pub mean: f64,
}

/// One finished run of one value combination.
#[derive(Clone, Debug, PartialEq)]
pub struct RunTrace {
    /// Index of the value combination.
    pub variant: usize,
    /// Run index (0-based); its seed is the sweep's seed + run.
    pub run: usize,
    /// The run's seed.
    pub seed: u64,
    /// Every generation, in order.
    pub points: Vec<GenPoint>,
    /// Wall-clock seconds the run took (the one measurement that differs
    /// between identical sweeps; it is in the summary, not the CSV).
    pub seconds: f64,
}

/// A finished (or interrupted) sweep: the keys, the value combinations and
/// the runs that finished, in (combination, run) order.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepResult {
    /// The swept keys, in `--set` order.
    pub keys: Vec<String>,
    /// Each combination's values as written, one per key.
    pub combinations: Vec<Vec<String>>,
    /// The finished runs.
    pub runs: Vec<RunTrace>,
}

/// A CSV cell: quoted when it holds a comma, quote or line break.
fn cell(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) { format!("\"{}\"", text.replace('"', "\"\"")) } else { text.to_string() }
}

/// A float in CSV: shortest round-trip form; empty when not finite.
fn num(v: f64) -> String {
    if v.is_finite() { format!("{v}") } else { String::new() }
}

impl SweepResult {
    /// `key=value` of every key for combination `variant`, space-separated.
    pub fn label(&self, variant: usize) -> String {
        let values = &self.combinations[variant];
        let label = self.keys.iter().zip(values).map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(" ");
        if label.is_empty() { "all runs".into() } else { label }
    }

    fn runs_of(&self, variant: usize) -> Vec<&RunTrace> {
        self.runs.iter().filter(|r| r.variant == variant).collect()
    }

    /// `sweep.csv`: one line per generation of every finished run; no
    /// wall-clock column, so the same sweep gives the same bytes at any
    /// thread count.
    pub fn csv(&self) -> String {
        let mut s = String::from("variant");
        for k in &self.keys {
            let _ = write!(s, ",{}", cell(k));
        }
        s.push_str(",run,seed,generation,evaluations,best_fitness,max_fitness,mean_fitness\n");
        for r in &self.runs {
            let values: String = self.combinations[r.variant].iter().map(|v| format!(",{}", cell(v))).collect();
            for p in &r.points {
                let _ = writeln!(
                    s,
                    "{}{values},{},{},{},{},{},{},{}",
                    r.variant,
                    r.run,
                    r.seed,
                    p.generation,
                    p.evaluations,
                    num(p.best),
                    num(p.max),
                    num(p.mean)
                );
            }
        }
        s
    }

    /// `sweep.svg`: the mean ± sd over runs of the best fitness so far, one
    /// line per combination, by generation (a generation is drawn while
    /// every run of the combination has reached it with a valid best) and
    /// by evaluations (the runs' mean evaluations at that generation).
    pub fn svg(&self, title: &str) -> String {
        let mut by_generation = Vec::new();
        let mut by_evaluations = Vec::new();
        for v in 0..self.combinations.len() {
            let runs = self.runs_of(v);
            if runs.is_empty() {
                continue;
            }
            let last = runs.iter().map(|r| r.points.len()).min().unwrap_or(0);
            let at = |g: usize| -> Option<Vec<f64>> {
                runs.iter().map(|r| Some(r.points[g].best).filter(|b| b.is_finite())).collect()
            };
            let (name, color) = (self.label(v), palette(v));
            let generation = |g: usize| runs[0].points[g].generation as f64;
            by_generation.push(mean_sd_series(&name, color, (0..last).map(|g| (generation(g), at(g)))));
            let evals = |g: usize| runs.iter().map(|r| r.points[g].evaluations as f64).sum::<f64>() / runs.len() as f64;
            by_evaluations.push(mean_sd_series(&name, color, (0..last).map(|g| (evals(g), at(g)))));
        }
        let runs = self.runs.iter().map(|r| r.run).max().map_or(0, |r| r + 1);
        charts_svg(&[
            Chart {
                title: format!("{title}: best fitness, mean ± sd of {runs} runs"),
                x_label: "generation".into(),
                y_label: "best fitness".into(),
                series: by_generation,
            },
            Chart {
                title: "by evaluations".into(),
                x_label: "evaluations".into(),
                y_label: "best fitness".into(),
                series: by_evaluations,
            },
        ])
    }

    /// The summary table (Markdown): per combination, the runs, the final
    /// best fitness (mean ± sd, min, max), the generations and evaluations
    /// made and the mean seconds per run.
    pub fn summary(&self) -> String {
        let mut s = String::new();
        let keys: Vec<String> = self.keys.iter().map(|k| format!(" {k} |")).collect();
        let _ = writeln!(
            s,
            "|{} runs | best fitness (mean ± sd) | min | max | generations | evaluations | s/run |",
            keys.concat()
        );
        let _ = writeln!(s, "|{}---:|---:|---:|---:|---:|---:|---:|", "---|".repeat(self.keys.len()));
        for (v, values) in self.combinations.iter().enumerate() {
            let runs = self.runs_of(v);
            let finals: Vec<f64> = runs.iter().filter_map(|r| r.points.last()).map(|p| p.best).collect();
            let valid: Vec<f64> = finals.iter().copied().filter(|b| b.is_finite()).collect();
            let (m, sd) = mean_sd(&valid);
            let (lo, hi) = valid.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
            let n = runs.len().max(1) as f64;
            let mean_of = |f: &dyn Fn(&RunTrace) -> f64| runs.iter().map(|r| f(r)).sum::<f64>() / n;
            let generations = mean_of(&|r| r.points.last().map_or(0.0, |p| p.generation as f64));
            let evaluations = mean_of(&|r| r.points.last().map_or(0.0, |p| p.evaluations as f64));
            let seconds = mean_of(&|r| r.seconds);
            let cells: String = values.iter().map(|v| format!(" {} |", v.replace('|', "\\|"))).collect();
            let stat = |x: f64| if x.is_finite() { format!("{x:.4}") } else { "–".into() };
            let _ = writeln!(
                s,
                "|{cells} {} | {} ± {} | {} | {} | {generations:.0} | {evaluations:.0} | {seconds:.2} |",
                runs.len(),
                stat(m),
                stat(sd),
                stat(lo),
                stat(hi),
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(variant: usize, run: usize, bests: &[f64]) -> RunTrace {
        let points = bests
            .iter()
            .enumerate()
            .map(|(g, &best)| GenPoint {
                generation: g,
                evaluations: 10 * (g as u64 + 1),
                best,
                max: best,
                mean: best - 1.0,
            })
            .collect();
        RunTrace { variant, run, seed: 7 + run as u64, points, seconds: 0.5 }
    }

    fn sweep() -> SweepResult {
        SweepResult {
            keys: vec!["ga.population".into(), "ga.selection.first".into()],
            combinations: vec![vec!["10".into(), "{tournament=3}".into()], vec!["50".into(), "\"random\"".into()]],
            runs: vec![run(0, 0, &[1.0, 2.0]), run(0, 1, &[3.0, 4.0]), run(1, 0, &[f64::NAN, 0.5, 0.75])],
        }
    }

    #[test]
    fn csv_quotes_values_and_has_a_line_per_generation() {
        let csv = sweep().csv();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines[0],
            "variant,ga.population,ga.selection.first,run,seed,generation,evaluations,best_fitness,max_fitness,mean_fitness"
        );
        assert_eq!(lines[1], "0,10,{tournament=3},0,7,0,10,1,1,0");
        assert_eq!(lines[5], "1,50,\"\"\"random\"\"\",0,7,0,10,,,", "NaN is an empty cell");
        assert_eq!(lines.len(), 1 + 2 + 2 + 3);
        assert_eq!(cell("{a=1,b=2}"), "\"{a=1,b=2}\"");
    }

    #[test]
    fn plot_and_summary_have_a_line_per_combination() {
        let s = sweep();
        let svg = s.svg("ship");
        assert_eq!(svg.matches("<polyline").count(), 4, "two combinations × two panels");
        assert!(svg.contains("ga.population=10 ga.selection.first={tournament=3}"), "{svg}");
        assert!(svg.contains("mean ± sd of 2 runs"));
        let table = s.summary();
        let rows: Vec<&str> = table.lines().collect();
        assert_eq!(rows.len(), 4);
        assert!(
            rows[2].starts_with("| 10 | {tournament=3} | 2 | 3.0000 ± 1.0000 | 2.0000 | 4.0000 | 1 | 20 |"),
            "{table}"
        );
        assert!(rows[3].contains("| 1 | 0.7500 ± 0.0000 |"), "{table}");
    }
}
