//! The verbs on graph grammars: rewrite the host graph and write the result
//! as a drawing (SVG, PNG) or as a graph (YAML).

use anyhow::{Context, Result, bail};
use genform_core::Rng;
use genform_graph::{DEFAULT_MAX_ELEMENTS, GraphGrammar};
use std::path::Path;

use crate::args::{InfoArgs, SampleArgs};
use crate::commands::{SAMPLE_STREAM, output_format, write_model};
use genform_cli::grammar;
use genform_cli::output::write_atomic;

fn is_yaml(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"))
}

/// `genform sample FILE.gg.yaml`.
pub fn sample(a: SampleArgs) -> Result<()> {
    if let Some(out) = &a.out
        && !is_yaml(out)
    {
        output_format(out)?;
    }
    if a.r#box.is_some() || a.world.is_some() || a.trace.is_some() || a.string_out.is_some() {
        bail!("--box, --world, --trace and --string-out do not apply to graph grammars");
    }
    let grammar: GraphGrammar = grammar::load_graph(&a.file)?;
    let mut rng = Rng::stream(a.seed, &[SAMPLE_STREAM]);
    let max_elements = a.max_modules.unwrap_or(DEFAULT_MAX_ELEMENTS);
    let d = grammar
        .derive(&mut rng, a.steps.map(|s| s as usize), max_elements)
        .with_context(|| format!("{}: the derivation stopped", grammar.name()))?;
    let (v, e) = (d.graph.vertex_count(), d.graph.edge_count());
    let summary =
        format!("{} seed {}: {} steps, {v} vertices, {e} edges, {} elements", grammar.name(), a.seed, d.steps, v + e);
    match &a.out {
        Some(out) => {
            if is_yaml(out) {
                write_atomic(out, d.graph.to_yaml().as_bytes())?;
            } else {
                write_model(&d.graph.to_scene(), out)?;
            }
            eprintln!("{summary} → {}", out.display());
        }
        None => println!("{summary}"),
    }
    Ok(())
}

/// `genform info FILE.gg.yaml`.
pub fn info(a: InfoArgs) -> Result<()> {
    let g = grammar::load_graph(&a.file)?;
    let host = g.host();
    println!("graph grammar {}: host {} vertices, {} edges", g.name(), host.vertex_count(), host.edge_count());
    match g.step_limit() {
        Some(n) => println!("step limit: {n}"),
        None => println!("step limit: none (runs until nothing matches)"),
    }
    println!("productions: {}", g.production_names().collect::<Vec<_>>().join(", "));
    Ok(())
}
