//! An L-system as a [`Generator`]: each module rewrite is a gene.
//!
//! The generator graph has a root symbol `axiom` and one symbol per module
//! that some production rewrites. A gene holds the rewrite's choices: a
//! roulette position `rule` in `[0, 1)` (only for modules with a stochastic
//! group), which picks among the matching members by weight exactly as a
//! random derivation would, and uniforms `u0, u1, …` replayed as the random
//! draws of the production's condition, weight and successor formulas. Its
//! slots are the rewritable modules of each production's successor (slot
//! `p2.4` = position 4 of the module's second production); only the chosen
//! production's slots are read. An empty link leaves the module as it is
//! (it stops growing), so a genome is a derivation that optimizers can prune
//! and regrow; the depth limit is the derivation length.
//!
//! The root gene holds one value per ranged constant (`define a = 30 in
//! [0, 90]`, `define n = 3 in 1..5`): a uniform real, or a uniform whole
//! number. A genome's derivation recompiles the system with those values,
//! so the optimizers steer the constants like any other parameter.

use crate::alphabet::Sym;
use crate::compile::LSystem;
use crate::derive::{Scratch, Site, emit};
use crate::ranged::RangedConstant;
use crate::rules::{Entry, Stored};
use crate::string::ModuleString;
use crate::turtle::TurtleError;
use genform_core::genome::{GenePos, Link};
use genform_core::graph::{Distribution, ParamSpec, SlotSpec, SymbolId, SymbolSpec};
use genform_core::{ExpressError, Generator, GeneratorGraph, Genome, LimitKind, Limits, Rng, Sampled, Scene};
use std::borrow::Cow;
use std::sync::Arc;

/// Why an L-system cannot be a generator.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GeneratorError {
    /// Context-sensitive productions depend on neighbours, not on a tree.
    #[error(
        "`{0}` has context-sensitive productions (a context, or a predecessor of several modules); evolutionary control needs a context-free L-system (a module's rewrite may depend only on the module)"
    )]
    Context(String),
    /// Decomposition rewrites modules outside the derivation tree.
    #[error("`{0}` has decomposition rules; evolutionary control supports productions and interpretation rules only")]
    Decomposition(String),
    /// Hooks change globals between steps, and bodies produce successors
    /// of varying shape: neither is a fixed rewrite of one module.
    #[error(
        "`{0}` has {1}; evolutionary control needs productions with a fixed successor and no Start/StartEach/EndEach/End hooks"
    )]
    Statements(String, &'static str),
    /// With growth 1 every link is mandatory, and optimizers would grow the
    /// successors of productions that are not chosen.
    #[error(
        "`{0}` chooses among productions (stochastic or conditional) with `growth: 1`; set `growth:` below 1 (e.g. 0.9) so optimizers can prune and regrow branches"
    )]
    Growth(String),
}

/// Where a gene's successor positions link.
#[derive(Clone, Debug)]
struct GeneSymbol {
    /// Whether the gene's first parameter is the roulette position.
    roulette: bool,
    /// Per rule of the productions table: the link of each successor
    /// position, `None` for modules that are not rewritten.
    links: Vec<Vec<Option<usize>>>,
}

/// A context-free L-system as a generator of derivation-tree genomes.
#[derive(Clone, Debug)]
pub struct LsGenerator {
    system: Arc<LSystem>,
    graph: GeneratorGraph,
    /// Graph symbol of each rewritable module symbol.
    symbol_of: Vec<Option<SymbolId>>,
    /// Per graph symbol (index 0 = the axiom).
    genes: Vec<GeneSymbol>,
}

const ROOT: SymbolId = 0;

/// The deepest derivation a genome may hold whatever the limits say, so
/// expression (which recurses per step) stays well within a thread's stack.
pub const MAX_GENERATOR_DEPTH: usize = 1000;

