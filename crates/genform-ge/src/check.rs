//! From raw rules to a [`Bnf`]: name resolution, terminal interning and the
//! grammar-level checks (duplicate rules, undefined names, rules that can
//! never finish, unused rules).

use crate::bnf::{Alternative, Bnf, Item, Rule, RuleId, TerminalId};
use crate::parse::{RawItem, RawRule};
use genform_core::{Diagnostic, Span};
use std::collections::HashMap;

/// Placeholder id of an undefined non-terminal (already reported).
const UNDEFINED: u32 = u32::MAX;

/// Resolves `raw`; returns the grammar (meaningful only without errors) and
/// every diagnostic, warnings included.
pub(crate) fn resolve(raw: Vec<RawRule>) -> (Bnf, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let mut ids: HashMap<String, u32> = HashMap::new();
    let mut first_span: HashMap<String, Span> = HashMap::new();
    let mut kept = Vec::new();
    for rule in raw {
        if let Some(&first) = first_span.get(&rule.name) {
            diags.push(
                Diagnostic::error(rule.span, format!("rule `{}` is defined twice", rule.name))
                    .with_label(first, "first defined here")
                    .with_hint("join the alternatives into one rule with `|`"),
            );
            // Still resolve its names so their errors are reported too.
            kept.push((rule, false));
            continue;
        }
        first_span.insert(rule.name.clone(), rule.span);
        ids.insert(rule.name.clone(), ids.len() as u32);
        kept.push((rule, true));
    }

    let mut interner = Interner::default();
    let mut rules = Vec::new();
    for (rule, keep) in kept {
        let mut alternatives = Vec::new();
        for alt in &rule.alts {
            let items = resolve_items(&alt.items, &ids, &mut interner, &mut diags);
            alternatives.push(Alternative { items, span: alt.span });
        }
        if keep {
            rules.push(Rule { name: rule.name, span: rule.span, alternatives });
        }
    }
    let bnf = Bnf { rules, terminals: interner.texts };
    if bnf.rules.is_empty() {
        diags.push(
            Diagnostic::error(Span::default(), "no rules: the grammar needs at least one `<name> ::= …` line")
                .with_hint("the first rule is the start symbol"),
        );
        return (bnf, diags);
    }
    check_termination(&bnf, &mut diags);
    (bnf, diags)
}

#[derive(Default)]
struct Interner {
    texts: Vec<String>,
    index: HashMap<String, u32>,
}

impl Interner {
    fn intern(&mut self, text: &str) -> TerminalId {
        if let Some(&i) = self.index.get(text) {
            return TerminalId(i);
        }
        let i = self.texts.len() as u32;
        self.texts.push(text.to_string());
        self.index.insert(text.to_string(), i);
        TerminalId(i)
    }
}

