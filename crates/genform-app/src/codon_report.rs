//! Run reports of codon scenes: `stats.csv` with the invalid reasons,
//! `fitness.svg` with the surface criteria, `best-codons.json`, and
//! previews of surfaces seen with +z up.

use genform_core::{GuideKind, Scene};
use genform_export::plot::{Chart, Series, charts_svg};
use std::fmt::Write as _;

use crate::codon_objective::{CodonObjective, Invalid, InvalidCounts, ScoreDetail};
use crate::report::{self, Row};
use genform_evolve::{Codons, Individual};

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

/// A number to 4 significant digits, for [`look`].
fn sig4(v: f64) -> String {
    if v == 0.0 || !v.is_finite() { format!("{v}") } else { format!("{v:.3e}") }
}

/// What a model looks like in a gallery, as text: per surface its face
/// count, the scene's instance and polyline counts, its bounds and the
/// scorer's `measures` (the surface criteria's raw values, or a target's
/// covered cells), numbers to 4 significant digits. Two individuals with
/// the same look draw the same picture, give or take an edge's colour or
/// a vertex splitting a straight edge: GE phenotypes often differ only in
/// rules that never fire or in an edge type, so a gallery of distinct
/// phenotype texts can show one surface 16 times. Galleries keep one
/// individual per look.
pub fn look(scene: &Scene, measures: &[f64]) -> String {
    let mut out = String::new();
    for s in &scene.surfaces {
        let _ = write!(out, "surface {} faces; ", s.face_count());
    }
    let _ = write!(out, "{} instances {} polylines; ", scene.instances.len(), scene.polylines.len());
    if let Some((lo, hi)) = scene.bounds(Default::default()) {
        let corners: Vec<String> = lo.to_array().into_iter().chain(hi.to_array()).map(|v| sig4(v.into())).collect();
        let _ = write!(out, "bounds {}; ", corners.join(" "));
    }
    let values: Vec<String> = measures.iter().map(|&m| sig4(m)).collect();
    let _ = write!(out, "measures {}", values.join(" "));
    out
}

/// What a surface looks like in a gallery, as text: per surface its face
/// count, then the surface criteria's raw values (`criteria`), numbers to 4
/// significant digits. Unlike [`look`] it leaves out the bounds: a surface
/// and its mirror image or a shifted copy (GE finds many: a rule set that
/// turns left where another turns right) score alike and look alike, but
/// their bounds differ, so galleries of Genr8 runs showed one surface
/// twice with the same score (canopy, seed 3: two cells at 3.8118). Two
/// surfaces with one face count and one set of criteria values show once.
pub fn surface_look(scene: &Scene, criteria: &[f64]) -> String {
    let mut out = String::new();
    for s in &scene.surfaces {
        let _ = write!(out, "surface {} faces; ", s.face_count());
    }
    let values: Vec<String> = criteria.iter().map(|&m| sig4(m)).collect();
    let _ = write!(out, "criteria {}", values.join(" "));
    out
}

/// The look a gallery compares for a model scored with `detail`: Genr8
/// surfaces by [`surface_look`], targets' counts by [`look`].
pub fn gallery_look(scene: &Scene, detail: &ScoreDetail) -> String {
    match detail {
        ScoreDetail::Surface(s) => surface_look(scene, &s.components().iter().map(|c| c.measure).collect::<Vec<_>>()),
        ScoreDetail::Counts(c) => look(scene, &[c.good, c.bad, c.overlap, c.outside]),
    }
}

/// The individuals a codon run's `gallery.png` shows: going down
/// `population` (best first), each valid individual whose
/// [`gallery_look`] is new, at most `n`, as its index in `population` and
/// its model. Individuals that cannot be rebuilt are skipped.
pub fn gallery_picks(objective: &CodonObjective, population: &[Individual<Codons>], n: usize) -> Vec<(usize, Scene)> {
    let looks = population.iter().enumerate().filter(|(_, ind)| ind.is_valid()).filter_map(|(i, ind)| {
        let e = objective.express(&ind.genome).ok()?;
        Some((gallery_look(&e.scene, &e.detail), (i, e.scene)))
    });
    distinct_looks(looks, n)
}

