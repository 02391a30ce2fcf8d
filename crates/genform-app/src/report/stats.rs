//! The statistics of a run, for every scene kind: `stats.csv` (one line
//! per generation, the optimizer's statistics and the run's own columns)
//! and `fitness.svg` (fitness by generation, the best model's criteria when
//! its scorer charts them, fitness by time). One function writes each.

use genform_evolve::GenerationStats;
use genform_export::plot::{Chart, Series, charts_svg};
use std::fmt::Write as _;

/// One generation's line of `stats.csv`: the optimizer's statistics and
/// the wall-clock seconds since the start of the run.
pub type Row = (GenerationStats, f64);

/// Column names of `stats.csv`, in order.
pub const CSV_HEADER: &str = "generation,evaluations,seconds,max_fitness,avg_fitness,min_fitness,invalid,eval_seconds,reproduction_seconds,crossover_retries,min_length,avg_length,max_length";

/// A float in CSV: shortest round-trip form, so identical runs give
/// identical text.
fn num(v: f64) -> String {
    if v.is_finite() { format!("{v}") } else { String::new() }
}

/// A column a run adds to `stats.csv` after the optimizer's (codon runs:
/// invalid evaluations by reason), one value per generation.
#[derive(Clone, Debug)]
pub struct Column {
    /// The header.
    pub name: String,
    /// A value per row (missing rows read 0).
    pub values: Vec<u64>,
}

/// The whole `stats.csv` text: [`CSV_HEADER`]'s columns, then `extra`.
pub fn stats_csv(rows: &[Row], extra: &[Column]) -> String {
    let mut s = String::from(CSV_HEADER);
    for c in extra {
        let _ = write!(s, ",{}", c.name);
    }
    s.push('\n');
    for (i, (r, seconds)) in rows.iter().enumerate() {
        let _ = write!(
            s,
            "{},{},{:.3},{},{},{},{},{:.6},{:.6},{},{},{},{}",
            r.generation,
            r.total_evaluations,
            seconds,
            num(r.max),
            num(r.avg),
            num(r.min),
            r.invalid,
            r.eval_time.as_secs_f64(),
            r.reproduction_time.as_secs_f64(),
            r.reproduction.crossover_retries,
            r.len_min,
            num(r.len_avg),
            r.len_max
        );
        for c in extra {
            let _ = write!(s, ",{}", c.values.get(i).copied().unwrap_or_default());
        }
        s.push('\n');
    }
    s
}

/// The best individual's criteria in one generation: `(name, contribution)`
/// per weighted criterion, in the scorer's order.
#[derive(Clone, Debug, PartialEq)]
pub struct CriteriaRow {
    /// Generation index.
    pub generation: usize,
    /// Each criterion's contribution (`w / (1 + e)`, or `−w·e`).
    pub contributions: Vec<(&'static str, f64)>,
    /// Their sum, the fitness.
    pub total: f64,
}

/// Colours of the criteria lines.
fn criterion_color(name: &str) -> &'static str {
    match name {
        "size" => "#1f77b4",
        "smoothness" => "#ff7f0e",
        "soft_boundary" => "#9467bd",
        "subdivisions" => "#2ca02c",
        "symmetry" => "#8c564b",
        "undulation" => "#e377c2",
        _ => "#7f7f7f",
    }
}

/// `fitness.svg`: max/avg/min fitness by generation; when the scorer
/// charts its criteria (`criteria` not empty), the best individual's
/// contribution of each and their total by generation, titled with
/// `formula` (what one criterion adds, e.g. `w/(1+e)`); fitness by time.
pub fn fitness_svg(title: &str, rows: &[Row], criteria: &[CriteriaRow], formula: &str) -> String {
    let mut charts = vec![fitness_by_generation(title, rows)];
    if let Some(first) = criteria.first() {
        let mut series: Vec<Series> = first
            .contributions
            .iter()
            .enumerate()
            .map(|(i, (name, _))| {
                let points = criteria
                    .iter()
                    .filter_map(|c| c.contributions.get(i).map(|(_, v)| (c.generation as f64, *v)))
                    .collect();
                Series::line(*name, criterion_color(name), points)
            })
            .collect();
        series.push(Series::line(
            "total",
            "#000000",
            criteria.iter().map(|c| (c.generation as f64, c.total)).collect(),
        ));
        charts.push(Chart {
            title: format!("best: contribution {formula} per criterion"),
            x_label: "generation".into(),
            y_label: "contribution".into(),
            series,
        });
    }
    charts.push(fitness_by_time(rows));
    charts_svg(&charts)
}

