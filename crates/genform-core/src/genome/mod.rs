//! The packed derivation-tree genome (ShapeGenetics thesis §3.2).
//!
//! A genome is one contiguous `Vec<u64>`. Each gene occupies
//! `2 + params + links` words:
//!
//! ```text
//! word 0   symbol id (bits 0..32) | param count (32..48) | link count (48..64)
//! word 1   distance back to the parent (bits 0..32, 0 for the root)
//!          | index of the parent's link holding this gene (32..64)
//! params   f64 bit patterns
//! links    per link: distance forward to the child (> 0), 0 = empty,
//!          CLOSED = never to be expressed (SMC marks skipped slots)
//! ```
//!
//! Invariants: the root is the first gene; every child is stored after its
//! parent, so offsets to children are positive and to parents negative; the
//! child's (parent, link) pair and the parent's link agree. Because links are
//! relative, a subtree copied to another genome keeps its internal links;
//! growing appends at the end; cutting is one forward sweep (O(words)).

mod file;
mod json;

pub use file::{GenomeFile, JsonGene};

use crate::graph::{GeneratorGraph, SymbolId};
use std::fmt;

/// Word position of a gene inside a [`Genome`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GenePos(pub u32);

/// Link value meaning "decided: never expressed".
const CLOSED: u64 = u64::MAX;
const HEADER: usize = 2;

/// State of one link of a gene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Link {
    /// No child; may be grown.
    Empty,
    /// No child, and marked never to be expressed.
    Closed,
    /// The child gene.
    Child(GenePos),
}

/// Why a genome does not fit its generator graph.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GenomeError {
    /// The genome has no genes.
    #[error("the genome is empty")]
    Empty,
    /// The first gene's symbol is not the graph's start symbol.
    #[error("the root gene is `{found}`, but the generator starts with `{expected}`")]
    WrongRoot {
        /// Symbol of the root gene.
        found: String,
        /// The graph's start symbol.
        expected: String,
    },
    /// A gene names a symbol the graph does not have.
    #[error("gene {gene} uses symbol id {symbol}, which the generator does not have")]
    UnknownSymbol {
        /// Gene ordinal.
        gene: usize,
        /// Offending id.
        symbol: u32,
    },
    /// A gene's parameter or link count does not match its symbol.
    #[error("gene {gene} (`{symbol}`) has {found} {what}, the generator declares {expected}")]
    Shape {
        /// Gene ordinal.
        gene: usize,
        /// Its symbol.
        symbol: String,
        /// "parameter values" or "links".
        what: &'static str,
        /// Count in the genome.
        found: usize,
        /// Count the graph declares.
        expected: usize,
    },
    /// A parameter value lies outside its distribution's support.
    #[error("gene {gene} (`{symbol}`): parameter `{param}` = {value} is outside {dist}")]
    ParamOutOfRange {
        /// Gene ordinal.
        gene: usize,
        /// Its symbol.
        symbol: String,
        /// Parameter name (with component).
        param: String,
        /// The value.
        value: f64,
        /// The distribution, described.
        dist: String,
    },
    /// A child sits in a slot whose target is another symbol.
    #[error("gene {gene} (`{child}`) sits in slot `{slot}` of `{parent}`, which holds `{expected}`")]
    WrongChild {
        /// Gene ordinal of the child.
        gene: usize,
        /// The child's symbol.
        child: String,
        /// The parent's symbol.
        parent: String,
        /// The slot name.
        slot: String,
        /// The symbol the slot holds.
        expected: String,
    },
    /// Links, parent offsets or gene boundaries are inconsistent.
    #[error("corrupt genome: {0}")]
    Corrupt(String),
    /// A JSON genome file could not be read.
    #[error("{0}")]
    Json(String),
}

/// A derivation tree, packed. See the module documentation for the layout.
#[derive(Clone, Default, PartialEq, Eq, Hash)]
pub struct Genome {
    words: Vec<u64>,
    genes: u32,
}

/// New positions of genes stored at or after `start`, indexed by old word
/// offset, so the sweeps of `cut` and `graft` stay O(words).
struct Remap {
    start: usize,
    to: Vec<u32>,
}

impl Remap {
    fn new(start: usize, end: usize) -> Self {
        Remap { start, to: vec![u32::MAX; end.saturating_sub(start)] }
    }

