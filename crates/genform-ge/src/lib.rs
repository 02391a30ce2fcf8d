//! Grammatical evolution (GE): maps a genome of integer codons to a
//! phenotype over any BNF grammar, with Genr8's extensions.
//!
//! - [`compile`] reads a `.bnf` file (every error at once, with positions);
//!   [`parse_str`] does the same for a string.
//! - [`Mapper`] maps genomes: standard GE exactly as the golden traces of
//!   `shared/reference/ge` define it, or with [`Genr8Options`]: `{ }`
//!   repetition and `[ ]` options decided by genes, edge IDs with
//!   `EdgeX`/`EdgeY`/`EdgeZ` binding, depth-limited choice, and repair.
//! - [`Mapping`] is a full trace whose JSON has the traces' field names.
//!
//! # The `.bnf` format
//!
//! One rule per line, `<name> ::= alternative | alternative …`; the first
//! rule is the start symbol. An alternative is a sequence of non-terminals
//! `<name>` and double-quoted terminals `"text"`; whitespace between
//! symbols does not matter, whitespace inside quotes is part of the
//! terminal. The phenotype is the terminals' texts concatenated (or
//! separated by spaces with [`MapOptions::spaced`]). Extensions over the
//! traces' format:
//!
//! - `{ … }` repeats its items zero or more times and `[ … ]` includes
//!   them at most once, each decision read from a gene (Genr8 §6.2–6.3);
//!   `[? … ]` is an option that is never evolved: it reads no gene and is
//!   always left out (the `[ ~ ]` of Genr8's axiom). Groups nest and hold
//!   terminals, non-terminals and groups, but no `|`.
//! - `#` or `//` outside quotes starts a comment to the end of the line.
//! - A line that starts with `|` continues the previous rule.
//! - Inside quotes, `\n`, `\t`, `\\` and `\"` are escapes (so a backslash
//!   terminal is written `"\\"`).
//!
//! ```
//! use genform_ge::{MapOptions, Mapper};
//! let bnf = genform_ge::parse_str("doc.bnf", "<e> ::= <e><op><e> | \"x\"\n<op> ::= \"+\" | \"*\"").unwrap();
//! let mut mapper = Mapper::new(&bnf, MapOptions::standard(1, None)).unwrap();
//! let trace = mapper.trace(&[0, 1, 1, 1]);
//! assert_eq!(trace.phenotype.as_deref(), Some("x*x"));
//! assert_eq!(trace.choices, vec![0, 1, 1, 1]);
//! ```

mod bnf;
mod check;
mod generate;
mod mapper;
mod options;
mod outcome;
mod parse;
mod program;

pub use bnf::{Alternative, Bnf, Item, Rule, RuleId, TerminalId};
pub use generate::{Growth, Sensible};
pub use mapper::Mapper;
pub use options::{CodonLayout, Genr8Options, MapError, MapOptions, RepairOptions};
pub use outcome::{Failure, Mapping, Outcome, Step, StepKind, Subtree};

use genform_core::{Diagnostics, SourceFile};

/// Compiles a `.bnf` file. Returns the grammar and its warnings (unused
/// rules), or every error found.
pub fn compile(file: &SourceFile) -> Result<(Bnf, Diagnostics), Diagnostics> {
    let (raw, syntax) = parse::parse(&file.text);
    let (bnf, checks) = check::resolve(raw);
    let mut diags = Diagnostics::new(file.clone());
    for d in syntax.into_iter().chain(checks) {
        diags.push(d);
    }
    if diags.has_errors() {
        return Err(diags);
    }
    let mut warnings = Vec::new();
    check::check_unused(&bnf, &mut warnings);
    for w in warnings {
        diags.push(w);
    }
    if diags.has_errors() { Err(diags) } else { Ok((bnf, diags)) }
}

/// Compiles `.bnf` text, named `name` in messages, dropping warnings.
pub fn parse_str(name: &str, text: &str) -> Result<Bnf, Diagnostics> {
    compile(&SourceFile::new(name, text)).map(|(bnf, _)| bnf)
}

/// Maps one genome with a fresh [`Mapper`] and returns its full trace.
pub fn map(bnf: &Bnf, genome: &[u32], options: &MapOptions) -> Result<Mapping, MapError> {
    Ok(Mapper::new(bnf, options.clone())?.trace(genome))
}

#[cfg(test)]
mod tests;
