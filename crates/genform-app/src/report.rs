//! Run reports of `genform evolve`: the per-generation statistics table,
//! the fitness plot and the gallery of the best individuals.

use genform_core::Scene;
use genform_evolve::GenerationStats;
use genform_export::RenderOptions;
use genform_export::plot::{Chart, Series, Tile, charts_svg, encode_png_rgb, gallery_rgb};
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

/// The whole `stats.csv` text.
pub fn stats_csv(rows: &[Row]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for (r, seconds) in rows {
        let _ = writeln!(
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
    }
    s
}

/// `fitness.svg`: max/avg/min fitness over generations and over seconds.
pub fn fitness_svg(title: &str, rows: &[Row]) -> String {
    charts_svg(&[fitness_by_generation(title, rows), fitness_by_time(rows)])
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

/// `gallery.png`: the given scenes in a 4-column grid of 256×256 previews,
/// each captioned with its rank and fitness under it.
pub fn gallery_png(scenes: &[(Scene, f64)]) -> Vec<u8> {
    let tiles: Vec<(&Scene, String)> =
        scenes.iter().enumerate().map(|(i, (scene, fitness))| (scene, format!("#{} {:.4}", i + 1, fitness))).collect();
    gallery_png_captioned(&tiles)
}

/// [`gallery_png`] with the captions given (lines split at `\n`).
///
/// Every cell is framed on its own model (the renderer's fitted 3/4 view),
/// so each model fills its cell. One camera fitted to all of them would
/// keep sizes comparable, but the models rarely share a place: ships grow
/// from the origin in different directions and lengths, so each one ended
/// up small in a corner of a frame made for their union. Sizes are in the
/// captions' descriptors and in `best.png`, which shows the target.
pub fn gallery_png_captioned(scenes: &[(&Scene, String)]) -> Vec<u8> {
    let tiles: Vec<Tile> = scenes
        .iter()
        .map(|(scene, caption)| {
            let opts = RenderOptions { width: 256, height: 256, camera: None, ..RenderOptions::default() };
            let (rgb, width, height) = genform_export::render_rgb(scene, &opts);
            Tile { rgb, width, height, caption: caption.clone() }
        })
        .collect();
    let (rgb, w, h) = gallery_rgb(&tiles, 4);
    encode_png_rgb(&rgb, w, h)
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
        let csv = stats_csv(&[row(0, -3.5), row(1, 0.1)]);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 3);
        assert_eq!(lines[0], CSV_HEADER);
        assert_eq!(lines[0].split(',').count(), lines[2].split(',').count());
        assert!(lines[2].starts_with("1,10,0.500,0.1,-0.9,-1.9,0,"));
    }

    #[test]
    fn non_finite_fitness_is_an_empty_cell() {
        let csv = stats_csv(&[row(0, f64::NEG_INFINITY)]);
        assert!(csv.lines().nth(1).unwrap().contains(",,"));
    }

    #[test]
    fn plot_has_two_panels() {
        let svg = fitness_svg("ship", &[row(0, -1.0), row(1, 0.5)]);
        assert_eq!(svg.matches("<polyline").count(), 6);
    }
}