impl LsGenerator {
    /// The generator of `system`, or why it cannot be one.
    pub fn new(system: Arc<LSystem>) -> Result<LsGenerator, GeneratorError> {
        let name = system.settings.name.clone();
        if system.productions.context {
            return Err(GeneratorError::Context(name));
        }
        if !system.decomposition.is_empty() {
            return Err(GeneratorError::Decomposition(name));
        }
        let table = &system.productions;
        if system.has_hooks() {
            return Err(GeneratorError::Statements(name, "hooks"));
        }
        if table.rules.iter().any(|r| r.body.is_some()) {
            return Err(GeneratorError::Statements(name, "production bodies (`-> { … produce … }`)"));
        }
        let n = system.alphabet.symbols.len();
        let rewritable: Vec<bool> = (0..n).map(|s| !table.by_sym[s].is_empty()).collect();
        let growth = system.settings.growth;
        let chooses = |s: usize| {
            let e = &table.by_sym[s];
            e.len() > 1
                || matches!(e.first(), Some(Entry::Group(_)))
                || table.rules.iter().any(|r| r.strict as usize == s && r.cond.is_some())
        };
        if growth >= 1.0 && (0..n).any(chooses) {
            return Err(GeneratorError::Growth(name));
        }
        let mut symbol_of = vec![None; n];
        let mut next = 1;
        for (s, r) in rewritable.iter().enumerate() {
            if *r {
                symbol_of[s] = Some(next);
                next += 1;
            }
        }
        let display = |s: usize| {
            let info = &system.alphabet.symbols[s];
            let same_name = system.alphabet.named(&info.name).count();
            if same_name > 1 { format!("{}/{}", info.name, info.arity) } else { info.name.clone() }
        };
        let slot = |name: String, s: Sym| SlotSpec {
            name,
            target: symbol_of[s as usize].expect("slots target rewritable modules"),
            prob: growth,
            max_count: 1,
        };
        // The axiom's rewritable positions.
        let mut root_slots = Vec::new();
        let mut root_links = Vec::new();
        for (j, &s) in system.axiom.syms.iter().enumerate() {
            if rewritable[s as usize] {
                root_links.push(Some(root_slots.len()));
                root_slots.push(slot(format!("a{j}"), s));
            } else {
                root_links.push(None);
            }
        }
        let emits = |rules: &[usize]| {
            rules.iter().any(|&r| {
                table.rules[r].succ_syms.iter().any(|&s| system.alphabet.command(s) == crate::alphabet::Command::Draw)
            })
        };
        let root_params = system.ranged_constants().iter().map(constant_param).collect();
        let mut symbols =
            vec![SymbolSpec { name: "axiom".into(), params: root_params, slots: root_slots, emits_geometry: false }];
        let mut genes = vec![GeneSymbol { roulette: false, links: vec![root_links] }];
        let unit = || vec![Distribution::Uniform { min: 0.0, max: 1.0 }];
        for s in 0..n {
            if !rewritable[s] {
                continue;
            }
            let mine: Vec<usize> = (0..table.rules.len()).filter(|&r| table.rules[r].strict as usize == s).collect();
            let roulette = table.by_sym[s].iter().any(|e| matches!(e, Entry::Group(_)));
            let mut params = Vec::new();
            if roulette {
                params.push(ParamSpec { name: "rule".into(), components: unit() });
            }
            let draws = mine.iter().map(|&r| table.rules[r].draws).max().unwrap_or(0);
            for k in 0..draws {
                params.push(ParamSpec { name: format!("u{k}"), components: unit() });
            }
            let mut slots = Vec::new();
            let mut links = vec![Vec::new(); table.rules.len()];
            for (k, &r) in mine.iter().enumerate() {
                for (j, &t) in table.rules[r].succ_syms.iter().enumerate() {
                    if rewritable[t as usize] {
                        links[r].push(Some(slots.len()));
                        slots.push(slot(format!("p{}.{j}", k + 1), t));
                    } else {
                        links[r].push(None);
                    }
                }
            }
            let emits_geometry = emits(&mine);
            symbols.push(SymbolSpec { name: display(s), params, slots, emits_geometry });
            genes.push(GeneSymbol { roulette, links });
        }
        let graph = GeneratorGraph { name: system.settings.name.clone(), symbols, root: ROOT };
        Ok(LsGenerator { system, graph, symbol_of, genes })
    }

    /// The L-system.
    pub fn system(&self) -> &LSystem {
        &self.system
    }

    /// Derivation limits: the derivation length is the depth limit.
    pub fn limits(&self) -> Limits {
        Limits { max_depth: self.system.settings.derivation as usize, ..Limits::default() }
    }

    /// The module string a genome derives.
    pub fn derive(&self, genome: &Genome, limits: &Limits) -> Result<ModuleString, ExpressError> {
        Ok(self.derived(genome, limits)?.1)
    }

    /// The system with the genome's constants, and the string it derives.
    fn derived(&self, genome: &Genome, limits: &Limits) -> Result<(Cow<'_, LSystem>, ModuleString), ExpressError> {
        let root = genome.root().ok_or_else(|| ExpressError::Eval("the genome is empty".into()))?;
        let system = self.system_for(genome.gene(root).params())?;
        let mut walk = Walk {
            owner: self,
            system: &system,
            genome: GenomeAccess::Read(genome),
            limits,
            out: ModuleString::default(),
            sc: Scratch::with_state(&system.initial_state),
            values: Vec::new(),
        };
        walk.axiom(root)?;
        // The state a derivation of that many steps ends with (no hook
        // changes it in a generator).
        let mut out = walk.out;
        out.state.clone_from(&system.initial_state);
        out.state[0] = limits.max_depth as f64;
        Ok((system, out))
    }

