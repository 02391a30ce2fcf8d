//! The verbs: validated settings in, files out.

use anyhow::{Context, Result, bail};
use genform_core::generator::Generator;
use genform_core::{Genome, Limits, Rng, Sampled, Scene};
use genform_export::{ExportOptions, Format};
use std::path::Path;

use crate::args::{Cli, Command, DeriveArgs, InfoArgs, SampleArgs};
use genform_cli::grammar::{self, Loaded};
use genform_cli::output::write_atomic;

/// Stream id of `sample` (so other verbs' streams never coincide with it).
pub(crate) const SAMPLE_STREAM: u64 = 0x5A4D_504C;

/// Runs one command.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Sample(a) if grammar::is_lsystem(&a.file) => crate::lsystem::sample(a),
        Command::Sample(a) if grammar::is_boxsplit(&a.file) => crate::boxsplit::sample(a),
        Command::Sample(a) if grammar::is_graph(&a.file) => crate::graph::sample(a),
        Command::Sample(a) => sample(a),
        Command::Derive(a) => derive(a),
        Command::Info(a) if grammar::is_lsystem(&a.file) => crate::lsystem::info(a),
        Command::Info(a) if grammar::is_boxsplit(&a.file) => crate::boxsplit::info(a),
        Command::Info(a) if grammar::is_graph(&a.file) => crate::graph::info(a),
        Command::Info(a) => info(a),
        Command::Evolve(a) => crate::evolve::evolve(a),
        Command::Score(a) => crate::evolve::score(a),
        Command::Compare(a) => crate::evolve::compare(a),
    }
}

pub(crate) fn output_format(path: &Path) -> Result<Format> {
    match Format::from_path(path) {
        Some(f) => Ok(f),
        None => bail!(
            "cannot tell the output format of {}; use one of the extensions: {}",
            path.display(),
            Format::extensions().iter().map(|e| format!(".{e}")).collect::<Vec<_>>().join(" ")
        ),
    }
}

fn express(g: &dyn Generator, genome: &Genome, limits: &Limits) -> Result<Scene> {
    let mut scene = Scene::new();
    g.express(genome, limits, &mut scene).context("cannot build the model")?;
    Ok(scene)
}

pub(crate) fn write_model(scene: &Scene, path: &Path) -> Result<()> {
    write_model_with(scene, path, &ExportOptions::default())
}

/// [`write_model`] with explicit export options.
pub(crate) fn write_model_with(scene: &Scene, path: &Path, options: &ExportOptions) -> Result<()> {
    let format = output_format(path)?;
    let bytes =
        genform_export::export(scene, format, options).with_context(|| format!("cannot export {}", path.display()))?;
    write_atomic(path, &bytes)
}

fn summary(scene: &Scene, genome: &Genome) -> String {
    format!(
        "{} genes, {} primitives, {} triangles",
        genome.len(),
        scene.instances.len() + scene.polylines.len() + scene.polygons.len(),
        scene.triangle_count(Default::default())
    )
}

fn sample(a: SampleArgs) -> Result<()> {
    if let Some(out) = &a.out {
        output_format(out)?;
    }
    if a.steps.is_some() || a.max_modules.is_some() || a.string_out.is_some() {
        bail!("--steps, --max-modules and --string-out apply to L-systems (.ls) only");
    }
    if a.r#box.is_some() || a.world.is_some() || a.trace.is_some() {
        bail!("--box, --world and --trace apply to box-split grammars (.bsg) only");
    }
    let Loaded { generator, name, limits } = grammar::load(&a.file)?;
    let limits = a.limits.overrides().apply(limits);
    let mut rng = Rng::stream(a.seed, &[SAMPLE_STREAM]);
    let sampled = sample_prior(generator.as_ref(), &mut rng, &limits)?;
    let scene = express(generator.as_ref(), &sampled.genome, &limits)?;
    if let Some(path) = &a.genome_out {
        write_atomic(path, sampled.genome.to_json(generator.graph()).as_bytes())?;
    }
    if let Some(out) = &a.out {
        write_model(&scene, out)?;
        eprintln!("{name} seed {}: {} → {}", a.seed, summary(&scene, &sampled.genome), out.display());
    } else {
        println!("{name} seed {}: {}", a.seed, summary(&scene, &sampled.genome));
    }
    Ok(())
}

/// Draws a genome from `g`'s prior, warning when a limit truncated it.
pub(crate) fn sample_prior(g: &dyn Generator, rng: &mut Rng, limits: &Limits) -> Result<Sampled> {
    let sampled = g.sample(rng, limits).context("cannot sample")?;
    if let Some(kind) = sampled.truncated {
        eprintln!(
            "warning: growth stopped at the {kind} limit ({}); the model is truncated (raise it with {})",
            kind.value(limits),
            kind.flag()
        );
    }
    Ok(sampled)
}

fn derive(a: DeriveArgs) -> Result<()> {
    output_format(&a.out)?;
    let Loaded { generator, name, limits } = grammar::load(&a.file)?;
    let limits = a.limits.overrides().apply(limits);
    let text = std::fs::read_to_string(&a.genome).with_context(|| format!("cannot read {}", a.genome.display()))?;
    let genome = Genome::from_json(&text, generator.graph())
        .with_context(|| format!("{} does not fit grammar `{name}`", a.genome.display()))?;
    if genome.len() > limits.max_genes {
        bail!(
            "the genome has {} genes, more than the gene limit ({}); raise it with --max-genes",
            genome.len(),
            limits.max_genes
        );
    }
    let scene = express(generator.as_ref(), &genome, &limits)?;
    write_model(&scene, &a.out)?;
    eprintln!("{name}: {} → {}", summary(&scene, &genome), a.out.display());
    Ok(())
}

fn info(a: InfoArgs) -> Result<()> {
    let Loaded { generator, name, limits } = grammar::load(&a.file)?;
    let g = generator.graph();
    let mut out = String::new();
    out.push_str(&format!("grammar {name}: {} symbols, start `{}`\n", g.symbols.len(), g.symbol(g.root).name));
    out.push_str(&format!(
        "limits: genes {}, depth {}, primitives {}\n",
        limits.max_genes, limits.max_depth, limits.max_primitives
    ));
    for s in &g.symbols {
        out.push_str(&format!("\n{}{}\n", s.name, if s.emits_geometry { "  (emits geometry)" } else { "" }));
        for p in &s.params {
            let dists: Vec<String> = p.components.iter().map(|d| d.describe()).collect();
            let all_same = dists.windows(2).all(|w| w[0] == w[1]);
            let shown = if p.dim() == 1 || all_same {
                let prefix = if p.dim() > 1 { format!("vec{} ", p.dim()) } else { String::new() };
                format!("{prefix}{}", dists[0])
            } else {
                format!("[{}]", dists.join(", "))
            };
            out.push_str(&format!("  param {:<10} {shown}\n", p.name));
        }
        for slot in &s.slots {
            let max = if slot.max_count > 1 { format!(" x {}", slot.max_count) } else { String::new() };
            out.push_str(&format!(
                "  slot  {:<10} → {} p {}{max}\n",
                slot.name,
                g.symbol(slot.target).name,
                format_prob(slot.prob)
            ));
        }
    }
    print!("{out}");
    Ok(())
}

fn format_prob(p: f64) -> String {
    let s = format!("{p:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
