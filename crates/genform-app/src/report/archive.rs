//! Quality-diversity reports: MAP-Elites' archive (`archive.csv`,
//! `archive.png`) and the choice of the distinct individuals `gallery.png`
//! shows for every algorithm.
//!
//! Both work on individuals with their two descriptor values (what the
//! scene's `[map_elites]` names, by default genome length and bounding-box
//! aspect); the caller measures them on the derived models.

use super::gallery::gallery_png_captioned;
use crate::files::write_atomic;
use anyhow::{Context, Result};
use genform_core::{Generator, Genome, Limits, Scene};
use genform_evolve::{Individual, MapElitesConfig};
use genform_export::plot::{caption_rgb, caption_size, encode_png_rgb};
use genform_score::Descriptor;
use std::fmt::Write as _;
use std::path::Path;

/// Most individuals `gallery.png` shows.
pub const GALLERY_SIZE: usize = 16;

/// Smallest distance between two gallery picks, in descriptor space with
/// each axis scaled to its range (0..1): two thirds of a cell of the
/// default 8 × 8 archive, so near-copies of one design are shown once.
pub const GALLERY_SPACING: f64 = 0.08;

/// An individual as reports see it.
#[derive(Clone, Copy, Debug)]
pub struct Described<'a> {
    /// Its genome.
    pub genome: &'a Genome,
    /// Its fitness.
    pub fitness: f64,
    /// Its two descriptor values.
    pub descriptors: [f64; 2],
}

/// The diversity reports of one tree-scene run: `gallery.png` for every
/// algorithm, and for MAP-Elites `archive.csv`, `archive.png` and `elites/`.
pub struct Reports<'a> {
    /// Expresses genomes.
    pub generator: &'a dyn Generator,
    /// Derivation limits.
    pub limits: Limits,
    /// The scene's `[map_elites]` with every range set
    /// ([`crate::optimizers::OptimizerSettings::map_elites`]): its
    /// descriptors are the gallery's too.
    pub config: MapElitesConfig,
}

impl Reports<'_> {
    /// The valid individuals of `population` with their models and
    /// descriptor values, in population order.
    pub fn describe<'p>(&self, population: &'p [Individual]) -> Result<Vec<(Scene, Described<'p>)>> {
        let descriptors =
            self.config.descriptors.each_ref().map(|d| Descriptor::from_name(&d.name).unwrap_or(Descriptor::Length));
        population
            .iter()
            .filter(|i| i.is_valid())
            .map(|i| {
                let mut scene = Scene::new();
                self.generator.express(&i.genome, &self.limits, &mut scene).context("cannot build a model")?;
                let values = descriptors.map(|d| d.value(i.genome.len(), &scene));
                Ok((scene, Described { genome: &i.genome, fitness: i.fitness, descriptors: values }))
            })
            .collect()
    }

    /// `gallery.png`: the best distinct individuals of `described`
    /// ([`pick_distinct`]), captioned with fitness and descriptors.
    pub fn gallery_png(&self, described: &[(Scene, Described)]) -> Vec<u8> {
        let items: Vec<Described> = described.iter().map(|(_, d)| *d).collect();
        let ranges = self.config.descriptors.each_ref().map(|d| d.range.unwrap_or([0.0, 1.0]));
        let names = self.config.descriptors.each_ref().map(|d| d.name.as_str());
        let picked = pick_distinct(&items, ranges, GALLERY_SPACING, GALLERY_SIZE);
        let tiles: Vec<(&Scene, String)> = picked
            .iter()
            .enumerate()
            .map(|(rank, &i)| (&described[i].0, caption(rank + 1, &items[i], names)))
            .collect();
        gallery_png_captioned(&tiles)
    }

    /// Writes `archive.csv`, `archive.png` and `elites/cell-C-R.json` (each
    /// elite's genome, as `best-genome.json`) for the elites `described`
    /// into `out`; `elites/` is emptied first, so it holds this run's only.
    pub fn write_archive(&self, out: &Path, described: &[(Scene, Described)]) -> Result<()> {
        let elites: Vec<Described> = described.iter().map(|(_, d)| *d).collect();
        write_atomic(&out.join("archive.csv"), archive_csv(&self.config, &elites).as_bytes())?;
        write_atomic(&out.join("archive.png"), &archive_png(&self.config, &elites))?;
        let dir = out.join("elites");
        if dir.exists() {
            crate::gate::check_write(&dir)?;
            std::fs::remove_dir_all(&dir).with_context(|| format!("cannot empty {}", dir.display()))?;
        }
        crate::gate::create_dir(&dir)?;
        let graph = self.generator.graph();
        for e in &elites {
            let [c, r] = self.config.cell(e.descriptors);
            write_atomic(&dir.join(format!("cell-{c}-{r}.json")), e.genome.to_json(graph).as_bytes())?;
        }
        Ok(())
    }
}

