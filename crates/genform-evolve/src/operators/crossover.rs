//! Single-point subtree crossover on compatible connections (paper
//! Algorithm 1).

use super::shared::{Connection, LengthBounds};
use genform_core::genome::{GenePos, Link};
use genform_core::{GeneratorGraph, Genome, Limits, Rng};

/// Two children made by [`crossover`].
#[derive(Clone, Debug, PartialEq)]
pub struct Crossed {
    /// Parent 1 with the subtree at `points[0]` replaced by parent 2's
    /// subtree at `points[1]` (or removed when that link was empty), and
    /// parent 2 with the subtrees exchanged the other way.
    pub children: [Genome; 2],
    /// The exchanged connections: `points[0]` in parent 1 (and child 1),
    /// `points[1]` in parent 2 (and child 2). Both belong to the same graph
    /// edge (parent symbol, slot).
    pub points: [Connection; 2],
}

/// What [`crossover`] produced.
#[derive(Clone, Debug, PartialEq)]
pub struct CrossoverOutcome {
    /// The children, `None` when every try failed.
    pub crossed: Option<Crossed>,
    /// Failed tries: tries before the successful one, or all tries.
    pub retries: usize,
}

/// Exchanges subtrees between two parents on the same graph edge.
///
/// Each try picks a uniformly random non-root gene `e1` of parent 1, hanging
/// at (`q1`, `l1`). The compatible connections in parent 2 are the links of
/// the same edge — genes with `q1`'s symbol, links of `l1`'s slot — that hold
/// a child or are empty (an empty link: fewer siblings than `max_count`), but
/// not closed ones, and not empty links of `p = 1` slots, which would strip a
/// mandatory child from child 1. One is picked uniformly. Child 1 receives
/// its subtree (or nothing) in place of `e1`; child 2 receives `e1`'s subtree
/// at that link.
///
/// A try fails when parent 2 has no compatible connection or a child would
/// leave `bounds` or `limits` (genes, depth); at most `tries` tries are made.
pub fn crossover(
    parents: [&Genome; 2],
    graph: &GeneratorGraph,
    limits: &Limits,
    bounds: &LengthBounds,
    tries: usize,
    rng: &mut Rng,
) -> CrossoverOutcome {
    let [p1, p2] = parents;
    if p1.len() < 2 || p2.is_empty() {
        return CrossoverOutcome { crossed: None, retries: tries };
    }
    // Depth is bounded by length, so it only matters for long parents.
    let check_depth = p1.len() + p2.len() > limits.max_depth;
    let mut candidates = Vec::new();
    for failed in 0..tries {
        let e1 = p1.iter().nth(1 + rng.index(p1.len() - 1)).expect("index below length").pos;
        let (q1, l1) = p1.gene(e1).parent().expect("non-root gene");
        let symbol = p1.gene(q1).symbol();
        let spec = graph.symbol(symbol);
        let Some((slot, _)) = spec.slot_of_link(l1) else { continue };
        let first = spec.link_offset(slot);
        let links = first..first + spec.slots[slot].max_count as usize;
        let mandatory = spec.slots[slot].prob >= 1.0;

        candidates.clear();
        for g in p2.iter().filter(|g| g.symbol() == symbol) {
            for link in links.clone() {
                match g.link(link) {
                    Link::Child(c) => candidates.push((Connection { parent: g.pos, link }, Some(c))),
                    Link::Empty if !mandatory => candidates.push((Connection { parent: g.pos, link }, None)),
                    _ => {}
                }
            }
        }
        if candidates.is_empty() {
            continue;
        }
        let (at2, e2) = candidates[rng.index(candidates.len())];

        let s1 = p1.subtree_len(e1);
        let s2 = e2.map_or(0, |e| p2.subtree_len(e));
        let lens = [p1.len() - s1 + s2, p2.len() - s2 + s1];
        if lens.iter().any(|&n| !bounds.contains(n) || n > limits.max_genes) {
            continue;
        }
        if check_depth {
            let h1 = subtree_height(p1, e1);
            let h2 = e2.map_or(0, |e| subtree_height(p2, e));
            // Attaching under a gene at depth d puts the subtree root at d + 1.
            if p1.depth(q1) + h2 >= limits.max_depth || p2.depth(at2.parent) + h1 >= limits.max_depth {
                continue;
            }
        }

        let at1 = Connection { parent: q1, link: l1 };
        // Cutting compacts only genes stored after the cut one, and parents
        // precede their children, so the parents' positions stay valid.
        let mut c1 = p1.clone();
        c1.cut(e1);
        if let Some(e2) = e2 {
            c1.graft(p2, e2, q1, l1);
        }
        let mut c2 = p2.clone();
        if let Some(e2) = e2 {
            c2.cut(e2);
        }
        c2.graft(p1, e1, at2.parent, at2.link);
        return CrossoverOutcome { crossed: Some(Crossed { children: [c1, c2], points: [at1, at2] }), retries: failed };
    }
    CrossoverOutcome { crossed: None, retries: tries }
}

/// Height of the subtree rooted at `pos` (0 for a single gene).
fn subtree_height(genome: &Genome, pos: GenePos) -> usize {
    let mut height = 0;
    let mut stack = vec![(pos, 0usize)];
    while let Some((p, h)) = stack.pop() {
        height = height.max(h);
        for l in genome.gene(p).links() {
            if let Link::Child(c) = l {
                stack.push((c, h + 1));
            }
        }
    }
    height
}
