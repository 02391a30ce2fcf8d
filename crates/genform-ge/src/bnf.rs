//! The compiled grammar: rules, alternatives and interned terminals.
//!
//! Plain data produced by [`crate::compile`]; [`std::fmt::Display`] writes
//! it back as `.bnf` text that compiles to the same grammar.

use genform_core::Span;
use std::fmt;

/// Index of a rule in [`Bnf::rules`]; rule 0 is the start symbol.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RuleId(pub u32);

/// Index of an interned terminal text in [`Bnf::terminals`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TerminalId(pub u32);

/// One symbol or group of an alternative.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Item {
    /// A double-quoted terminal.
    Terminal(TerminalId),
    /// A `<name>` reference.
    NonTerminal(RuleId),
    /// `{ … }`: zero or more times, each decision read from a gene (Genr8 §6.2).
    Repeat(Vec<Item>),
    /// `[ … ]` (evolved: one gene decides) or `[? … ]` (not evolved: always
    /// left out, reads no gene; Genr8's axiom `[ ~ ]`).
    Optional {
        /// The group's items.
        items: Vec<Item>,
        /// Whether a gene decides; `false` for `[? … ]`.
        evolved: bool,
    },
}

/// One alternative (production) of a rule.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Alternative {
    /// Its items in order; never empty.
    pub items: Vec<Item>,
    /// Where it is written.
    pub span: Span,
}

impl Alternative {
    /// Whether a non-terminal occurs anywhere in it, groups included (the
    /// productions Genr8's depth limit excludes).
    pub fn has_nonterminal(&self) -> bool {
        fn any(items: &[Item]) -> bool {
            items.iter().any(|i| match i {
                Item::Terminal(_) => false,
                Item::NonTerminal(_) => true,
                Item::Repeat(g) | Item::Optional { items: g, .. } => any(g),
            })
        }
        any(&self.items)
    }
}

/// A rule `<name> ::= alt | alt …`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rule {
    /// The name with its angle brackets, e.g. `<expr>`.
    pub name: String,
    /// Where the name is defined.
    pub span: Span,
    /// The alternatives in file order (production index = position).
    pub alternatives: Vec<Alternative>,
}

/// A compiled BNF grammar.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bnf {
    /// The rules in file order; the first is the start symbol.
    pub rules: Vec<Rule>,
    /// Interned terminal texts (escapes resolved).
    pub terminals: Vec<String>,
}

impl Bnf {
    /// The start symbol (the first rule).
    pub fn start(&self) -> RuleId {
        RuleId(0)
    }

    /// The rule with this id.
    pub fn rule(&self, id: RuleId) -> &Rule {
        &self.rules[id.0 as usize]
    }

    /// The rule named `name` (with or without its angle brackets).
    pub fn rule_id(&self, name: &str) -> Option<RuleId> {
        let bracketed;
        let name = if name.starts_with('<') {
            name
        } else {
            bracketed = format!("<{name}>");
            &bracketed
        };
        self.rules.iter().position(|r| r.name == name).map(|i| RuleId(i as u32))
    }

    /// The text of a terminal.
    pub fn terminal(&self, id: TerminalId) -> &str {
        &self.terminals[id.0 as usize]
    }

    /// Whether any alternative uses a `{ }` or `[ ]` group.
    pub fn has_groups(&self) -> bool {
        self.rules
            .iter()
            .flat_map(|r| &r.alternatives)
            .any(|a| a.items.iter().any(|i| matches!(i, Item::Repeat(_) | Item::Optional { .. })))
    }
}

/// Writes a terminal with the escapes the reader understands.
fn write_terminal(f: &mut fmt::Formatter<'_>, text: &str) -> fmt::Result {
    f.write_str("\"")?;
    for c in text.chars() {
        match c {
            '\n' => f.write_str("\\n")?,
            '\t' => f.write_str("\\t")?,
            '\\' => f.write_str("\\\\")?,
            '"' => f.write_str("\\\"")?,
            c => write!(f, "{c}")?,
        }
    }
    f.write_str("\"")
}

impl Bnf {
    fn write_items(&self, f: &mut fmt::Formatter<'_>, items: &[Item]) -> fmt::Result {
        for (i, item) in items.iter().enumerate() {
            if i > 0 {
                f.write_str(" ")?;
            }
            match item {
                Item::Terminal(t) => write_terminal(f, self.terminal(*t))?,
                Item::NonTerminal(r) => f.write_str(&self.rule(*r).name)?,
                Item::Repeat(g) => {
                    f.write_str("{ ")?;
                    self.write_items(f, g)?;
                    f.write_str(" }")?;
                }
                Item::Optional { items, evolved } => {
                    f.write_str(if *evolved { "[ " } else { "[? " })?;
                    self.write_items(f, items)?;
                    f.write_str(" ]")?;
                }
            }
        }
        Ok(())
    }
}

impl fmt::Display for Bnf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for rule in &self.rules {
            write!(f, "{} ::=", rule.name)?;
            for (i, alt) in rule.alternatives.iter().enumerate() {
                f.write_str(if i == 0 { " " } else { " | " })?;
                self.write_items(f, &alt.items)?;
            }
            f.write_str("\n")?;
        }
        Ok(())
    }
}