fn resolve_items(
    raw: &[RawItem],
    ids: &HashMap<String, u32>,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Item> {
    raw.iter()
        .map(|item| match item {
            RawItem::Terminal(t) => Item::Terminal(interner.intern(t)),
            RawItem::NonTerminal(name, span) => match ids.get(name) {
                Some(&id) => Item::NonTerminal(RuleId(id)),
                None => {
                    let mut d = Diagnostic::error(*span, format!("undefined non-terminal `{name}`"));
                    if let Some(near) = genform_core::expr::did_you_mean(name, ids.keys().map(String::as_str)) {
                        d = d.with_hint(format!("did you mean `{near}`?"));
                    } else {
                        d = d.with_hint(format!("define it with a line `{name} ::= …`"));
                    }
                    diags.push(d);
                    Item::NonTerminal(RuleId(UNDEFINED))
                }
            },
            RawItem::Repeat(g) => Item::Repeat(resolve_items(g, ids, interner, diags)),
            RawItem::Optional(g, evolved) => {
                Item::Optional { items: resolve_items(g, ids, interner, diags), evolved: *evolved }
            }
        })
        .collect()
}

/// Whether every item of `items` can finish, given the rules known to
/// finish. Groups can always finish (zero times); undefined names are
/// already reported and count as finishing.
fn items_finish(items: &[Item], finishes: &[bool]) -> bool {
    items.iter().all(|i| match i {
        Item::NonTerminal(RuleId(UNDEFINED)) => true,
        Item::NonTerminal(r) => finishes[r.0 as usize],
        _ => true,
    })
}

/// Errors on every rule that derives no string of terminals (a cycle with
/// no terminal exit, e.g. `<a> ::= <a> "x"` alone), by fixed point.
fn check_termination(bnf: &Bnf, diags: &mut Vec<Diagnostic>) {
    // A rule with no alternatives is already reported; counting it as
    // finishing keeps the error from cascading to its users.
    let mut finishes: Vec<bool> = bnf.rules.iter().map(|r| r.alternatives.is_empty()).collect();
    loop {
        let mut changed = false;
        for (i, rule) in bnf.rules.iter().enumerate() {
            if !finishes[i] && rule.alternatives.iter().any(|a| items_finish(&a.items, &finishes)) {
                finishes[i] = true;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // Each stuck rule has a stuck non-terminal at the top level of each
    // alternative; following the first one from any stuck rule must cycle.
    let next = |r: usize| -> Option<usize> {
        bnf.rules[r].alternatives.iter().flat_map(|a| &a.items).find_map(|i| match i {
            Item::NonTerminal(RuleId(id)) if *id != UNDEFINED && !finishes[*id as usize] => Some(*id as usize),
            _ => None,
        })
    };
    for (i, rule) in bnf.rules.iter().enumerate() {
        if finishes[i] || rule.alternatives.is_empty() {
            continue;
        }
        let mut path = vec![i];
        let cycle_start = loop {
            let Some(nx) = next(*path.last().expect("non-empty")) else { break None };
            if let Some(at) = path.iter().position(|&p| p == nx) {
                break Some(at);
            }
            path.push(nx);
        };
        let name = |r: &usize| format!("`{}`", bnf.rules[*r].name);
        let message = match cycle_start {
            Some(at) => {
                let mut cycle: Vec<String> = path[at..].iter().map(name).collect();
                cycle.push(name(&path[at]));
                let cycle = cycle.join(" → ");
                if at == 0 {
                    format!("`{}` can never finish: every alternative leads back into the cycle {cycle}", rule.name)
                } else {
                    format!("`{}` can never finish: every alternative leads into the cycle {cycle}", rule.name)
                }
            }
            None => format!("`{}` can never finish: no alternative derives a string of terminals", rule.name),
        };
        diags.push(
            Diagnostic::error(rule.span, message)
                .with_hint("give one of the rules in the cycle an alternative made of terminals only"),
        );
    }
}

/// Warns about rules the start symbol never reaches (run only on grammars
/// without errors: in a broken one they are noise).
pub(crate) fn check_unused(bnf: &Bnf, diags: &mut Vec<Diagnostic>) {
    fn visit(items: &[Item], out: &mut Vec<usize>) {
        for i in items {
            match i {
                Item::NonTerminal(RuleId(id)) if *id != UNDEFINED => out.push(*id as usize),
                Item::Repeat(g) | Item::Optional { items: g, .. } => visit(g, out),
                _ => {}
            }
        }
    }
    let mut seen = vec![false; bnf.rules.len()];
    let mut todo = vec![0usize];
    seen[0] = true;
    while let Some(r) = todo.pop() {
        let mut next = Vec::new();
        for alt in &bnf.rules[r].alternatives {
            visit(&alt.items, &mut next);
        }
        for n in next {
            if !seen[n] {
                seen[n] = true;
                todo.push(n);
            }
        }
    }
    let start = &bnf.rules[0].name;
    for (rule, used) in bnf.rules.iter().zip(seen) {
        if !used {
            diags.push(
                Diagnostic::warning(rule.span, format!("rule `{}` is never used", rule.name))
                    .with_hint(format!("the start symbol `{start}` (the first rule) does not reach it")),
            );
        }
    }
}