/// Indices of the best distinct individuals among `items`, best first, at
/// most `max`: going down by fitness (ties in input order), an individual
/// is skipped when it is invalid, when its genome equals a picked one's,
/// or when its descriptors lie within `spacing` of a picked one's
/// (Euclidean, each axis divided by the width of its `ranges` entry).
/// A NaN descriptor counts as equal to anything on that axis.
pub fn pick_distinct(items: &[Described], ranges: [[f64; 2]; 2], spacing: f64, max: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..items.len()).filter(|&i| items[i].fitness.is_finite()).collect();
    order.sort_by(|&a, &b| items[b].fitness.total_cmp(&items[a].fitness));
    let scaled = |d: &Described| {
        let mut out = [0.0; 2];
        for k in 0..2 {
            out[k] = d.descriptors[k] / (ranges[k][1] - ranges[k][0]);
        }
        out
    };
    let mut picked: Vec<usize> = Vec::new();
    for i in order {
        if picked.len() == max {
            break;
        }
        let x = scaled(&items[i]);
        let close = picked.iter().any(|&p| {
            let y = scaled(&items[p]);
            let d2: f64 = (0..2).map(|k| if (x[k] - y[k]).is_nan() { 0.0 } else { (x[k] - y[k]).powi(2) }).sum();
            items[p].genome == items[i].genome || d2 < spacing * spacing
        });
        if !close {
            picked.push(i);
        }
    }
    picked
}

/// A descriptor value in a caption or table: integers without decimals,
/// the rest with two.
pub fn short(v: f64) -> String {
    if v.is_finite() && v.fract() == 0.0 && v.abs() < 1e9 { format!("{v}") } else { format!("{v:.2}") }
}

/// The caption of gallery pick `rank` (from 1): rank and fitness on the
/// first line, the descriptors on the second.
pub fn caption(rank: usize, item: &Described, names: [&str; 2]) -> String {
    let [a, b] = item.descriptors;
    format!("#{rank} fitness {:.4}\n{}={} {}={}", item.fitness, names[0], short(a), names[1], short(b))
}

/// `archive.csv`: one line per elite in cell order: the cell (`column` is
/// the bin of the first descriptor, `row` of the second), the descriptor
/// values under their names, the fitness and the genome's genes.
pub fn archive_csv(config: &MapElitesConfig, elites: &[Described]) -> String {
    let [a, b] = config.descriptors.each_ref().map(|d| d.name.as_str());
    let mut rows: Vec<([usize; 2], &Described)> = elites.iter().map(|e| (config.cell(e.descriptors), e)).collect();
    rows.sort_by_key(|(cell, _)| *cell);
    let mut s = format!("column,row,{a},{b},fitness,genes\n");
    for ([c, r], e) in rows {
        let [x, y] = e.descriptors;
        let _ = writeln!(s, "{c},{r},{x},{y},{},{}", e.fitness, e.genome.len());
    }
    s
}

/// Colour of `t` in 0..1 on a dark-blue → green → yellow ramp (viridis'
/// ends and middle), so better cells are brighter.
fn ramp(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] =
        [[68.0, 1.0, 84.0], [59.0, 82.0, 139.0], [33.0, 145.0, 140.0], [94.0, 201.0, 98.0], [253.0, 231.0, 37.0]];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 } * 4.0;
    let i = (t as usize).min(3);
    let f = t - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [0, 1, 2].map(|k| (a[k] + (b[k] - a[k]) * f).round() as u8)
}