/// The max/avg/min fitness of `rows` against `x`. The y-axis follows max
/// and avg; min is clipped to it: a population's worst individual is often
/// far below (a broken design scores very low), and an axis stretched to it
/// squashes the best and the mean into one line at the top.
fn fitness_series(rows: &[Row], x: &dyn Fn(&Row) -> f64) -> Vec<Series> {
    [
        ("max", "#d62728", (|r: &Row| r.0.max) as fn(&Row) -> f64),
        ("avg", "#2ca02c", |r| r.0.avg),
        ("min", "#1f77b4", |r| r.0.min),
    ]
    .into_iter()
    .map(|(name, color, y)| Series {
        scales_axis: name != "min",
        ..Series::line(name, color, rows.iter().map(|r| (x(r), y(r))).collect())
    })
    .collect()
}

/// The first panel of `fitness.svg`: max/avg/min fitness by generation,
/// titled after the scene.
pub fn fitness_by_generation(title: &str, rows: &[Row]) -> Chart {
    Chart {
        title: format!("{title}: fitness by generation"),
        x_label: "generation".into(),
        y_label: "fitness".into(),
        series: fitness_series(rows, &|r| r.0.generation as f64),
    }
}

/// The last panel of `fitness.svg`: max/avg/min fitness by seconds.
pub fn fitness_by_time(rows: &[Row]) -> Chart {
    Chart {
        title: "fitness by time".into(),
        x_label: "seconds".into(),
        y_label: "fitness".into(),
        series: fitness_series(rows, &|r| r.1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(g: usize, max: f64) -> Row {
        let mut stats = GenerationStats::of_population(g, &[]);
        stats.total_evaluations = 10 * g as u64;
        (stats.max, stats.avg, stats.min) = (max, max - 1.0, max - 2.0);
        stats.eval_time = std::time::Duration::from_millis(100);
        stats.reproduction_time = std::time::Duration::from_millis(10);
        stats.reproduction.crossover_retries = 2;
        (stats.len_min, stats.len_avg, stats.len_max) = (4, 10.5, 20);
        (stats, 0.5 * g as f64)
    }

    #[test]
    fn csv_has_header_and_one_line_per_generation() {
        let csv = stats_csv(&[row(0, -3.5), row(1, 0.1)], &[]);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 3);
        assert_eq!(lines[0], CSV_HEADER);
        assert_eq!(lines[0].split(',').count(), lines[2].split(',').count());
        assert!(lines[2].starts_with("1,10,0.500,0.1,-0.9,-1.9,0,"));
    }

    #[test]
    fn non_finite_fitness_is_an_empty_cell() {
        let csv = stats_csv(&[row(0, f64::NEG_INFINITY)], &[]);
        assert!(csv.lines().nth(1).unwrap().contains(",,"));
    }

    #[test]
    fn plot_has_two_panels() {
        let svg = fitness_svg("ship", &[row(0, -1.0), row(1, 0.5)], &[], "");
        assert_eq!(svg.matches("<polyline").count(), 6);
    }

    #[test]
    fn extra_columns_follow_the_optimizers() {
        let extra = [Column { name: "invalid_parse".into(), values: vec![0, 7] }];
        let csv = stats_csv(&[row(0, 1.0), row(1, 2.0)], &extra);
        let lines: Vec<&str> = csv.lines().collect();
        assert!(lines[0].ends_with(",max_length,invalid_parse"), "{}", lines[0]);
        assert!(lines[2].ends_with(",7"), "{}", lines[2]);
        assert_eq!(lines[0].split(',').count(), lines[1].split(',').count());
    }

    #[test]
    fn criteria_get_a_panel_with_their_total() {
        let criteria: Vec<CriteriaRow> = (0..3)
            .map(|g| CriteriaRow { generation: g, contributions: vec![("size", 0.5), ("symmetry", 0.9)], total: 1.4 })
            .collect();
        let rows = [row(0, 2.0), row(1, 2.0), row(2, 2.0)];
        let svg = fitness_svg("t", &rows, &criteria, "−w·e");
        // 3 panels: max/avg/min twice, size + symmetry + total once.
        assert_eq!(svg.matches("<polyline").count(), 9, "{svg}");
        assert!(svg.contains("symmetry") && svg.contains("total"));
        assert!(svg.contains("contribution −w·e per criterion"), "the form names the contribution");
    }
}
