//! `genform compare` reports: the best fitness of every run over time as
//! CSV, the mean ± standard deviation per algorithm as an SVG plot (as the
//! thesis' figures 4.7 and 4.11), and a summary table.

use genform_export::plot::{Chart, Series, charts_svg};
use std::fmt::Write as _;

/// The best fitness found so far, at one moment of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TracePoint {
    /// Seconds since the run started.
    pub seconds: f64,
    /// Evaluations so far.
    pub evaluations: u64,
    /// Best fitness so far (NaN while none is valid).
    pub best: f64,
}

/// One run of one algorithm.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    /// Algorithm name.
    pub algorithm: String,
    /// Run index (0-based).
    pub run: usize,
    /// Its seed.
    pub seed: u64,
    /// Points in time order; the last is the end of the run.
    pub points: Vec<TracePoint>,
}

impl Trace {
    /// A run with no points yet.
    pub fn new(algorithm: &str, run: usize, seed: u64) -> Self {
        Trace { algorithm: algorithm.to_string(), run, seed, points: Vec::new() }
    }

    /// Records a point. While the best stays the same, the latest point
    /// replaces the previous one unless `spacing` seconds have passed since
    /// the flat stretch's last kept point, so every change of the best is
    /// kept exactly and flat stretches cost a point per `spacing`.
    pub fn record(&mut self, point: TracePoint, spacing: f64) {
        let n = self.points.len();
        if n >= 2
            && same(self.points[n - 1].best, point.best)
            && same(self.points[n - 2].best, point.best)
            && point.seconds - self.points[n - 2].seconds < spacing
        {
            self.points[n - 1] = point;
            return;
        }
        self.points.push(point);
    }

    /// The best fitness at `seconds` (the last point at or before it).
    pub fn best_at(&self, seconds: f64) -> Option<f64> {
        self.points.iter().take_while(|p| p.seconds <= seconds).last().map(|p| p.best).filter(|b| b.is_finite())
    }

    /// The final point.
    pub fn last(&self) -> Option<&TracePoint> {
        self.points.last()
    }
}

fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

/// Column names of `comparison.csv`.
pub const CSV_HEADER: &str = "algorithm,run,seed,seconds,evaluations,best_fitness";

/// `comparison.csv`: every kept point of every run.
pub fn csv(traces: &[Trace]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for t in traces {
        for p in &t.points {
            let best = if p.best.is_finite() { format!("{}", p.best) } else { String::new() };
            let _ = writeln!(s, "{},{},{},{:.3},{},{best}", t.algorithm, t.run, t.seed, p.seconds, p.evaluations);
        }
    }
    s
}

/// Mean and (population) standard deviation.
pub fn mean_sd(values: &[f64]) -> (f64, f64) {
    if values.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    (mean, var.sqrt())
}

/// A line of the mean of several runs with a ± one standard deviation
/// band: `values` gives, at each x, every run's value there (`None` when
/// some run has none, and the x is left out).
pub fn mean_sd_series(name: &str, color: &str, values: impl IntoIterator<Item = (f64, Option<Vec<f64>>)>) -> Series {
    let mut points = Vec::new();
    let mut band = Vec::new();
    for (x, v) in values {
        if let Some(v) = v {
            let (m, sd) = mean_sd(&v);
            points.push((x, m));
            band.push((x, m - sd, m + sd));
        }
    }
    Series { band, ..Series::line(name, color, points) }
}

/// A colour for line `i` of a plot with many (matplotlib's tab10, cycled).
pub fn palette(i: usize) -> &'static str {
    const TAB10: [&str; 10] =
        ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"];
    TAB10[i % TAB10.len()]
}

/// The algorithms of `traces`, in first-appearance order.
fn algorithms(traces: &[Trace]) -> Vec<&str> {
    let mut out: Vec<&str> = Vec::new();
    for t in traces {
        if !out.contains(&t.algorithm.as_str()) {
            out.push(&t.algorithm);
        }
    }
    out
}

