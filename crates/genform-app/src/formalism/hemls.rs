//! HEMLS surface grammars (`.gr8`, Genr8's map L-systems): grow a surface
//! from a seed polygon in an environment (`--env`), optionally write every
//! derivation step and smooth the result.

use anyhow::{Result, anyhow, bail};
use genform_core::{Scene, SourceFile, Surface};
use genform_hemls::{Environment, GrowError, Settings};
use std::path::{Path, PathBuf};

use super::options::{SAMPLE_STREAM, SampleRequest};
use super::row::{Formalism, Genomes, Loaded, LoadedGrammar, Sample, ends_with_any, no_generator};
use crate::files::{write_atomic, write_model};
use crate::text::compile_file;
use genform_export::preview_y_up;

/// The HEMLS row of the table.
pub struct Hemls;

/// Most Catmull–Clark steps `--smooth` takes (each multiplies the faces by about 4).
pub const MAX_SMOOTH: u32 = 6;

/// Pictures that show every step in one image with `--every-step`: small
/// multiples, one panel per step.
const PICTURES: &[&str] = &[".png", ".svg"];

/// Pixel size of one step's panel in an `--every-step` PNG.
const PANEL_PX: (u32, u32) = (400, 300);

impl Formalism for Hemls {
    fn name(&self) -> &'static str {
        "HEMLS surface grammar"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".gr8"]
    }

    fn sample_options(&self) -> &'static [&'static str] {
        &["--steps", "--env", "--every-step", "--smooth"]
    }

    fn genomes(&self) -> Genomes {
        Genomes::Phenotype
    }

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        let grammar = compile_file(path, genform_hemls::compile)?;
        Ok(Box::new(HemlsFile { path: path.to_path_buf(), grammar }))
    }
}

/// Reads an environment file (`--env`) into growth settings and an
/// environment; mesh boundaries are read relative to the file.
pub fn load_environment(path: &Path) -> Result<(Settings, Environment)> {
    let text = crate::text::read_text(path, "environment")?;
    let file = SourceFile::new(path.display().to_string(), text);
    let spec = genform_hemls::parse_env(&file).map_err(|d| crate::text::SourceErrors::new(&d, false))?;
    let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut load_mesh = |rel: &str| -> Result<genform_core::Mesh, String> {
        crate::gate::read_mesh(&base.join(rel)).map_err(|e| format!("{e:#}"))
    };
    // A mesh's errors start at the line naming it.
    spec.resolve(&mut load_mesh).map_err(anyhow::Error::msg)
}

/// A growth error in words, with the rule's file position when it names one.
pub fn grow_error(path: &Path, grammar: &genform_hemls::Hemls, e: GrowError) -> anyhow::Error {
    match &e {
        GrowError::Rule { span, .. } if span.end > span.start => match crate::text::read_text(path, "grammar") {
            Ok(text) => {
                let (line, col) = SourceFile::new(path.display().to_string(), text).line_col(span.start);
                anyhow!("{}:{line}:{col}: {e}", path.display())
            }
            Err(_) => anyhow!("{}: {e}", path.display()),
        },
        _ => anyhow!("{}: {e}", grammar.name),
    }
}

/// A compiled `.gr8` grammar and the file it came from.
struct HemlsFile {
    path: PathBuf,
    grammar: genform_hemls::Hemls,
}

/// A grown surface: every recorded step and the scene of the final one.
struct Grown {
    /// The final model (smoothed if asked), with the environment's guides.
    scene: Scene,
    /// Every step's surface when `--every-step` was given (the last one is
    /// the final, smoothed, surface).
    steps: Vec<Surface>,
    /// Catmull–Clark steps taken on the final surface.
    smooth: u32,
    summary: String,
}

impl HemlsFile {
    /// Grows the grammar with `settings` in `env`; `keep_steps` records every step.
    fn grow(
        &self,
        settings: &Settings,
        env: &Environment,
        seed: u64,
        keep_steps: bool,
    ) -> Result<(genform_hemls::Growth, Vec<Surface>)> {
        let mut rng = genform_core::Rng::stream(seed, &[SAMPLE_STREAM]);
        let mut steps = Vec::new();
        let mut record = |_: u32, map: &genform_hemls::Map| {
            if keep_steps {
                steps.push(map.to_surface(0));
            }
        };
        let growth = genform_hemls::grow_with(&self.grammar, settings, env, &mut rng, &mut record)
            .map_err(|e| grow_error(&self.path, &self.grammar, e))?;
        Ok((growth, steps))
    }
}

