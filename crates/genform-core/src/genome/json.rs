//! Converting between a [`Genome`] and its JSON file form
//! ([`GenomeFile`]): [`Genome::to_file`], [`Genome::from_file`] and the
//! JSON text of both.

use super::file::{FORMAT, GenomeFile, JsonGene, JsonValue, VERSION};
use super::{GenePos, Genome, GenomeError, Link};
use crate::graph::GeneratorGraph;
use std::collections::BTreeMap;

fn link_name(slot: &str, index: u32) -> String {
    if index == 0 { slot.to_string() } else { format!("{slot}#{index}") }
}

impl Genome {
    /// The JSON file form of this genome (names taken from `graph`).
    pub fn to_file(&self, graph: &GeneratorGraph) -> GenomeFile {
        let mut ordinal_of = BTreeMap::new();
        let mut genes = Vec::with_capacity(self.len());
        for (i, g) in self.iter().enumerate() {
            ordinal_of.insert(g.pos, i);
            let spec = graph.symbol(g.symbol());
            let mut values = g.params();
            let params = spec
                .params
                .iter()
                .map(|p| {
                    let v: Vec<f64> = values.by_ref().take(p.dim()).collect();
                    let v = if v.len() == 1 { JsonValue::Scalar(v[0]) } else { JsonValue::Vector(v) };
                    (p.name.clone(), v)
                })
                .collect();
            let (parent, slot, index) = match g.parent() {
                Some((q, link)) => {
                    let pspec = graph.symbol(self.gene(q).symbol());
                    let (s, k) = pspec.slot_of_link(link).expect("valid genome");
                    (Some(ordinal_of[&q]), Some(pspec.slots[s].name.clone()), k)
                }
                None => (None, None, 0),
            };
            let closed = g
                .links()
                .enumerate()
                .filter(|(_, l)| *l == Link::Closed)
                .map(|(i, _)| {
                    let (s, k) = spec.slot_of_link(i).expect("valid genome");
                    link_name(&spec.slots[s].name, k)
                })
                .collect();
            genes.push(JsonGene { symbol: spec.name.clone(), parent, slot, index, params, closed });
        }
        GenomeFile { format: FORMAT.into(), version: VERSION, generator: graph.name.clone(), genes }
    }

    /// Pretty JSON text of [`Genome::to_file`], ending in a newline.
    pub fn to_json(&self, graph: &GeneratorGraph) -> String {
        let mut s = serde_json::to_string_pretty(&self.to_file(graph)).expect("serializable");
        s.push('\n');
        s
    }

    /// Builds a genome from its file form and validates it against `graph`.
    pub fn from_file(file: &GenomeFile, graph: &GeneratorGraph) -> Result<Genome, GenomeError> {
        let err = |i: usize, msg: String| GenomeError::Json(format!("gene {i}: {msg}"));
        if file.format != FORMAT {
            return Err(GenomeError::Json(format!(
                "not a genome file: format is `{}`, expected `{FORMAT}`",
                file.format
            )));
        }
        if file.version != VERSION {
            return Err(GenomeError::Json(format!(
                "unsupported genome version {} (this genform reads {VERSION})",
                file.version
            )));
        }
        let mut g = Genome::new();
        let mut pos_of: Vec<GenePos> = Vec::with_capacity(file.genes.len());
        let mut values = Vec::new();
        for (i, jg) in file.genes.iter().enumerate() {
            let sym = graph.symbol_id(&jg.symbol).ok_or_else(|| err(i, format!("unknown symbol `{}`", jg.symbol)))?;
            let spec = graph.symbol(sym);
            values.clear();
            for p in &spec.params {
                match jg.params.get(&p.name) {
                    None => {
                        return Err(err(i, format!("`{}` lacks parameter `{}`", spec.name, p.name)));
                    }
                    Some(JsonValue::Scalar(v)) if p.dim() == 1 => values.push(*v),
                    Some(JsonValue::Vector(v)) if v.len() == p.dim() => values.extend_from_slice(v),
                    Some(_) => {
                        return Err(err(
                            i,
                            format!("parameter `{}` of `{}` needs {} value(s)", p.name, spec.name, p.dim()),
                        ));
                    }
                }
            }
            if let Some(extra) = jg.params.keys().find(|k| !spec.params.iter().any(|p| &&p.name == k)) {
                return Err(err(i, format!("`{}` has no parameter `{extra}`", spec.name)));
            }
            let pos = match (jg.parent, &jg.slot) {
                (None, None) if i == 0 => {
                    g.push_gene(sym, &values, spec.link_len(), None);
                    GenePos(0)
                }
                (None, _) | (_, None) => {
                    return Err(err(i, "every gene but the first needs `parent` and `slot`".into()));
                }
                (Some(p), Some(slot)) => {
                    if p >= i {
                        return Err(err(i, format!("parent {p} must come before the gene")));
                    }
                    let parent = pos_of[p];
                    let pspec = graph.symbol(g.gene(parent).symbol());
                    let s = pspec
                        .slot_index(slot)
                        .ok_or_else(|| err(i, format!("`{}` has no slot `{slot}`", pspec.name)))?;
                    let sspec = &pspec.slots[s];
                    if sspec.target != sym {
                        return Err(err(
                            i,
                            format!(
                                "slot `{}.{slot}` holds `{}`, not `{}`",
                                pspec.name,
                                graph.symbol(sspec.target).name,
                                spec.name
                            ),
                        ));
                    }
                    if jg.index >= sspec.max_count {
                        return Err(err(
                            i,
                            format!("slot `{}.{slot}` has only {} link(s)", pspec.name, sspec.max_count),
                        ));
                    }
                    let link = pspec.link_offset(s) + jg.index as usize;
                    if let Link::Child(_) = g.gene(parent).link(link) {
                        return Err(err(i, format!("link `{}` of gene {p} is used twice", link_name(slot, jg.index))));
                    }
                    g.grow(parent, link, sym, &values, spec.link_len())
                }
            };
            pos_of.push(pos);
            for name in &jg.closed {
                let (slot, index) = match name.split_once('#') {
                    Some((s, k)) => (s, k.parse::<u32>().map_err(|_| err(i, format!("bad closed link `{name}`")))?),
                    None => (name.as_str(), 0),
                };
                let s = spec.slot_index(slot).ok_or_else(|| err(i, format!("`{}` has no slot `{slot}`", spec.name)))?;
                if index >= spec.slots[s].max_count {
                    return Err(err(i, format!("closed link `{name}` does not exist")));
                }
                g.set_closed(pos, spec.link_offset(s) + index as usize, true);
            }
        }
        g.validate(graph)?;
        Ok(g)
    }

    /// Parses JSON text and builds a validated genome.
    pub fn from_json(text: &str, graph: &GeneratorGraph) -> Result<Genome, GenomeError> {
        let file: GenomeFile =
            serde_json::from_str(text).map_err(|e| GenomeError::Json(format!("invalid genome JSON: {e}")))?;
        Genome::from_file(&file, graph)
    }
}
