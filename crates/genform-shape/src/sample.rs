//! Execution-driven prior sampling.
//!
//! The program runs as in expression, but links are decided when first
//! touched (by an invocation or by `has(slot)`): the slot's probability is
//! drawn once, and an expressed link grows a child gene with parameters
//! drawn from its distributions. Links the run never reaches stay empty, so
//! the genome follows the grammar's prior exactly: alternatives, conditions
//! and the template chain are respected, and a link touched twice (the
//! second pass of a `mirror`, the next face or tile of an invocation that
//! re-expresses its gene) keeps its first decision.

use crate::grammar::ShapeGrammar;
use crate::interp::{self, Mode, Stop};
use crate::program::SlotCode;
use crate::scratch::with_scratch;
use genform_core::genome::{GenePos, Link};
use genform_core::{ExpressError, Genome, LimitKind, Limits, Primitive, Rng, Sampled};
use glam::Affine3A;

/// Sampling mode: grows the genome as the run touches links.
pub(crate) struct SampleMode<'a> {
    pub genome: Genome,
    rng: &'a mut Rng,
    g: &'a ShapeGrammar,
    limits: Limits,
    pub truncated: Option<LimitKind>,
    /// Per gene (in storage order): its position and the start of its
    /// "decided" flags in `decided`.
    genes: Vec<(u32, usize)>,
    decided: Vec<bool>,
    params: Vec<f64>,
}

impl SampleMode<'_> {
    fn register(&mut self, pos: GenePos, links: usize) {
        self.genes.push((pos.0, self.decided.len()));
        self.decided.extend(std::iter::repeat_n(false, links));
    }
}

impl Mode for SampleMode<'_> {
    fn genome(&self) -> &Genome {
        &self.genome
    }

    fn touch(
        &mut self,
        gene: GenePos,
        link: usize,
        slot: &SlotCode,
        child_depth: usize,
    ) -> Result<Option<GenePos>, Stop> {
        match self.genome.gene(gene).link(link) {
            Link::Child(c) => return Ok(Some(c)),
            Link::Closed => return Ok(None),
            Link::Empty => {}
        }
        // Genes are appended in increasing position order.
        let Ok(i) = self.genes.binary_search_by_key(&gene.0, |(p, _)| *p) else {
            return Ok(None);
        };
        let flag = self.genes[i].1 + link;
        if self.decided[flag] {
            return Ok(None);
        }
        self.decided[flag] = true;
        if !self.rng.bernoulli(slot.prob) {
            return Ok(None);
        }
        if child_depth > self.limits.max_depth {
            self.truncated.get_or_insert(LimitKind::Depth);
            return Ok(None);
        }
        if self.genome.len() >= self.limits.max_genes {
            self.truncated.get_or_insert(LimitKind::Genes);
            return Ok(None);
        }
        let graph = &self.g.graph;
        self.params.clear();
        graph.draw_params(slot.target, self.rng, &mut self.params);
        let links = graph.symbol(slot.target).link_len();
        let child = self.genome.grow(gene, link, slot.target, &self.params, links);
        self.register(child, links);
        Ok(Some(child))
    }

    fn emit(&mut self, _: &ShapeGrammar, _: Affine3A, _: Primitive, _: u32) {}

    fn emit_polygon(&mut self, _: &ShapeGrammar, _: Vec<glam::Vec3>, _: u32) {}

    fn emit_mesh(&mut self, _: &ShapeGrammar, _: Affine3A, _: genform_core::Mesh, _: u32) {}

    fn limit(&self, kind: LimitKind, _: &Limits) -> Stop {
        Stop::Truncate(kind)
    }
}

/// Draws a genome from the grammar's prior by running it.
pub(crate) fn sample(g: &ShapeGrammar, rng: &mut Rng, limits: &Limits) -> Result<Sampled, ExpressError> {
    let graph = &g.graph;
    let mut params = Vec::new();
    graph.draw_params(graph.root, rng, &mut params);
    let genome = Genome::with_root(graph, graph.root, &params);
    let links = graph.symbol(graph.root).link_len();
    let mut mode =
        SampleMode { genome, rng, g, limits: *limits, truncated: None, genes: Vec::new(), decided: Vec::new(), params };
    mode.register(GenePos(0), links);
    if limits.max_genes == 0 {
        mode.truncated = Some(LimitKind::Genes);
    }
    let (res, mut mode) = with_scratch(|scratch| interp::run(g, limits, mode, &mut scratch.stacks));
    match res {
        Ok(()) => {}
        Err(Stop::Truncate(kind)) => {
            mode.truncated.get_or_insert(kind);
        }
        Err(Stop::Error(e)) => return Err(*e),
    }
    Ok(Sampled { genome: mode.genome, truncated: mode.truncated })
}