/// `comparison.svg`: mean best fitness over time with a ± one standard
/// deviation band, one line per algorithm, sampled at 200 moments over
/// `budget` seconds. A moment is drawn once every run has a valid best.
pub fn svg(title: &str, traces: &[Trace], budget: f64) -> String {
    let series = algorithms(traces)
        .into_iter()
        .map(|alg| {
            let runs: Vec<&Trace> = traces.iter().filter(|t| t.algorithm == alg).collect();
            let moments = (0..=200).map(|k| budget * k as f64 / 200.0);
            let values = moments.map(|t| (t, runs.iter().map(|r| r.best_at(t)).collect()));
            mean_sd_series(alg, crate::optimizers::color(alg), values)
        })
        .collect();
    let runs = traces.iter().map(|t| t.run).max().map_or(0, |r| r + 1);
    charts_svg(&[Chart {
        title: format!("{title}: best fitness, mean ± sd of {runs} runs"),
        x_label: "seconds".into(),
        y_label: "best fitness".into(),
        series,
    }])
}

/// The summary table: per algorithm, the final best fitness (mean ± sd,
/// min, max over runs) and the evaluations made.
pub fn summary(traces: &[Trace]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<8} {:>4} {:>22} {:>11} {:>11} {:>12} {:>10}",
        "algorithm", "runs", "best fitness (mean ± sd)", "min", "max", "evaluations", "evals/s"
    );
    for alg in algorithms(traces) {
        let runs: Vec<&TracePoint> = traces.iter().filter(|t| t.algorithm == alg).filter_map(|t| t.last()).collect();
        let best: Vec<f64> = runs.iter().map(|p| p.best).filter(|b| b.is_finite()).collect();
        let (m, sd) = mean_sd(&best);
        let (lo, hi) = best.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(*v), b.max(*v)));
        let evals = runs.iter().map(|p| p.evaluations as f64).sum::<f64>() / runs.len().max(1) as f64;
        let secs = runs.iter().map(|p| p.seconds).sum::<f64>() / runs.len().max(1) as f64;
        let _ = writeln!(
            s,
            "{alg:<9} {:>4} {:>22} {lo:>11.4} {hi:>11.4} {evals:>12.0} {:>10.0}",
            runs.len(),
            format!("{m:.4} ± {sd:.4}"),
            evals / secs.max(1e-9)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trace(alg: &str, run: usize, points: &[(f64, f64)]) -> Trace {
        let mut t = Trace::new(alg, run, run as u64);
        for (i, &(seconds, best)) in points.iter().enumerate() {
            t.record(TracePoint { seconds, evaluations: 100 * (i as u64 + 1), best }, 0.5);
        }
        t
    }

    #[test]
    fn flat_stretches_are_thinned_but_steps_kept() {
        let t = trace("ga", 0, &[(0.0, 1.0), (0.1, 1.0), (0.2, 1.0), (0.3, 2.0), (0.4, 2.0), (0.45, 2.0), (2.0, 2.0)]);
        let secs: Vec<f64> = t.points.iter().map(|p| p.seconds).collect();
        assert_eq!(secs, vec![0.0, 0.2, 0.3, 0.45, 2.0]);
        assert_eq!(t.best_at(0.25), Some(1.0));
        assert_eq!(t.best_at(0.3), Some(2.0));
        assert_eq!(t.best_at(-1.0), None);
        assert_eq!(t.last().unwrap().evaluations, 700);
    }

    #[test]
    fn csv_svg_and_table() {
        let traces = vec![
            trace("ga", 0, &[(0.0, 1.0), (1.0, 3.0)]),
            trace("ga", 1, &[(0.0, 2.0), (1.0, 5.0)]),
            trace("mh", 0, &[(0.5, f64::NAN), (1.0, 0.5)]),
        ];
        let c = csv(&traces);
        let lines: Vec<&str> = c.lines().collect();
        assert_eq!(lines[0], CSV_HEADER);
        assert_eq!(lines[1], "ga,0,0,0.000,100,1");
        assert_eq!(lines[5], "mh,0,0,0.500,100,");
        let svg = svg("ship", &traces, 1.0);
        assert_eq!(svg.matches("<polyline").count(), 2);
        assert_eq!(svg.matches("<polygon").count(), 1, "one run's mh line is a single point: no band");
        assert!(svg.contains("mean ± sd of 2 runs"));
        let table = summary(&traces);
        assert!(table.lines().nth(1).unwrap().contains("4.0000 ± 1.0000"), "{table}");
        assert!(table.lines().nth(2).unwrap().starts_with("mh "), "{table}");
        assert_eq!(mean_sd(&[1.0, 3.0]), (2.0, 1.0));
    }
}