    /// The system with the root gene's constant values (the compiled
    /// system itself when there are no ranged constants).
    fn system_for(&self, values: impl Iterator<Item = f64>) -> Result<Cow<'_, LSystem>, ExpressError> {
        if self.system.ranged_constants().is_empty() {
            return Ok(Cow::Borrowed(&self.system));
        }
        let values: Vec<f64> = values.collect();
        self.system.with_constants(&values).map(Cow::Owned).map_err(ExpressError::Eval)
    }
}

/// The root parameter of a ranged constant: a uniform real, or a uniform
/// whole number (an L-Py `Bool` is `0..1`).
fn constant_param(c: &RangedConstant) -> ParamSpec {
    let d = if c.integer {
        // `check` admitted only whole, finite bounds.
        Distribution::IntRange { min: c.min as i64, max: c.max as i64 }
    } else {
        Distribution::Uniform { min: c.min, max: c.max }
    };
    ParamSpec { name: c.name.clone(), components: vec![d] }
}

enum GenomeAccess<'a> {
    Read(&'a Genome),
    Grow { genome: &'a mut Genome, rng: &'a mut Rng, truncated: Option<LimitKind>, params: Vec<f64> },
}

struct Walk<'a> {
    owner: &'a LsGenerator,
    /// The system with the genome's constants.
    system: &'a LSystem,
    genome: GenomeAccess<'a>,
    limits: &'a Limits,
    out: ModuleString,
    sc: Scratch,
    /// The parameters of the gene being rewritten.
    values: Vec<f64>,
}

impl Walk<'_> {
    fn genome(&self) -> &Genome {
        match &self.genome {
            GenomeAccess::Read(g) => g,
            GenomeAccess::Grow { genome, .. } => genome,
        }
    }

    /// The child at `link` of the gene at `pos` (grown first when
    /// sampling), if any.
    fn child(&mut self, pos: GenePos, link: usize, target: Sym, depth: usize) -> Result<Option<GenePos>, ExpressError> {
        let sym = self.owner.symbol_of[target as usize].expect("rewritable");
        match &mut self.genome {
            GenomeAccess::Read(g) => {
                let gene = g.gene(pos);
                if link >= gene.link_len() {
                    return Err(ExpressError::Eval("a gene has fewer links than its symbol".into()));
                }
                match gene.link(link) {
                    Link::Child(c) => {
                        if g.gene(c).symbol() != sym {
                            return Err(ExpressError::Eval(format!(
                                "gene {} is a `{}`, expected `{}`",
                                c.0,
                                self.owner.graph.symbol(g.gene(c).symbol()).name,
                                self.owner.graph.symbol(sym).name
                            )));
                        }
                        let max = self.limits.max_depth.min(MAX_GENERATOR_DEPTH);
                        if depth > max {
                            return Err(ExpressError::Limit { kind: LimitKind::Depth, limit: max });
                        }
                        Ok(Some(c))
                    }
                    _ => Ok(None),
                }
            }
            GenomeAccess::Grow { genome, rng, truncated, params } => {
                if !rng.bernoulli(self.system.settings.growth) {
                    return Ok(None);
                }
                if depth > self.limits.max_depth.min(MAX_GENERATOR_DEPTH) {
                    return Ok(None);
                }
                if genome.len() >= self.limits.max_genes {
                    truncated.get_or_insert(LimitKind::Genes);
                    return Ok(None);
                }
                let graph = &self.owner.graph;
                params.clear();
                graph.draw_params(sym, rng, params);
                Ok(Some(genome.grow(pos, link, sym, params, graph.symbol(sym).link_len())))
            }
        }
    }

    fn push(&mut self, sym: Sym, params: &[f64]) -> Result<(), ExpressError> {
        self.out.syms.push(sym);
        self.out.params.extend_from_slice(params);
        let cap = self.system.settings.max_modules;
        if !crate::derive::within(&self.out, cap) {
            return Err(ExpressError::Eval(format!(
                "the derived string has more than {cap} modules; raise `max_modules:` or shorten the derivation"
            )));
        }
        Ok(())
    }

    fn axiom(&mut self, root: GenePos) -> Result<(), ExpressError> {
        let sys = self.system;
        let links = &self.owner.genes[ROOT as usize].links[0];
        for ((sym, params), link) in sys.axiom.modules(&sys.alphabet).zip(links) {
            match link {
                Some(l) => match self.child(root, *l, sym, 1)? {
                    Some(c) => self.rewrite(c, sym, params, 1)?,
                    None => self.push(sym, params)?,
                },
                None => self.push(sym, params)?,
            }
        }
        Ok(())
    }

    /// Rewrites module (`sym`, `params`) as the gene at `pos` says.
    fn rewrite(&mut self, pos: GenePos, sym: Sym, params: &[f64], depth: usize) -> Result<(), ExpressError> {
        let owner = self.owner;
        let sys = self.system;
        let gene_sym = &owner.genes[owner.symbol_of[sym as usize].expect("rewritable") as usize];
        // The gene's values are needed only until the successor is emitted,
        // so one buffer serves every gene.
        let mut values = std::mem::take(&mut self.values);
        values.clear();
        values.extend(self.genome().gene(pos).params());
        let (roulette, uniforms) =
            if gene_sym.roulette { (values.first().copied(), &values[1..]) } else { (None, &values[..]) };
        let mut draws = Stored { values: uniforms, next: 0 };
        let site = Site { sym, params, ctx: None };
        // A module rewritten at depth d is rewritten by step d.
        self.sc.state[0] = (depth - 1) as f64;
        let chosen = sys.choose_with(&sys.productions, &site, &mut draws, roulette, &mut self.sc);
        let mut produced = ModuleString::default();
        let mut emitted = Ok(());
        if let Some(r) = chosen {
            emitted = emit(&sys.productions.rules[r as usize], &sys.alphabet, &self.sc, &mut produced, &mut draws);
        }
        self.values = values;
        if let (Some(r), Err(v)) = (chosen, emitted) {
            let e = sys.non_finite(&sys.productions.rules[r as usize], v, depth as u32, sys.settings.derivation);
            return Err(ExpressError::Eval(e.to_string()));
        }
        let Some(r) = chosen else {
            // No production applies: the module stays.
            return self.push(sym, params);
        };
        for ((s, p), link) in produced.modules(&sys.alphabet).zip(&gene_sym.links[r as usize]) {
            match link {
                Some(l) => match self.child(pos, *l, s, depth + 1)? {
                    Some(c) => self.rewrite(c, s, p, depth + 1)?,
                    None => self.push(s, p)?,
                },
                None => self.push(s, p)?,
            }
        }
        Ok(())
    }
}