impl LoadedGrammar for HemlsFile {
    fn sample(&self, request: &SampleRequest) -> Result<Box<dyn Sample>> {
        let (mut settings, env) = match &request.env {
            Some(path) => load_environment(path)?,
            None => (Settings::default(), Environment::default()),
        };
        if let Some(steps) = request.steps {
            if steps > genform_hemls::envfile::MAX_STEPS {
                bail!("--steps {steps} is more than {} (growth is exponential)", genform_hemls::envfile::MAX_STEPS);
            }
            settings.steps = steps;
        }
        let smooth = request.smooth.unwrap_or(0);
        if smooth > MAX_SMOOTH {
            bail!("--smooth {smooth} is more than {MAX_SMOOTH} (each step multiplies the faces by about 4)");
        }
        let (growth, mut steps) = self.grow(&settings, &env, request.seed, request.every_step)?;
        let mut scene = Scene::new();
        let tag = scene.tag(&self.grammar.name);
        let mut surface = growth.surface(tag);
        let raw = (surface.positions.len(), surface.edges.len(), surface.face_count());
        if smooth > 0 {
            surface = surface.catmull_clark(smooth);
        }
        if let Some(last) = steps.last_mut() {
            *last = surface.clone();
        }
        for s in &mut steps {
            s.tag = tag;
        }
        scene.surfaces.push(surface);
        env.guides(&mut scene);
        let summary = format!(
            "{} seed {}: {} steps, {} vertices, {} edges, {} faces{}",
            self.grammar.name,
            request.seed,
            settings.steps,
            raw.0,
            raw.1,
            raw.2,
            if smooth > 0 { format!(" (smoothed {smooth}×)") } else { String::new() }
        );
        Ok(Box::new(Grown { scene, steps, smooth, summary }))
    }

    fn describe(&self) -> String {
        let g = &self.grammar;
        let mut out = format!(
            "HEMLS surface grammar {}: {}-sided seed, {} rules, Angle {}, {} joining{}\n\n",
            g.name,
            g.axiom.len(),
            g.rules.len(),
            g.angle,
            if g.sync { "synchronous (Sync)" } else { "asynchronous" },
            g.branch_angle.map(|a| format!(", BranchAngle {a}")).unwrap_or_default()
        );
        out.push_str(&g.to_string());
        let settings = Settings::default();
        out.push_str(&format!(
            "\ngrowth with the default settings (scale {}, start length {}, seed 0):\n",
            settings.scale.x, settings.start_length
        ));
        match self.grow(&settings, &Environment::default(), 0, false) {
            Ok((growth, _)) => {
                out.push_str("step  vertices     edges     faces  V-E+F\n");
                for s in &growth.steps {
                    let euler = s.vertices as i64 - s.edges as i64 + s.faces as i64;
                    out.push_str(&format!(
                        "{:>4} {:>9} {:>9} {:>9} {:>6}\n",
                        s.step, s.vertices, s.edges, s.faces, euler
                    ));
                }
            }
            Err(e) => out.push_str(&format!("  growth fails: {e}\n")),
        }
        out
    }

    fn into_generator(self: Box<Self>) -> Result<Loaded> {
        Err(no_generator(
            &self.path,
            "HEMLS grammars grow surfaces by rewriting and joining edges, with no derivation tree; evolve them \
             with a GE scene (a .bnf grammar that writes .gr8 rule sets, see docs/hemls.md)",
        ))
    }
}

/// Writes `scene` to `out`; PNG previews are seen with +z up.
fn write_surface_scene(scene: &Scene, out: &Path) -> Result<Vec<PathBuf>> {
    if ends_with_any(out, &[".png"]) { write_model(&preview_y_up(scene), out) } else { write_model(scene, out) }
}

/// `dir/name.ext` → `dir/name-step{k}.ext`.
fn step_path(out: &Path, k: usize) -> PathBuf {
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = out.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    out.with_file_name(format!("{stem}-step{k}{ext}"))
}

/// Columns of a grid of `n` panels: about square, never more than 4 (a
/// row of 5 800-pixel-wide steps would be too wide to read).
fn grid_columns(n: usize) -> usize {
    ((n as f64).sqrt().ceil() as usize).clamp(1, 4)
}

/// `scene` with every surface and guide moved by `by`.
fn translated(scene: &Scene, by: glam::Vec3) -> Scene {
    let mut s = scene.clone();
    for surface in &mut s.surfaces {
        surface.positions.iter_mut().for_each(|p| *p += by);
    }
    for g in &mut s.guides {
        match &mut g.kind {
            genform_core::GuideKind::Point { at, .. } => *at += by,
            genform_core::GuideKind::Mesh(m) => {
                let mut mesh = (**m).clone();
                mesh.positions.iter_mut().for_each(|p| *p += by);
                *m = std::sync::Arc::new(mesh);
            }
        }
    }
    s
}

impl Grown {
    /// Step `k`'s surface with the environment's guides.
    fn step_scene(&self, k: usize) -> Scene {
        let mut one = self.scene.clone();
        one.surfaces = vec![self.steps[k].clone()];
        one
    }

    /// The label of step `k`: its number and faces (and the smoothing, on
    /// the last step).
    fn step_label(&self, k: usize) -> String {
        let faces = self.steps[k].face_count();
        let smoothed = if k + 1 == self.steps.len() && self.smooth > 0 {
            format!(" (smoothed {}x)", self.smooth)
        } else {
            String::new()
        };
        format!("step {k}: {faces} face{}{smoothed}", if faces == 1 { "" } else { "s" })
    }

