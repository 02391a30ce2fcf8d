//! `map`: a codon genome mapped through a GE grammar (`.bnf`), with every
//! codon read, as text or as the mapper's JSON trace.

use anyhow::Result;
use genform_ge::{CodonLayout, MapOptions, Step, StepKind};
use std::path::PathBuf;

use crate::text::compile_file;

/// One `map`, as a door asks for it.
#[derive(Clone, Debug, Default)]
pub struct MapRequest {
    /// The BNF grammar.
    pub grammar: PathBuf,
    /// The codons.
    pub genome: Vec<u32>,
    /// How often reading may wrap (default 0; 4 with Genr8's extensions).
    pub max_wraps: Option<u32>,
    /// The derivation-tree depth limit (with Genr8's extensions: the depth
    /// from which only terminal productions are chosen).
    pub max_depth: Option<u32>,
    /// Genr8's mapping extensions.
    pub genr8: bool,
    /// One codon stream per choice (`per-choice`) instead of one reading.
    pub per_choice: bool,
    /// The whole trace as JSON instead of text.
    pub json: bool,
}

/// Bytes one codon read may take in a mapping's trace: its step (with the
/// non-terminal's name) and its share of the pending symbols and output.
const TRACE_CODON_BYTES: u64 = 160;

/// The mapping `request` asks for, as the text the door prints.
pub fn map(request: &MapRequest) -> Result<String> {
    let bnf = compile_file(&request.grammar, genform_ge::compile)?;
    // Reading stops after (wraps + 1) passes over the genome: a recursive
    // rule allowed a billion wraps would fill the memory before that.
    if let Some(w) = request.max_wraps {
        let codons = (u64::from(w) + 1).saturating_mul(request.genome.len() as u64);
        crate::memory::check_limit(
            &format!("--max-wraps {w}"),
            "--max-wraps",
            usize::try_from(codons).unwrap_or(usize::MAX),
            TRACE_CODON_BYTES,
            "codons read",
        )?;
    }
    let mut options = if request.genr8 { MapOptions::genr8() } else { MapOptions::default() };
    if let Some(w) = request.max_wraps {
        options.max_wraps = w;
    }
    if request.per_choice {
        options.layout = CodonLayout::PerChoice;
    }
    if let Some(d) = request.max_depth {
        match &mut options.genr8 {
            Some(g) => g.max_depth = Some(d),
            None => options.max_tree_depth = Some(d),
        }
    }
    let m = genform_ge::map(&bnf, &request.genome, &options)
        .map_err(|e| anyhow::anyhow!("cannot map with {}: {e}", request.grammar.display()))?;
    if request.json {
        return Ok(serde_json::to_string(&m)? + "\n");
    }
    let mut out = String::new();
    for s in &m.steps {
        let step = describe_step(s);
        out += &format!("codon {:>3} = {:>4}  {:<18} {} of {} → {step}\n", s.pos, s.codon, s.nt, s.choice, s.n);
    }
    out += &match (&m.phenotype, &m.fail) {
        (Some(p), _) => format!("valid: {} codons read, {} wraps\n{p}\n", m.used_codons, m.wraps),
        (None, fail) => {
            let why = fail
                .as_ref()
                .and_then(|f| serde_json::to_value(f).ok())
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default();
            format!("invalid ({why}): {} codons read, {} wraps\n", m.used_codons, m.wraps)
        }
    };
    Ok(out)
}

/// What a step decided, in words.
fn describe_step(s: &Step) -> String {
    match s.kind {
        StepKind::Expand => format!("production {}", s.choice),
        StepKind::Limited => format!("production {} (depth limit: terminal-only choices)", s.choice),
        StepKind::Repeat => (if s.choice + 2 > s.n { "repeat" } else { "stop" }).to_string(),
        StepKind::Option => (if s.choice == 1 { "include" } else { "leave out" }).to_string(),
        StepKind::Edge => format!("Edge{}", s.choice),
    }
}
