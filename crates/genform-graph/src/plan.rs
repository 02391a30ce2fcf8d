//! Search plans: in which order a mother pattern's elements are bound, and
//! which checks run after each binding.
//!
//! One plan per possible anchor (every mother element), made at compile
//! time; at run time the anchor with the fewest candidates in the label
//! index is chosen. From the anchor, a plan extends along edges incident to
//! bound vertices (both ends bound first — the cheapest test — then
//! labelled, then directed edges), so every later element is found through
//! an adjacency list, never by scanning the graph. A pattern with several
//! components starts each further component with a scan. Conditions,
//! named vectors and spatial-order tests run as soon as everything they
//! read is bound.

use crate::mother::{MEdge, MVertex, PairVector, SpatialPair};

/// One binding operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    /// Try every candidate host vertex for mother vertex `v`.
    ScanVertex(usize),
    /// Try every candidate host edge for mother edge `e` (binds its ends).
    ScanEdge(usize),
    /// Walk the adjacency list of the host vertex bound to mother vertex
    /// `from` for mother edge `edge`; its other end is mother vertex `to`
    /// (already bound when `to_bound`).
    Extend { edge: usize, from: usize, to: usize, to_bound: bool },
}

/// A binding and what to check once it holds.
#[derive(Clone, Debug)]
pub(crate) struct Step {
    pub(crate) op: Op,
    /// Pair vectors (indices) whose ends are now both bound.
    pub(crate) vectors: Vec<usize>,
    /// Spatial pairs (indices) now testable.
    pub(crate) spatial: Vec<usize>,
    /// Conditions (indices) now evaluable.
    pub(crate) conditions: Vec<usize>,
}

#[derive(Clone, Debug)]
pub(crate) struct Plan {
    pub(crate) steps: Vec<Step>,
}

/// Elements are numbered vertices first, then edges.
pub(crate) fn make_plan(
    anchor: usize,
    mv: &[MVertex],
    me: &[MEdge],
    vectors: &[PairVector],
    spatial: &[SpatialPair],
    condition_deps: &[Vec<usize>],
) -> Plan {
    let nv = mv.len();
    let mut vb = vec![false; nv];
    let mut eb = vec![false; me.len()];
    let mut ops = Vec::new();
    let mut push = |op: Op, vb: &mut Vec<bool>, eb: &mut Vec<bool>| {
        match op {
            Op::ScanVertex(v) => vb[v] = true,
            Op::ScanEdge(e) => {
                eb[e] = true;
                vb[me[e].from] = true;
                vb[me[e].to] = true;
            }
            Op::Extend { edge, to, .. } => {
                eb[edge] = true;
                vb[to] = true;
            }
        }
        ops.push(op);
    };
    if anchor < nv {
        push(Op::ScanVertex(anchor), &mut vb, &mut eb);
    } else if anchor < nv + me.len() {
        push(Op::ScanEdge(anchor - nv), &mut vb, &mut eb);
    }
    loop {
        // Edges hanging off the bound part, best first.
        let score = |e: &MEdge| {
            let both = vb[e.from] && vb[e.to];
            (usize::from(both) << 2) | (usize::from(e.label.is_some()) << 1) | usize::from(e.directed)
        };
        let next = (0..me.len())
            .filter(|&e| !eb[e] && (vb[me[e].from] || vb[me[e].to]))
            .max_by_key(|&e| (score(&me[e]), std::cmp::Reverse(e)));
        if let Some(e) = next {
            let (from, to) = if vb[me[e].from] { (me[e].from, me[e].to) } else { (me[e].to, me[e].from) };
            push(Op::Extend { edge: e, from, to, to_bound: vb[to] }, &mut vb, &mut eb);
            continue;
        }
        // A new component: a labelled edge, an edge, a labelled vertex, a
        // vertex.
        let edge = (0..me.len()).filter(|&e| !eb[e]).max_by_key(|&e| (me[e].label.is_some(), std::cmp::Reverse(e)));
        if let Some(e) = edge {
            push(Op::ScanEdge(e), &mut vb, &mut eb);
            continue;
        }
        let vertex =
            (0..nv).filter(|&v| !vb[v]).max_by_key(|&v| (mv[v].label.is_some(), !mv[v].wildcard, std::cmp::Reverse(v)));
        match vertex {
            Some(v) => push(Op::ScanVertex(v), &mut vb, &mut eb),
            None => break,
        }
    }

    // When is each element bound?
    let mut bound_at = vec![usize::MAX; nv + me.len()];
    for (i, op) in ops.iter().enumerate() {
        let mut set = |k: usize| {
            if bound_at[k] == usize::MAX {
                bound_at[k] = i;
            }
        };
        match *op {
            Op::ScanVertex(v) => set(v),
            Op::ScanEdge(e) => {
                set(nv + e);
                set(me[e].from);
                set(me[e].to);
            }
            Op::Extend { edge, to, .. } => {
                set(nv + edge);
                set(to);
            }
        }
    }
    let ready = |deps: &mut dyn Iterator<Item = usize>| deps.map(|k| bound_at[k]).max();
    let mut steps: Vec<Step> = ops
        .into_iter()
        .map(|op| Step { op, vectors: Vec::new(), spatial: Vec::new(), conditions: Vec::new() })
        .collect();
    for (i, v) in vectors.iter().enumerate() {
        if let Some(s) = ready(&mut [v.from, v.to].into_iter()) {
            steps[s].vectors.push(i);
        }
    }
    for (i, p) in spatial.iter().enumerate() {
        if let Some(s) = ready(&mut [p.a, p.b].into_iter()) {
            steps[s].spatial.push(i);
        }
    }
    for (i, deps) in condition_deps.iter().enumerate() {
        // Conditions without dependencies are checked before the search.
        if let Some(s) = ready(&mut deps.iter().copied()) {
            steps[s].conditions.push(i);
        }
    }
    Plan { steps }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(label: Option<u32>) -> MVertex {
        MVertex { name: String::new(), label, attrs: vec![], wildcard: false, at: None, loads: vec![] }
    }

    fn e(from: usize, to: usize, label: Option<u32>) -> MEdge {
        MEdge { name: String::new(), from, to, directed: false, label, attrs: vec![], loads: vec![] }
    }

    #[test]
    fn plans_walk_adjacency_and_close_cycles_first() {
        // Triangle 0-1-2 plus a lone vertex 3.
        let mv = vec![v(None), v(None), v(None), v(Some(1))];
        let me = vec![e(0, 1, None), e(1, 2, Some(2)), e(2, 0, None)];
        let plan = make_plan(3 + 1, &mv, &me, &[], &[], &[vec![0, 2], vec![3]]);
        let ops: Vec<Op> = plan.steps.iter().map(|s| s.op).collect();
        assert_eq!(
            ops,
            [
                Op::ScanEdge(0),
                // Both ends of edge 1 and 2 are not bound yet; edge 1 has a label.
                Op::Extend { edge: 1, from: 1, to: 2, to_bound: false },
                Op::Extend { edge: 2, from: 2, to: 0, to_bound: true },
                Op::ScanVertex(3),
            ]
        );
        // Condition 0 reads vertices 0 and 2: ready after step 1.
        assert_eq!(plan.steps[1].conditions, [0]);
        assert_eq!(plan.steps[3].conditions, [1]);
    }
}
