//! The verbs on L-systems that do not go through a genome: sampling a
//! derivation directly (context-sensitive systems and decomposition
//! included) and describing a system.

use anyhow::{Context, Result};
use genform_core::generator::Generator;
use genform_core::{Limits, Rng, Scene};
use genform_lsystem::{Command, LSystem, LsGenerator, View};
use std::sync::Arc;

use crate::args::{InfoArgs, SampleArgs};
use crate::commands::{SAMPLE_STREAM, output_format, sample_prior, write_model};
use genform_cli::grammar;
use genform_cli::output::write_atomic;

/// `genform sample FILE.ls`: derive, draw, write.
pub fn sample(a: SampleArgs) -> Result<()> {
    if let Some(out) = &a.out {
        output_format(out)?;
    }
    if a.r#box.is_some() || a.world.is_some() || a.trace.is_some() {
        anyhow::bail!("--box, --world and --trace apply to box-split grammars (.bsg) only");
    }
    let system = grammar::load_lsystem(&a.file)?;
    let st = &system.settings;
    let steps = a.steps.unwrap_or(st.derivation);
    let max_modules = a.max_modules.unwrap_or(st.max_modules);
    let max_primitives = a.limits.max_primitives.unwrap_or(Limits::default().max_primitives);
    let mut rng = Rng::stream(a.seed, &[SAMPLE_STREAM]);
    let mut scene = Scene::new();
    let string = if let Some(genome_path) = &a.genome_out {
        // Through the generator, so `genform derive` replays the genome.
        let generator = LsGenerator::new(Arc::clone(&system))
            .with_context(|| format!("--genome-out needs {} to be a generator", a.file.display()))?;
        let base = Limits { max_depth: steps as usize, max_primitives, ..generator.limits() };
        let limits = a.limits.overrides().apply(base);
        let sampled = sample_prior(&generator, &mut rng, &limits)?;
        write_atomic(genome_path, sampled.genome.to_json(generator.graph()).as_bytes())?;
        let s = generator.derive(&sampled.genome, &limits).context("cannot derive the genome")?;
        generator.express(&sampled.genome, &limits, &mut scene).context("cannot draw the model")?;
        s
    } else {
        let s = system.derive_limited(steps, &mut rng, max_modules, |_, _| {}).context("cannot derive")?;
        system.interpret(&s, &mut rng, max_primitives, &mut scene).context("cannot draw the model")?;
        s
    };
    if let Some(path) = &a.string_out {
        let mut text = string.display(&system.alphabet, true);
        text.push('\n');
        write_atomic(path, text.as_bytes())?;
    }
    let summary = format!(
        "{} seed {}, {steps} steps: {} modules, {} segments, {} polygons",
        st.name,
        a.seed,
        string.len(),
        scene.polylines.iter().map(|l| l.points.len() - 1).sum::<usize>() + scene.instances.len(),
        scene.polygons.len()
    );
    match &a.out {
        Some(out) => {
            write_model(&scene, out)?;
            eprintln!("{summary} → {}", out.display());
        }
        None => println!("{summary}"),
    }
    Ok(())
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
        Command::Color => "colour",
        Command::PolygonStart => "polygon start",
        Command::PolygonVertex => "polygon vertex",
        Command::PolygonEnd => "polygon end",
        Command::Sphere => "sphere",
        Command::Cut => "cut branch",
        Command::None => "-",
    }
}

/// `genform info FILE.ls`: settings, modules, rules, growth per step, and
/// the generator graph (or why there is none).
pub fn info(a: InfoArgs) -> Result<()> {
    let system = grammar::load_lsystem(&a.file)?;
    print!("{}", describe(&system));
    Ok(())
}

fn describe(system: &Arc<LSystem>) -> String {
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
    match LsGenerator::new(Arc::clone(system)) {
        Ok(g) => {
            let graph = g.graph();
            out.push_str(&format!("generator: {} symbols, growth {}\n", graph.symbols.len(), st.growth));
            for s in &graph.symbols {
                let params: Vec<&str> = s.params.iter().map(|p| p.name.as_str()).collect();
                out.push_str(&format!("  {:<8} params [{}], {} slot(s)\n", s.name, params.join(", "), s.slots.len()));
            }
        }
        Err(e) => out.push_str(&format!("generator: none ({e})\n")),
    }
    out
}
