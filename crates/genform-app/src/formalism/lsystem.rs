//! L-systems (`.ls`): sampling derives a string and draws it with the
//! turtle (context-sensitive systems and decomposition included); with
//! `--genome-out` it goes through the generator instead, so `derive` can
//! replay the genome (context-free systems only).

use anyhow::{Context, Result};
use genform_core::generator::Generator;
use genform_core::{Limits, Rng, Scene};
use genform_lsystem::{Command, LSystem, LsGenerator, View};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::options::SampleRequest;
use super::row::{FileAssets, Formalism, Genomes, Loaded, LoadedGrammar, Sample, SceneSample, sample_genome};
use crate::files::write_atomic_with;
use crate::text::compile_file;

/// The L-system row of the table.
pub struct LSystems;

impl Formalism for LSystems {
    fn name(&self) -> &'static str {
        "L-system"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".ls", ".lpy"]
    }

    fn sample_options(&self) -> &'static [&'static str] {
        &["--steps", "--max-modules", "--string-out", "--genome-out", "--max-genes", "--max-depth", "--max-primitives"]
    }

    fn genomes(&self) -> Genomes {
        Genomes::Tree
    }

    fn load(&self, path: &Path) -> Result<Box<dyn LoadedGrammar>> {
        // `.lpy`: L-Py files, in the subset the Rust reader translates (docs/lsystem.md).
        let lpy = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("lpy"));
        let system = Arc::new(compile_file(path, |file| match lpy {
            true => genform_lsystem::compile_lpy_with_assets(file, &FileAssets::beside(path)),
            false => genform_lsystem::compile_with_assets(file, &FileAssets::beside(path)),
        })?);
        Ok(Box::new(LsFile { path: path.to_path_buf(), system }))
    }
}

/// Whether `request` asks for the derived string and no model.
fn string_only(request: &SampleRequest) -> bool {
    request.string_out.is_some() && request.out.is_none()
}

/// A compiled L-system and the file it came from.
struct LsFile {
    path: PathBuf,
    system: Arc<LSystem>,
}

impl LsFile {
    /// The system as a generator, or why it cannot be one.
    fn generator(&self) -> Result<LsGenerator, genform_lsystem::GeneratorError> {
        LsGenerator::new(Arc::clone(&self.system))
    }
}

/// Bytes a module may take while deriving: its symbol in two strings (the
/// current and the next) and a share of parameters, as `--max-modules`
/// counts it.
const MODULE_BYTES: u64 = 64;

/// Bytes one drawn primitive may take from turtle to file: its scene entry
/// and its share of an exporter's meshes (measured: 1.05 M segments of ABOP
/// Fig. 1.24e peak at 2.0 GB while writing GLB, 0.8 GB for PNG).
const DRAWN_PRIMITIVE_BYTES: u64 = 4096;

/// The primitive limit of a sampled drawing when `--max-primitives` is not
/// given: what fits in the memory budget, and never below the generators'
/// default. A drawing is what the user asked for, so it scales with the
/// machine rather than stopping at a count meant for runaway individuals of
/// an evolution (ABOP Fig. 1.24e at n = 12 is 1.05 M segments).
fn drawing_limit() -> usize {
    let fits = crate::memory::budget().bytes / DRAWN_PRIMITIVE_BYTES;
    usize::try_from(fits).unwrap_or(usize::MAX).max(Limits::default().max_primitives)
}

impl LoadedGrammar for LsFile {
    fn sample(&self, request: &SampleRequest) -> Result<Box<dyn Sample>> {
        let system = &self.system;
        let st = &system.settings;
        let steps = request.steps.unwrap_or(st.derivation);
        let max_modules = request.max_modules.unwrap_or(st.max_modules);
        if let (None, Some(span)) = (request.max_modules, st.max_modules_at) {
            let at = system.location(span).unwrap_or_else(|| self.path.display().to_string());
            crate::memory::check_limit(
                &format!("`max_modules: {max_modules}` ({at})"),
                "`max_modules:` in the file, or give --max-modules",
                max_modules,
                MODULE_BYTES,
                "modules",
            )?;
        }
        let max_primitives = request.limits.max_primitives.unwrap_or_else(drawing_limit);
        let mut scene = Scene::new();
        let mut kept = None;
        let string = if request.genome_out.is_some() || request.keep_genome {
            // Through the generator, so `genform derive` replays the genome.
            let generator = self
                .generator()
                .with_context(|| format!("--genome-out needs {} to be a generator", self.path.display()))?;
            let base = Limits { max_depth: steps as usize, max_primitives, ..generator.limits() };
            let limits = request.limits.apply(base);
            let genome = sample_genome(&generator, request, &limits)?;
            let s = generator.derive(&genome, &limits).context("cannot derive the genome")?;
            generator.express(&genome, &limits, &mut scene).context("cannot draw the model")?;
            kept = Some(genome);
            s
        } else {
            let mut rng = request.rng();
            let s = system.derive_limited(steps, &mut rng, max_modules, |_, _| {}).context("cannot derive")?;
            // Only the string was asked for: no turtle, and no primitive
            // limit for geometry nobody will see.
            if !string_only(request) {
                system.interpret(&s, &mut rng, max_primitives, &mut scene).context("cannot draw the model")?;
            }
            s
        };
        if let Some(path) = &request.string_out {
            write_atomic_with(path, |w| {
                string.display_pieces(&system.alphabet, true, |piece| w.write_all(piece.as_bytes()))?;
                w.write_all(b"\n")
            })?;
        }
        let drawn = if string_only(request) && kept.is_none() {
            " (not drawn: only --string-out was asked for)".to_string()
        } else {
            format!(
                ", {} segments, {} polygons",
                scene.polylines.segments() + scene.instances.len(),
                scene.polygons.len()
            )
        };
        let summary = format!("{} seed {}, {steps} steps: {} modules{drawn}", st.name, request.seed, string.len());
        Ok(Box::new(SceneSample { scene, summary, genome: kept }))
    }