    fn set(&mut self, old: usize, new: usize) {
        self.to[old - self.start] = new as u32;
    }

    /// Where the gene formerly at `old` went; `None` if it was dropped, not
    /// yet reached, or lies before `start`.
    fn get(&self, old: usize) -> Option<usize> {
        let i = old.checked_sub(self.start)?;
        self.to.get(i).filter(|&&v| v != u32::MAX).map(|&v| v as usize)
    }
}

/// A read-only view of one gene.
#[derive(Clone, Copy)]
pub struct GeneRef<'a> {
    /// Where the gene starts.
    pub pos: GenePos,
    w: &'a [u64],
}

impl<'a> GeneRef<'a> {
    /// The gene's symbol.
    #[inline]
    pub fn symbol(&self) -> SymbolId {
        self.w[0] as u32
    }
    /// Number of parameter values.
    #[inline]
    pub fn param_len(&self) -> usize {
        ((self.w[0] >> 32) & 0xFFFF) as usize
    }
    /// Number of links.
    #[inline]
    pub fn link_len(&self) -> usize {
        (self.w[0] >> 48) as usize
    }
    /// Total words.
    #[inline]
    pub fn size(&self) -> usize {
        HEADER + self.param_len() + self.link_len()
    }
    /// Parameter value `i`.
    #[inline]
    pub fn param(&self, i: usize) -> f64 {
        debug_assert!(i < self.param_len());
        f64::from_bits(self.w[HEADER + i])
    }
    /// All parameter values.
    pub fn params(&self) -> impl ExactSizeIterator<Item = f64> + 'a {
        let n = self.param_len();
        self.w[HEADER..HEADER + n].iter().map(|b| f64::from_bits(*b))
    }
    /// The parent and the parent's link index; `None` for the root.
    #[inline]
    pub fn parent(&self) -> Option<(GenePos, usize)> {
        let back = self.w[1] as u32;
        (back != 0).then(|| (GenePos(self.pos.0 - back), (self.w[1] >> 32) as usize))
    }
    /// Link `i`.
    #[inline]
    pub fn link(&self, i: usize) -> Link {
        let v = self.w[HEADER + self.param_len() + i];
        match v {
            0 => Link::Empty,
            CLOSED => Link::Closed,
            d => Link::Child(GenePos(self.pos.0 + d as u32)),
        }
    }
    /// All links in order.
    pub fn links(&self) -> impl ExactSizeIterator<Item = Link> + 'a {
        let me = *self;
        (0..self.link_len()).map(move |i| me.link(i))
    }
    /// Number of expressed children.
    pub fn child_count(&self) -> usize {
        self.links().filter(|l| matches!(l, Link::Child(_))).count()
    }
}

impl fmt::Debug for GeneRef<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Gene")
            .field("pos", &self.pos.0)
            .field("symbol", &self.symbol())
            .field("parent", &self.parent())
            .field("params", &self.params().collect::<Vec<_>>())
            .field("links", &self.links().collect::<Vec<_>>())
            .finish()
    }
}

impl fmt::Debug for Genome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

fn header(symbol: SymbolId, params: usize, links: usize) -> u64 {
    assert!(params <= u16::MAX as usize && links <= u16::MAX as usize, "gene too large");
    symbol as u64 | (params as u64) << 32 | (links as u64) << 48
}

impl Genome {
    /// A genome with no genes.
    pub fn new() -> Self {
        Genome::default()
    }

    /// A genome holding only a root gene of `symbol` with `params`, sized for `graph`.
    pub fn with_root(graph: &GeneratorGraph, symbol: SymbolId, params: &[f64]) -> Self {
        let mut g = Genome::new();
        g.push_gene(symbol, params, graph.symbol(symbol).link_len(), None);
        g
    }

    /// Number of genes.
    #[inline]
    pub fn len(&self) -> usize {
        self.genes as usize
    }