    /// The steps as small multiples in a PNG: one panel per step, labelled,
    /// all through one camera fitted to every step together, so growth
    /// reads as growth (the same place and scale in every panel).
    fn steps_png(&self) -> Vec<u8> {
        let (w, h) = PANEL_PX;
        let mut all = self.scene.clone();
        all.surfaces = self.steps.clone();
        let camera = genform_export::fitted_camera(&preview_y_up(&all), w, h);
        let tiles: Vec<genform_export::plot::Tile> = (0..self.steps.len())
            .map(|k| {
                let opts =
                    genform_export::RenderOptions { width: w, height: h, camera: Some(camera), ..Default::default() };
                let (rgb, width, height) = genform_export::render_rgb(&preview_y_up(&self.step_scene(k)), &opts);
                genform_export::plot::Tile { rgb, width, height, caption: self.step_label(k) }
            })
            .collect();
        let (rgb, w, h) = genform_export::plot::gallery_rgb(&tiles, grid_columns(tiles.len()));
        genform_export::plot::encode_png_rgb(&rgb, w, h)
    }

    /// The steps as small multiples in an SVG drawing: step `k` moved to
    /// cell `k` of a grid in the xy plane (all at one scale), each cell
    /// framed, its label above the surface.
    fn steps_svg(&self) -> Result<String> {
        let points = self.steps.iter().flat_map(|s| s.positions.iter().copied()).filter(|p| p.is_finite());
        let (lo, hi) = points
            .fold(None, |b: Option<(glam::Vec3, glam::Vec3)>, p| Some(b.map_or((p, p), |(l, h)| (l.min(p), h.max(p)))))
            .unwrap_or((glam::Vec3::ZERO, glam::Vec3::ONE));
        let extent = (hi - lo).truncate().max(glam::Vec2::splat(1e-3 * (hi - lo).max_element().max(1e-3)));
        let unit = extent.max_element();
        let (pad, band, gap) = (0.06 * unit, 0.14 * unit, 0.05 * unit);
        let cell = glam::Vec2::new(extent.x + 2.0 * pad, extent.y + 2.0 * pad + band);
        let columns = grid_columns(self.steps.len());
        let mut out = self.scene.clone();
        out.surfaces.clear();
        out.guides.clear();
        let frame_tag = out.tag("step_frame");
        let mut labels = Vec::new();
        for k in 0..self.steps.len() {
            let (c, r) = ((k % columns) as f32, (k / columns) as f32);
            // Cells run right, then down; y points up.
            let corner = glam::Vec2::new(c * (cell.x + gap), -r * (cell.y + gap));
            let by = (corner + glam::Vec2::splat(pad) - lo.truncate()).extend(0.0);
            let moved = translated(&self.step_scene(k), by);
            out.surfaces.extend(moved.surfaces);
            out.guides.extend(moved.guides);
            out.shapes2d.push(genform_core::scene::Shape2d {
                kind: genform_core::scene::Shape2dKind::Rect { min: corner, size: cell },
                attributes: vec![
                    ("fill".into(), "none".into()),
                    ("stroke".into(), "#bbbbbb".into()),
                    ("stroke-width".into(), format!("{}", 0.004 * unit)),
                ]
                .into(),
                tag: frame_tag,
            });
            labels.push((corner + glam::Vec2::new(pad, cell.y - 0.75 * band), self.step_label(k)));
        }
        let bytes = genform_export::export(&out, genform_export::Format::Svg, &Default::default())?;
        let mut svg = String::from_utf8(bytes)?;
        // The writer draws no text: the labels go in last, on top, in its
        // y-down coordinates.
        let end = svg.rfind("</svg>").ok_or_else(|| anyhow!("the SVG writer gave no closing tag"))?;
        let text: String = labels
            .iter()
            .map(|(at, label)| {
                format!(
                    "<text x=\"{}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"{}\" fill=\"#333333\">{label}</text>\n",
                    at.x,
                    -at.y,
                    0.6 * band
                )
            })
            .collect();
        svg.insert_str(end, &text);
        Ok(svg)
    }
}

impl Sample for Grown {
    fn scene(&self) -> &Scene {
        &self.scene
    }

    fn summary(&self) -> String {
        self.summary.clone()
    }

    /// Surfaces keep one node/object each whatever the granularity, so
    /// `_export` changes nothing here.
    fn write(&self, out: &Path, _export: &genform_export::ExportOptions) -> Result<Vec<PathBuf>> {
        if self.steps.is_empty() {
            return write_surface_scene(&self.scene, out);
        }
        if ends_with_any(out, &[".png"]) {
            write_atomic(out, &self.steps_png())?;
            return Ok(vec![out.to_path_buf()]);
        }
        if ends_with_any(out, PICTURES) {
            write_atomic(out, self.steps_svg()?.as_bytes())?;
            return Ok(vec![out.to_path_buf()]);
        }
        let mut written = Vec::with_capacity(self.steps.len());
        for (k, surface) in self.steps.iter().enumerate() {
            let mut one = Scene::new();
            one.tags = self.scene.tags.clone();
            one.surfaces.push(surface.clone());
            let path = step_path(out, k);
            written.extend(write_model(&one, &path)?);
        }
        Ok(written)
    }
}