impl Generator for LsGenerator {
    fn graph(&self) -> &GeneratorGraph {
        &self.graph
    }

    fn express(&self, genome: &Genome, limits: &Limits, scene: &mut Scene) -> Result<(), ExpressError> {
        if genome.len() > limits.max_genes {
            return Err(ExpressError::Limit { kind: LimitKind::Genes, limit: limits.max_genes });
        }
        let (system, s) = self.derived(genome, limits)?;
        // Interpretation rules draw from a fixed stream, so a genome always
        // gives the same drawing.
        system.interpret(&s, &mut Rng::from_seed(0), limits.max_primitives, scene).map_err(|e| match e {
            TurtleError::TooManyPrimitives { limit } => ExpressError::Limit { kind: LimitKind::Primitives, limit },
        })?;
        Ok(())
    }

    /// Grows a derivation from the root: each module the derivation reaches
    /// is rewritten with probability `growth`, up to the derivation length.
    /// The root's constants are drawn first (uniformly in their ranges).
    fn sample(&self, rng: &mut Rng, limits: &Limits) -> Result<Sampled, ExpressError> {
        let mut constants = Vec::new();
        // No draw without ranged constants, so such systems sample as before.
        if !self.system.ranged_constants().is_empty() {
            self.graph.draw_params(ROOT, rng, &mut constants);
        }
        let mut genome = Genome::with_root(&self.graph, ROOT, &constants);
        let system = self.system_for(constants.iter().copied())?;
        let mut walk = Walk {
            owner: self,
            system: &system,
            genome: GenomeAccess::Grow { genome: &mut genome, rng, truncated: None, params: Vec::new() },
            limits,
            out: ModuleString::default(),
            sc: Scratch::with_state(&system.initial_state),
            values: Vec::new(),
        };
        walk.axiom(GenePos(0))?;
        let truncated = match walk.genome {
            GenomeAccess::Grow { truncated, .. } => truncated,
            GenomeAccess::Read(_) => None,
        };
        Ok(Sampled { genome, truncated })
    }
}
