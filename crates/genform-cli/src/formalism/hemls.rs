//! HEMLS surface grammars (`.gr8`, Genr8's map L-systems): grow a surface
//! from a seed polygon in an environment (`--env`), optionally write every
//! derivation step and smooth the result.

use anyhow::{Result, anyhow, bail};
use genform_core::{Scene, SourceFile, Surface};
use genform_hemls::{Environment, GrowError, Settings};
use std::path::{Path, PathBuf};

use super::{Formalism, LoadedGrammar, Sample, SampleRequest, compile_file, ends_with_any, no_generator};
use crate::grammar::Loaded;
use crate::output::write_model;

/// The HEMLS row of the table.
pub struct Hemls;

/// Most Catmull–Clark steps `--smooth` takes (each multiplies the faces by about 4).
pub const MAX_SMOOTH: u32 = 6;

/// Pictures that overlay every step in one image with `--every-step`.
const PICTURES: &[&str] = &[".png", ".svg"];

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

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        let grammar = compile_file(path, genform_hemls::compile)?;
        Ok(Box::new(HemlsFile { path: path.to_path_buf(), grammar }))
    }
}

/// Reads an environment file (`--env`) into growth settings and an
/// environment; mesh boundaries are read relative to the file.
pub fn load_environment(path: &Path) -> Result<(Settings, Environment)> {
    let text = crate::source_text::read_text(path, "environment")?;
    let file = SourceFile::new(path.display().to_string(), text);
    let spec = genform_hemls::parse_env(&file).map_err(|d| crate::source_text::SourceErrors::new(&d, false))?;
    let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut load_mesh = |rel: &str| -> Result<genform_core::Mesh, String> {
        let full = base.join(rel);
        let format = genform_export::MeshFormat::from_path(&full)
            .ok_or_else(|| format!("{}: a boundary mesh must be .obj, .stl or .glb", full.display()))?;
        let bytes = std::fs::read(&full).map_err(|e| format!("cannot read boundary mesh {}: {e}", full.display()))?;
        let name = Path::new(rel).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        genform_export::read_mesh(&name, &bytes, format).map_err(|e| e.to_string())
    };
    spec.resolve(&mut load_mesh).map_err(|e| anyhow!("{}: {e}", path.display()))
}

/// A growth error in words, with the rule's file position when it names one.
pub fn grow_error(path: &Path, grammar: &genform_hemls::Hemls, e: GrowError) -> anyhow::Error {
    match &e {
        GrowError::Rule { span, .. } if span.end > span.start => match std::fs::read_to_string(path) {
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
        let mut rng = genform_core::Rng::stream(seed, &[super::SAMPLE_STREAM]);
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
        Ok(Box::new(Grown { scene, steps, summary }))
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
fn write_surface_scene(scene: &Scene, out: &Path) -> Result<()> {
    if ends_with_any(out, &[".png"]) {
        write_model(&crate::codon_report::z_up(scene), out)
    } else {
        write_model(scene, out)
    }
}

/// `dir/name.ext` → `dir/name-step{k}.ext`.
fn step_path(out: &Path, k: usize) -> PathBuf {
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = out.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    out.with_file_name(format!("{stem}-step{k}{ext}"))
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
            write_surface_scene(&self.scene, out)?;
            return Ok(vec![out.to_path_buf()]);
        }
        if ends_with_any(out, PICTURES) {
            let mut overlay = self.scene.clone();
            overlay.surfaces = self.steps.clone();
            write_surface_scene(&overlay, out)?;
            return Ok(vec![out.to_path_buf()]);
        }
        let mut written = Vec::with_capacity(self.steps.len());
        for (k, surface) in self.steps.iter().enumerate() {
            let mut one = Scene::new();
            one.tags = self.scene.tags.clone();
            one.surfaces.push(surface.clone());
            let path = step_path(out, k);
            write_model(&one, &path)?;
            written.push(path);
        }
        Ok(written)
    }
}