/// `archive.png`: the descriptor grid, the first descriptor to the right
/// and the second upwards, each filled cell coloured by its elite's
/// fitness (dark = the archive's worst, yellow = its best), empty cells
/// grey; a header names the axes with their ranges and the fitness span.
pub fn archive_png(config: &MapElitesConfig, elites: &[Described]) -> Vec<u8> {
    const EMPTY: [u8; 3] = [200, 200, 200];
    const MARGIN: usize = 8;
    let [cols, rows] = config.shape();
    let (lo, hi) = elites
        .iter()
        .map(|e| e.fitness)
        .filter(|f| f.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), f| (a.min(f), b.max(f)));
    let axis = |k: usize| {
        let d = &config.descriptors[k];
        let [a, b] = d.range.unwrap_or([f64::NAN; 2]);
        format!("{} {} to {} ({} bins)", d.name, short(a), short(b), d.bins)
    };
    let fitness = if lo.is_finite() { format!("{lo:.4} dark to {hi:.4} yellow") } else { "none".into() };
    let header =
        format!("right: {}\nup: {}\n{} of {} cells, fitness {fitness}", axis(0), axis(1), elites.len(), cols * rows);
    // The header sets the width when it is wider than the grid, so no line is cut.
    let (text_w, text_h) = caption_size(&header);
    let header_h = text_h as usize + 12;
    let px = (480 / cols.max(rows)).clamp(2, 40);
    let (gw, gh) = (cols * px, rows * px);
    let width = (gw + 2 * MARGIN).max(text_w as usize + 2 * MARGIN).max(400);
    let height = header_h + gh + MARGIN;
    let mut img = vec![255u8; width * height * 3];
    let mut colour = vec![EMPTY; cols * rows];
    for e in elites.iter().filter(|e| e.fitness.is_finite()) {
        let [c, r] = config.cell(e.descriptors);
        let t = if hi > lo { (e.fitness - lo) / (hi - lo) } else { 1.0 };
        colour[c * rows + r] = ramp(t);
    }
    for c in 0..cols {
        for r in 0..rows {
            let (x0, y0) = (MARGIN + c * px, header_h + (rows - 1 - r) * px);
            // One-pixel white seams between cells when they are big enough to show them.
            let seam = usize::from(px >= 6);
            for y in y0..y0 + px - seam {
                for x in x0..x0 + px - seam {
                    img[(y * width + x) * 3..][..3].copy_from_slice(&colour[c * rows + r]);
                }
            }
        }
    }
    caption_rgb(&mut img, width as u32, MARGIN as u32, 4, &header);
    encode_png_rgb(&img, width as u32, height as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_evolve::DescriptorAxis;

    fn genomes(n: usize) -> Vec<Genome> {
        let graph = genform_evolve::fixtures::ship();
        (0..n)
            .map(|i| {
                let mut rng = genform_core::Rng::from_seed(i as u64);
                genform_evolve::operators::initial(&graph, &genform_core::Limits::default(), [3, 12], &mut rng)
            })
            .collect()
    }

    fn config() -> MapElitesConfig {
        MapElitesConfig {
            descriptors: [DescriptorAxis::new("length", 4, [0.0, 40.0]), DescriptorAxis::new("aspect", 3, [1.0, 4.0])],
            ..MapElitesConfig::default()
        }
    }

    #[test]
    fn a_converged_population_yields_distinct_picks() {
        let g = genomes(4);
        // 20 copies of one design (a converged GA), a near-copy with another
        // genome but the same shape, and three other designs.
        let mut items: Vec<Described> = Vec::new();
        for _ in 0..20 {
            items.push(Described { genome: &g[0], fitness: 1.0, descriptors: [20.0, 2.0] });
        }
        items.push(Described { genome: &g[1], fitness: 0.99, descriptors: [21.0, 2.01] });
        items.push(Described { genome: &g[2], fitness: 0.7, descriptors: [5.0, 1.2] });
        items.push(Described { genome: &g[1], fitness: 0.5, descriptors: [35.0, 3.5] });
        items.push(Described { genome: &g[3], fitness: f64::NAN, descriptors: [30.0, 1.0] });
        items.push(Described { genome: &g[3], fitness: 0.2, descriptors: [30.0, f64::NAN] });
        let ranges = [[0.0, 40.0], [1.0, 4.0]];
        let picked = pick_distinct(&items, ranges, GALLERY_SPACING, GALLERY_SIZE);
        // The best copy, then the other designs by fitness; the near-copy
        // and the invalid one are skipped, a NaN descriptor matches anything.
        assert_eq!(picked, [0, 21, 22, 24]);
        assert_eq!(pick_distinct(&items, ranges, 0.0, 2), [0, 20], "without spacing only copies are skipped");
    }

    #[test]
    fn captions_and_csv_name_the_descriptors() {
        let g = genomes(2);
        let d = Described { genome: &g[0], fitness: 0.123456, descriptors: [12.0, 2.345] };
        assert_eq!(caption(3, &d, ["length", "aspect"]), "#3 fitness 0.1235\nlength=12 aspect=2.35");
        let e = Described { genome: &g[1], fitness: -1.5, descriptors: [39.0, 1.0] };
        let csv = archive_csv(&config(), &[e, d]);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[0], "column,row,length,aspect,fitness,genes");
        assert_eq!(lines[1], format!("1,1,12,2.345,0.123456,{}", g[0].len()), "cell order");
        assert_eq!(lines[2], format!("3,0,39,1,-1.5,{}", g[1].len()));
    }

    #[test]
    fn archive_png_colours_filled_cells_and_greys_empty_ones() {
        let g = genomes(2);
        let elites = [
            Described { genome: &g[0], fitness: 0.0, descriptors: [5.0, 1.5] },
            Described { genome: &g[1], fitness: 1.0, descriptors: [35.0, 3.5] },
        ];
        let png = archive_png(&config(), &elites);
        let mut reader = png::Decoder::new(std::io::Cursor::new(&png)).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        let pixels: Vec<[u8; 3]> = buf.chunks(3).map(|p| [p[0], p[1], p[2]]).collect();
        let count = |c: [u8; 3]| pixels.iter().filter(|p| **p == c).count();
        let cell = count(ramp(0.0));
        assert!(cell > 100, "the worst elite's cell is dark blue");
        assert_eq!(count(ramp(1.0)), cell, "the best elite's cell is as big, in yellow");
        assert_eq!(count([200, 200, 200]), 10 * cell, "the other ten cells are grey");
        assert!(info.width >= 400);
    }
}