    /// Whether there are no genes.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.genes == 0
    }

    /// Storage size in words.
    pub fn word_len(&self) -> usize {
        self.words.len()
    }

    /// The root gene, if any.
    pub fn root(&self) -> Option<GenePos> {
        (!self.is_empty()).then_some(GenePos(0))
    }

    /// The gene at `pos`.
    #[inline]
    pub fn gene(&self, pos: GenePos) -> GeneRef<'_> {
        let p = pos.0 as usize;
        let h = self.words[p];
        let size = HEADER + ((h >> 32) & 0xFFFF) as usize + (h >> 48) as usize;
        GeneRef { pos, w: &self.words[p..p + size] }
    }

    /// All genes in storage order (every parent before its children).
    pub fn iter(&self) -> impl Iterator<Item = GeneRef<'_>> + '_ {
        let mut p = 0usize;
        std::iter::from_fn(move || {
            (p < self.words.len()).then(|| {
                let g = self.gene(GenePos(p as u32));
                p += g.size();
                g
            })
        })
    }

    /// Writes the position of every gene, in storage order, into `out` (cleared first).
    pub fn positions_into(&self, out: &mut Vec<GenePos>) {
        out.clear();
        out.extend(self.iter().map(|g| g.pos));
    }

    /// Depth of a gene (root = 0); O(depth).
    pub fn depth(&self, pos: GenePos) -> usize {
        let mut d = 0;
        let mut p = pos;
        while let Some((q, _)) = self.gene(p).parent() {
            d += 1;
            p = q;
        }
        d
    }

    /// Overwrites parameter value `i` of the gene at `pos`.
    #[inline]
    pub fn set_param(&mut self, pos: GenePos, i: usize, v: f64) {
        let g = self.gene(pos);
        assert!(i < g.param_len(), "parameter index out of range");
        self.words[pos.0 as usize + HEADER + i] = v.to_bits();
    }

    /// Overwrites all parameter values of the gene at `pos`.
    pub fn set_params(&mut self, pos: GenePos, values: &[f64]) {
        let n = self.gene(pos).param_len();
        assert_eq!(n, values.len(), "parameter count mismatch");
        let base = pos.0 as usize + HEADER;
        for (w, v) in self.words[base..base + n].iter_mut().zip(values) {
            *w = v.to_bits();
        }
    }

    fn link_word(&self, pos: GenePos, link: usize) -> usize {
        let g = self.gene(pos);
        assert!(link < g.link_len(), "link index out of range");
        pos.0 as usize + HEADER + g.param_len() + link
    }

    /// Marks an empty link as closed (never expressed), or reopens a closed
    /// one with `closed = false`. Links holding a child are left alone.
    pub fn set_closed(&mut self, pos: GenePos, link: usize, closed: bool) {
        let w = self.link_word(pos, link);
        match (self.words[w], closed) {
            (0, true) => self.words[w] = CLOSED,
            (CLOSED, false) => self.words[w] = 0,
            _ => {}
        }
    }

    fn push_gene(
        &mut self,
        symbol: SymbolId,
        params: &[f64],
        links: usize,
        parent: Option<(GenePos, usize)>,
    ) -> GenePos {
        let pos = self.words.len();
        assert!(pos < u32::MAX as usize / 2, "genome too large");
        self.words.push(header(symbol, params.len(), links));
        self.words.push(match parent {
            Some((p, link)) => (pos as u64 - p.0 as u64) | (link as u64) << 32,
            None => 0,
        });
        self.words.extend(params.iter().map(|v| v.to_bits()));
        self.words.extend(std::iter::repeat_n(0, links));
        self.genes += 1;
        GenePos(pos as u32)
    }

    /// Appends a new child gene under `parent`'s `link` (which must be empty
    /// or closed) and returns its position. `links` is the child symbol's
    /// link count (`graph.symbol(symbol).link_len()`).
    pub fn grow(&mut self, parent: GenePos, link: usize, symbol: SymbolId, params: &[f64], links: usize) -> GenePos {
        let w = self.link_word(parent, link);
        assert!(self.words[w] == 0 || self.words[w] == CLOSED, "link already holds a child");
        let pos = self.push_gene(symbol, params, links, Some((parent, link)));
        self.words[w] = (pos.0 - parent.0) as u64;
        pos
    }

    /// Removes the gene at `pos` and its whole subtree in one forward sweep,
    /// compacting storage and clearing the parent's link. Cutting the root
    /// empties the genome. Returns the number of genes removed.
    pub fn cut(&mut self, pos: GenePos) -> usize {
        let start = pos.0 as usize;
        if let Some((parent, link)) = self.gene(pos).parent() {
            let w = self.link_word(parent, link);
            self.words[w] = 0;
        }
        let mut moved = Remap::new(start, self.words.len());
        let mut read = start;
        let mut write = start;
        let mut removed = 0;
        while read < self.words.len() {
            let g = self.gene(GenePos(read as u32));
            let size = g.size();
            let parent = g.parent();
            let dead = read == start
                || parent.is_some_and(|(q, _)| q.0 as usize >= start && moved.get(q.0 as usize).is_none());
            if dead {
                removed += 1;
            } else {
                moved.set(read, write);
                if let Some((q, link)) = parent {
                    let q = q.0 as usize;
                    let nq = if q < start { q } else { moved.get(q).expect("kept parent was moved") };
                    self.words[read + 1] = (write as u64 - nq as u64) | (link as u64) << 32;
                }
                self.words.copy_within(read..read + size, write);
                write += size;
            }
            read += size;
        }
        self.words.truncate(write);
        self.genes -= removed;
        self.relink_from(start);
        removed as usize
    }

    /// Rewrites every parent's link to the genes stored at or after `start`
    /// from the children's (parent, link) records.
    fn relink_from(&mut self, start: usize) {
        let mut p = start;
        while p < self.words.len() {
            let g = self.gene(GenePos(p as u32));
            let size = g.size();
            if let Some((q, link)) = g.parent() {
                let w = self.link_word(q, link);
                self.words[w] = (p - q.0 as usize) as u64;
            }
            p += size;
        }
    }

    /// Appends a copy of `src`'s subtree rooted at `pos` under `self`'s gene
    /// `parent` at `link` (which must be empty or closed). Returns the new
    /// position of the copied subtree root. The caller guarantees that the
    /// subtree root's symbol is the one the link's slot holds.
    pub fn graft(&mut self, src: &Genome, pos: GenePos, parent: GenePos, link: usize) -> GenePos {
        let w = self.link_word(parent, link);
        assert!(self.words[w] == 0 || self.words[w] == CLOSED, "link already holds a child");
        let first = self.words.len();
        let start = pos.0 as usize;
        let mut copied = Remap::new(start, src.words.len());
        let mut read = start;
        while read < src.words.len() {
            let g = src.gene(GenePos(read as u32));
            let size = g.size();
            let member =
                if read == start { true } else { g.parent().is_some_and(|(q, _)| copied.get(q.0 as usize).is_some()) };
            if member {
                let write = self.words.len();
                copied.set(read, write);
                self.words.extend_from_slice(&src.words[read..read + size]);
                let (nq, l) = if read == start {
                    (parent.0 as usize, link)
                } else {
                    let (q, l) = g.parent().expect("member has a parent");
                    (copied.get(q.0 as usize).expect("parent copied first"), l)
                };
                self.words[write + 1] = (write - nq) as u64 | (l as u64) << 32;
                // Child links are rebuilt below; keep CLOSED markers.
                let links = write + HEADER + g.param_len();
                for v in &mut self.words[links..links + g.link_len()] {
                    if *v != CLOSED {
                        *v = 0;
                    }
                }
                self.genes += 1;
            }
            read += size;
        }
        self.relink_from(first);
        GenePos(first as u32)
    }

    /// The subtree rooted at `pos` as nested text, `symbol[params](links,)`
    /// with `_` for an empty and `x` for a closed link. It does not depend on
    /// where genes are stored, so two subtrees are equal exactly when their
    /// texts are (useful in tests and when comparing derivations).
    pub fn subtree_text(&self, pos: GenePos) -> String {
        let gene = self.gene(pos);
        let mut s = format!("{}{:?}(", gene.symbol(), gene.params().collect::<Vec<_>>());
        for l in gene.links() {
            match l {
                Link::Empty => s.push('_'),
                Link::Closed => s.push('x'),
                Link::Child(c) => s.push_str(&self.subtree_text(c)),
            }
            s.push(',');
        }
        s.push(')');
        s
    }

    /// Number of genes in the subtree rooted at `pos` (including it).
    pub fn subtree_len(&self, pos: GenePos) -> usize {
        let mut n = 0;
        let mut stack = vec![pos];
        while let Some(p) = stack.pop() {
            n += 1;
            stack.extend(self.gene(p).links().filter_map(|l| match l {
                Link::Child(c) => Some(c),
                _ => None,
            }));
        }
        n
    }

    /// Checks the packed structure and that the genome fits `graph`:
    /// symbols exist, the root is the start symbol, parameter and link counts
    /// match, values lie in their distributions, children sit in slots that
    /// hold their symbol, and links agree with parent records.
    pub fn validate(&self, graph: &GeneratorGraph) -> Result<(), GenomeError> {
        if self.is_empty() {
            return Err(GenomeError::Empty);
        }
        let nsym = graph.symbols.len() as u32;
        let mut positions = Vec::with_capacity(self.len());
        let mut p = 0usize;
        while p < self.words.len() {
            let h = self.words[p];
            let size = HEADER + ((h >> 32) & 0xFFFF) as usize + (h >> 48) as usize;
            if p + size > self.words.len() {
                return Err(GenomeError::Corrupt(format!("gene at word {p} runs past the end")));
            }
            positions.push(p as u32);
            p += size;
        }
        if positions.len() != self.len() {
            return Err(GenomeError::Corrupt(format!(
                "gene count {} but {} genes stored",
                self.len(),
                positions.len()
            )));
        }
        for (ordinal, &p) in positions.iter().enumerate() {
            let g = self.gene(GenePos(p));
            let sym = g.symbol();
            if sym >= nsym {
                return Err(GenomeError::UnknownSymbol { gene: ordinal, symbol: sym });
            }
            let spec = graph.symbol(sym);
            for (what, found, expected) in
                [("parameter values", g.param_len(), spec.param_len()), ("links", g.link_len(), spec.link_len())]
            {
                if found != expected {
                    return Err(GenomeError::Shape { gene: ordinal, symbol: spec.name.clone(), what, found, expected });
                }
            }
            let mut k = 0;
            for param in &spec.params {
                for (c, dist) in param.components.iter().enumerate() {
                    let v = g.param(k);
                    if !dist.contains(v) {
                        let name = if param.dim() > 1 { format!("{}[{c}]", param.name) } else { param.name.clone() };
                        return Err(GenomeError::ParamOutOfRange {
                            gene: ordinal,
                            symbol: spec.name.clone(),
                            param: name,
                            value: v,
                            dist: dist.describe(),
                        });
                    }
                    k += 1;
                }
            }
            match g.parent() {
                None if ordinal == 0 => {
                    if sym != graph.root {
                        return Err(GenomeError::WrongRoot {
                            found: spec.name.clone(),
                            expected: graph.symbol(graph.root).name.clone(),
                        });
                    }
                }
                None => {
                    return Err(GenomeError::Corrupt(format!("gene {ordinal} has no parent")));
                }
                Some(_) if ordinal == 0 => {
                    return Err(GenomeError::Corrupt("the root has a parent".into()));
                }
                Some((q, link)) => {
                    if positions.binary_search(&q.0).is_err() || q.0 >= p {
                        return Err(GenomeError::Corrupt(format!("gene {ordinal} has a bad parent offset")));
                    }
                    let pg = self.gene(q);
                    let pspec = graph.symbol(pg.symbol());
                    let Some((slot, _)) = pspec.slot_of_link(link) else {
                        return Err(GenomeError::Corrupt(format!("gene {ordinal} sits in missing link {link}")));
                    };
                    let s = &pspec.slots[slot];
                    if s.target != sym {
                        return Err(GenomeError::WrongChild {
                            gene: ordinal,
                            child: spec.name.clone(),
                            parent: pspec.name.clone(),
                            slot: s.name.clone(),
                            expected: graph.symbol(s.target).name.clone(),
                        });
                    }
                    if pg.link(link) != Link::Child(GenePos(p)) {
                        return Err(GenomeError::Corrupt(format!("gene {ordinal}'s parent link does not point back")));
                    }
                }
            }
            for (i, l) in g.links().enumerate() {
                if let Link::Child(c) = l {
                    let ok = positions.binary_search(&c.0).is_ok() && self.gene(c).parent() == Some((GenePos(p), i));
                    if !ok {
                        return Err(GenomeError::Corrupt(format!("gene {ordinal} link {i} is dangling")));
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