    /// Settings, modules, rules, growth per step, and the generator graph
    /// (or why there is none).
    fn describe(&self) -> String {
        let system = &self.system;
        let st = &system.settings;
        let mut out = String::new();
        let view = if st.view == View::Flat { "2d" } else { "3d" };
        out.push_str(&format!(
            "L-system {}: derivation {}, angle {}°, step {}, width {}, view {view}\n",
            st.name, st.derivation, st.angle, st.step, st.width
        ));
        out.push_str(&format!(
            "axiom: {} ({} modules)\n",
            system.axiom.display(&system.alphabet, true),
            system.axiom.len()
        ));
        let ranged: Vec<String> = system
            .ranged_constants()
            .iter()
            .map(|c| format!("{} = {} in {}", c.name, c.value, c.range_text()))
            .collect();
        if !ranged.is_empty() {
            out.push_str(&format!("ranged constants (genes of the root): {}\n", ranged.join(", ")));
        }
        let [p, d, i] = system.rule_counts();
        out.push_str(&format!(
            "rules: {p} production{}{}, {d} decomposition, {i} interpretation\n",
            if p == 1 { "" } else { "s" },
            if system.is_context_sensitive() { " (context-sensitive)" } else { "" }
        ));
        out.push_str("modules:\n");
        for s in &system.alphabet.symbols {
            out.push_str(&format!("  {:<8} {} parameter(s)  {}\n", s.name, s.arity, command_name(s.command)));
        }
        // Lengths per step, as far as the module limit allows.
        let mut lengths = vec![system.axiom.len()];
        let result =
            system.derive_limited(st.derivation, &mut Rng::from_seed(0), st.max_modules, |_, s| lengths.push(s.len()));
        let shown: Vec<String> = lengths.iter().enumerate().map(|(k, n)| format!("{k}: {n}")).collect();
        out.push_str(&format!("modules per step (seed 0): {}\n", shown.join(", ")));
        if let Err(e) = result {
            out.push_str(&format!("  stopped: {e}\n"));
        }
        match self.generator() {
            Ok(g) => {
                let graph = g.graph();
                out.push_str(&format!("generator: {} symbols, growth {}\n", graph.symbols.len(), st.growth));
                for s in &graph.symbols {
                    let params: Vec<&str> = s.params.iter().map(|p| p.name.as_str()).collect();
                    out.push_str(&format!(
                        "  {:<8} params [{}], {} slot(s)\n",
                        s.name,
                        params.join(", "),
                        s.slots.len()
                    ));
                }
            }
            Err(e) => out.push_str(&format!("generator: none ({e})\n")),
        }
        out
    }

    fn into_generator(self: Box<Self>) -> Result<Loaded> {
        let g = self.generator().with_context(|| format!("{} cannot be used as a generator", self.path.display()))?;
        Ok(Loaded { name: g.system().settings.name.clone(), limits: g.limits(), generator: Box::new(g) })
    }
}

fn command_name(c: Command) -> &'static str {
    match c {
        Command::Draw => "draw forward",
        Command::Move => "move forward",
        Command::Left => "turn left",
        Command::Right => "turn right",
        Command::Down => "pitch down",
        Command::Up => "pitch up",
        Command::RollLeft => "roll left",
        Command::RollRight => "roll right",
        Command::TurnAround => "turn around",
        Command::RollHorizontal => "roll horizontal",
        Command::Push => "push",
        Command::Pop => "pop",
        Command::Width => "width",
        Command::WidthUp => "width up",
        Command::Color => "colour",
        Command::ColorDown => "colour down",
        Command::SetHead => "set heading",
        Command::SetScale => "set scale",
        Command::MultScale => "multiply scale",
        Command::DivScale => "divide scale",
        Command::PolygonStart => "polygon start",
        Command::PolygonVertex => "polygon vertex",
        Command::PolygonEnd => "polygon end",
        Command::Sphere => "sphere",
        Command::CylinderStart => "cylinder start",
        Command::CylinderEnd => "cylinder end",
        Command::Cut => "cut branch",
        Command::None => "-",
    }
}