/// Up to `n` of `items` (`(look, item)`, best individual first) whose
/// looks differ: the first of each look, in order. Fewer than `n` when
/// fewer distinct looks exist, so a converged run shows a short gallery
/// rather than copies. Reads `items` only until it has `n`.
pub fn distinct_looks<T>(items: impl IntoIterator<Item = (String, T)>, n: usize) -> Vec<T> {
    let mut seen = std::collections::HashSet::new();
    items.into_iter().filter(|(l, _)| seen.insert(l.clone())).map(|(_, t)| t).take(n).collect()
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
    use genform_core::surface::Surface;
    use genform_evolve::GenerationStats;
    use std::collections::HashSet;

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
        assert!(svg.contains("contribution −w·e per criterion"), "the form names the contribution");
        assert_eq!(fitness_svg("t", &[row(0), row(1)], &[], "w/(1+e)").matches("<polyline").count(), 6);
    }

    /// A square of `faces` strips in the xy plane, its edges of `edge_type`.
    fn strips(faces: u32, edge_type: u32) -> Scene {
        let mut s = Surface::new(0);
        for k in 0..=faces {
            let x = k as f32 / faces as f32;
            s.positions.extend([glam::Vec3::new(x, 0.0, 0.0), glam::Vec3::new(x, 1.0, 0.0)]);
        }
        for k in 0..faces {
            s.push_face(&[2 * k, 2 * k + 2, 2 * k + 3, 2 * k + 1]);
            s.edges.push(genform_core::surface::SurfaceEdge { a: 2 * k, b: 2 * k + 2, kind: edge_type });
        }
        let mut scene = Scene::new();
        scene.surfaces.push(s);
        scene
    }

    #[test]
    fn galleries_keep_one_individual_per_look() {
        // A converged population: the best surface five times (two with
        // another edge type: another phenotype text, the same surface),
        // then a surface with more faces, then one scored differently.
        let population = [
            look(&strips(4, 1), &[10.0, 0.5]),
            look(&strips(4, 2), &[10.0, 0.5]),
            look(&strips(4, 1), &[10.0, 0.5]),
            look(&strips(4, 2), &[10.0, 0.500001]),
            look(&strips(4, 1), &[10.0, 0.5]),
            look(&strips(5, 1), &[10.0, 0.5]),
            look(&strips(4, 1), &[11.0, 0.5]),
        ];
        let ranked = || population.iter().cloned().enumerate().map(|(i, l)| (l, i));
        assert_eq!(distinct_looks(ranked(), 16), [0, 5, 6], "fewer cells when fewer looks exist");
        let mut read = 0;
        let counted = ranked().inspect(|_| read += 1);
        assert_eq!(distinct_looks(counted, 2), [0, 5]);
        assert_eq!(read, 6, "stops reading once it has enough");
        assert!(look(&strips(4, 1), &[]).starts_with("surface 4 faces; 0 instances 0 polylines; bounds"));
    }

    #[test]
    fn surface_looks_ignore_where_a_surface_lies_and_which_way_it_faces() {
        let mut mirrored = strips(4, 1);
        for p in &mut mirrored.surfaces[0].positions {
            *p = glam::Vec3::new(-p.x + 3.0, p.y, p.z);
        }
        assert_ne!(look(&strips(4, 1), &[10.0, 0.5]), look(&mirrored, &[10.0, 0.5]), "bounds differ");
        assert_eq!(surface_look(&strips(4, 1), &[10.0, 0.5]), surface_look(&mirrored, &[10.0, 0.5]));
        assert_ne!(surface_look(&strips(4, 1), &[10.0, 0.5]), surface_look(&strips(5, 1), &[10.0, 0.5]));
        assert_ne!(surface_look(&strips(4, 1), &[10.0, 0.5]), surface_look(&strips(4, 1), &[10.0, 0.5001]));
        assert_eq!(surface_look(&strips(4, 2), &[10.0, 0.5]), "surface 4 faces; criteria 1.000e1 5.000e-1");
    }

    #[test]
    fn a_genr8_gallery_never_shows_one_face_count_and_criteria_twice() {
        use genform_evolve::{Ge, Optimizer};
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/genr8_canopy.toml");
        let loaded = crate::codon_scene::CodonSceneConfig::load(&path).unwrap();
        let objective = CodonObjective::new(&loaded).unwrap();
        let mut ge = Ge::new(loaded.config.ge.clone(), 3).unwrap();
        for _ in 0..30 {
            Optimizer::step(&mut ge, &objective);
        }
        let population = ge.population();
        // Face counts and criteria to 4 significant digits.
        let described = |i: usize| {
            let e = objective.express(&population[i].genome).unwrap();
            let ScoreDetail::Surface(s) = &e.detail else { panic!("a surface scene") };
            let faces: Vec<usize> = e.scene.surfaces.iter().map(|s| s.face_count()).collect();
            let criteria: Vec<String> = s.components().iter().map(|c| format!("{:.3e}", c.measure)).collect();
            (faces, criteria)
        };
        let valid: Vec<usize> = (0..population.len()).filter(|&i| population[i].is_valid()).collect();
        let surfaces: HashSet<_> = valid.iter().map(|&i| described(i)).collect();
        // The population holds one surface more than once (copies, and rule
        // sets that differ only where nothing is drawn).
        assert!(surfaces.len() < valid.len(), "{} surfaces in {} members", surfaces.len(), valid.len());
        let picks = gallery_picks(&objective, population, 16);
        assert_eq!(picks.len(), surfaces.len().min(16), "as many cells as distinct surfaces allow");
        let mut shown = HashSet::new();
        for (i, _) in &picks {
            assert!(shown.insert(described(*i)), "#{i} shows a surface already shown");
        }
        assert_eq!(picks[0].0, 0, "the best first");
        assert!(picks.windows(2).all(|w| w[0].0 < w[1].0), "then down the ranks");
    }

    #[test]
    fn codons_json_round_trips() {
        let text = codons_json(&[1, 2, 999], 0.25, "ge", 4, "s.toml");
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["codons"], serde_json::json!([1, 2, 999]));
        assert_eq!((v["fitness"].as_f64(), v["seed"].as_u64()), (Some(0.25), Some(4)));
    }
}
