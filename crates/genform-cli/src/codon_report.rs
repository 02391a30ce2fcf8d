//! Run reports of codon scenes: `stats.csv` with the invalid reasons,
//! `fitness.svg` with the surface criteria, `best-codons.json`, and
//! previews of surfaces seen with +z up.

use genform_core::{GuideKind, Scene};
use genform_export::plot::{Chart, Series, charts_svg};
use std::fmt::Write as _;

use crate::codon_objective::{Invalid, InvalidCounts};
use crate::report::{self, Row};

/// The best individual's criteria in one generation: `(name, contribution)`
/// per weighted criterion, in the scorer's order.
#[derive(Clone, Debug, PartialEq)]
pub struct CriteriaRow {
    /// Generation index.
    pub generation: usize,
    /// Each criterion's contribution: `w / (1 + e)` (bounded form) or
    /// `−w·e` (paper form).
    pub contributions: Vec<(&'static str, f64)>,
    /// Their sum, the fitness.
    pub total: f64,
}

/// `stats.csv` of a codon run: the tree runs' columns, then one
/// `invalid_<reason>` column per [`Invalid`] reason (invalid evaluations of
/// that generation; children equal to a parent are not evaluated again).
/// `invalid[i]` belongs to `rows[i]`.
pub fn stats_csv(rows: &[Row], invalid: &[InvalidCounts]) -> String {
    let base = report::stats_csv(rows);
    let mut out = String::with_capacity(base.len() + 32 * rows.len());
    for (i, line) in base.lines().enumerate() {
        out.push_str(line);
        if i == 0 {
            for r in Invalid::ALL {
                let _ = write!(out, ",invalid_{}", r.name());
            }
        } else {
            let counts = invalid.get(i - 1).copied().unwrap_or_default();
            for r in Invalid::ALL {
                let _ = write!(out, ",{}", counts.get(r));
            }
        }
        out.push('\n');
    }
    out
}

/// Colours of the criteria lines, in [`genform_score::SurfaceCriterion::ALL`] order.
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

/// `fitness.svg` of a codon run: max/avg/min fitness by generation; for
/// surface scenes the best individual's contribution of every criterion
/// and their total by generation, the chart titled with the form's
/// `formula` (`w/(1+e)` or `−w·e`, [`genform_score::SurfaceForm::contribution_formula`]);
/// fitness by time.
pub fn fitness_svg(title: &str, rows: &[Row], criteria: &[CriteriaRow], formula: &str) -> String {
    let mut charts = vec![report::fitness_by_generation(title, rows)];
    if let Some(first) = criteria.first() {
        let mut series: Vec<Series> = first
            .contributions
            .iter()
            .enumerate()
            .map(|(i, (name, _))| Series {
                name: (*name).into(),
                color: criterion_color(name).into(),
                points: criteria
                    .iter()
                    .filter_map(|c| c.contributions.get(i).map(|(_, v)| (c.generation as f64, *v)))
                    .collect(),
                band: Vec::new(),
            })
            .collect();
        series.push(Series {
            name: "total".into(),
            color: "#000000".into(),
            points: criteria.iter().map(|c| (c.generation as f64, c.total)).collect(),
            band: Vec::new(),
        });
        charts.push(Chart {
            title: format!("best individual: contribution {formula} of each criterion"),
            x_label: "generation".into(),
            y_label: "contribution".into(),
            series,
        });
    }
    charts.push(report::fitness_by_time(rows));
    charts_svg(&charts)
}

/// `scene` turned so that its +z points up in previews (the renderer's up
/// is +y; HEMLS surfaces grow in the xy plane with +z as the seed's normal).
pub fn z_up(scene: &Scene) -> Scene {
    let turn = |p: glam::Vec3| glam::Vec3::new(p.x, p.z, -p.y);
    let mut s = scene.clone();
    for surface in &mut s.surfaces {
        surface.positions.iter_mut().for_each(|p| *p = turn(*p));
    }
    for g in &mut s.guides {
        match &mut g.kind {
            GuideKind::Point { at, .. } => *at = turn(*at),
            GuideKind::Mesh(m) => {
                let mut mesh = (**m).clone();
                mesh.positions.iter_mut().for_each(|p| *p = turn(*p));
                *m = std::sync::Arc::new(mesh);
            }
        }
    }
    s
}

/// `best-codons.json`: the genome with what made and scored it.
pub fn codons_json(codons: &[u32], fitness: f64, algorithm: &str, seed: u64, scene: &str) -> String {
    let value = serde_json::json!({
        "scene": scene,
        "algorithm": algorithm,
        "seed": seed,
        "fitness": fitness,
        "length": codons.len(),
        "codons": codons,
    });
    serde_json::to_string_pretty(&value).unwrap_or_default() + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_evolve::GenerationStats;

    fn row(g: usize) -> Row {
        let mut stats = GenerationStats::of_population(g, &[]);
        (stats.max, stats.avg, stats.min) = (2.0, 1.0, 0.5);
        (stats, g as f64)
    }

    #[test]
    fn csv_has_a_column_per_reason() {
        let mut counts = InvalidCounts::default();
        counts.0[4] = 7;
        let csv = stats_csv(&[row(0), row(1)], &[InvalidCounts::default(), counts]);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].ends_with(",invalid_wrap_limit,invalid_depth_limit,invalid_empty_genome,invalid_repair_limit,invalid_parse,invalid_growth,invalid_element_limit,invalid_exhausted,invalid_derivation"));
        assert!(lines[2].ends_with(",0,0,0,0,7,0,0,0,0"), "{}", lines[2]);
        assert_eq!(lines[0].split(',').count(), lines[1].split(',').count());
    }

    #[test]
    fn surface_plot_has_a_line_per_criterion_and_the_total() {
        let criteria: Vec<CriteriaRow> = (0..3)
            .map(|g| CriteriaRow { generation: g, contributions: vec![("size", 0.5), ("symmetry", 0.9)], total: 1.4 })
            .collect();
        let svg = fitness_svg("t", &[row(0), row(1), row(2)], &criteria, "−w·e");
        // 3 panels: max/avg/min twice, size + symmetry + total once.
        assert_eq!(svg.matches("<polyline").count(), 9, "{svg}");
        assert!(svg.contains("symmetry") && svg.contains("total"));
        assert!(svg.contains("contribution −w·e of each criterion"), "the form names the contribution");
        assert_eq!(fitness_svg("t", &[row(0), row(1)], &[], "w/(1+e)").matches("<polyline").count(), 6);
    }

    #[test]
    fn codons_json_round_trips() {
        let text = codons_json(&[1, 2, 999], 0.25, "ge", 4, "s.toml");
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["codons"], serde_json::json!([1, 2, 999]));
        assert_eq!((v["fitness"].as_f64(), v["seed"].as_u64()), (Some(0.25), Some(4)));
    }
}
