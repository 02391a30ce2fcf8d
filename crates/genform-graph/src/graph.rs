//! The host graph: vertices and edges in slot arrays, rewritten in place.
//!
//! Slots of deleted elements go to free lists and are reused last-freed
//! first, so the same derivation always gives the same ids. Every vertex
//! keeps an adjacency list of its edges; every edge knows its position in
//! both endpoint lists, so deleting an edge is O(1). The candidate indexes
//! ([`Index`]) hold, per label, the live elements (swap-remove sets whose
//! positions the elements store), and, when a grammar asks for "oldest"
//! matching, the same sets split by generation.

use crate::element::{Common, NONE};
pub(crate) use crate::index::Index;
use crate::index::{index_insert, index_remove, relabel, slot_of};
use crate::names::Interner;
use std::collections::HashMap;
use std::sync::Arc;

/// An attribute value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number.
    Num(f64),
    /// Text (labels are kept apart, see [`VertexRef::label`]).
    Text(Arc<str>),
}

impl Value {
    /// The number, if it is one.
    pub fn as_num(&self) -> Option<f64> {
        match self {
            Value::Num(v) => Some(*v),
            Value::Text(_) => None,
        }
    }

    /// The text, if it is text.
    pub fn as_text(&self) -> Option<&str> {
        match self {
            Value::Text(t) => Some(t),
            Value::Num(_) => None,
        }
    }
}

#[derive(Clone, Debug)]
pub(crate) struct Vertex {
    pub(crate) c: Common,
    pub(crate) pos: [f64; 2],
    /// Incident edges (inline, then in [`AdjPool`]); a self-loop is listed
    /// twice.
    pub(crate) adj: Adj,
}

#[derive(Clone, Debug)]
pub(crate) struct Edge {
    pub(crate) c: Common,
    pub(crate) from: u32,
    pub(crate) to: u32,
    pub(crate) directed: bool,
    /// Position in `from`'s and `to`'s adjacency lists, kept exact only in
    /// lists that [`Adj::tracked`] says are (and always for a self-loop):
    /// in a short list the edge is found by scanning when it is removed, so
    /// that removing another edge need not touch this record, a cache miss
    /// on a large graph.
    pub(crate) adj_pos: [u32; 2],
}

/// Attribute lists shared between elements: most elements of a grammar
/// carry one of a few lists (every Koch edge the same stroke), so an
/// element holds a 4-byte id instead of its own heap list. Lists are
/// reference counted and found again by content (a hash chain per content
/// hash), so equal lists share one entry and an unused one is freed.
#[derive(Clone, Debug)]
pub(crate) struct AttrSets {
    sets: Vec<AttrSet>,
    free: Vec<u32>,
    /// Content hash → first set of that hash (the rest chain via `next`);
    /// the key is already a hash, so the map only mixes it once more.
    by_hash: HashMap<u64, u32, std::hash::BuildHasherDefault<Fx>>,
}

#[derive(Clone, Debug)]
struct AttrSet {
    /// Sorted by attribute id.
    attrs: Box<[(u32, Value)]>,
    refs: u32,
    hash: u64,
    next: u32,
}

/// Bit-exact equality: two lists share an entry only when every reader sees
/// the same values.
fn same_attrs(a: &[(u32, Value)], b: &[(u32, Value)]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|((ia, va), (ib, vb))| {
            ia == ib
                && match (va, vb) {
                    (Value::Num(x), Value::Num(y)) => x.to_bits() == y.to_bits(),
                    (Value::Text(x), Value::Text(y)) => x == y,
                    _ => false,
                }
        })
}

/// A multiply-rotate hash (as rustc's FxHash): attribute lists are hashed
/// once per new element, where SipHash cost about 15 % of a Koch step.
/// Only in-process lookups use it, so its quality needs no more.
#[derive(Default)]
struct Fx(u64);

impl std::hash::Hasher for Fx {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_u32(&mut self, v: u32) {
        self.write_u64(u64::from(v));
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

fn hash_attrs(attrs: &[(u32, Value)]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = Fx(0);
    for (id, v) in attrs {
        id.hash(&mut h);
        match v {
            Value::Num(x) => x.to_bits().hash(&mut h),
            Value::Text(t) => t.hash(&mut h),
        }
    }
    h.finish()
}

impl AttrSets {
    fn new() -> AttrSets {
        // Set 0 is the empty list, never counted nor freed.
        let empty = AttrSet { attrs: Box::default(), refs: 0, hash: 0, next: NONE };
        AttrSets { sets: vec![empty], free: Vec::new(), by_hash: HashMap::default() }
    }

    /// One more than the largest set id.
    pub(crate) fn len(&self) -> usize {
        self.sets.len()
    }

    /// The list of set `id`.
    pub(crate) fn get(&self, id: u32) -> &[(u32, Value)] {
        &self.sets[id as usize].attrs
    }

    /// The id of `attrs` (sorted by attribute id), counting one more user.
    pub(crate) fn intern(&mut self, attrs: &[(u32, Value)]) -> u32 {
        if attrs.is_empty() {
            return 0;
        }
        let hash = hash_attrs(attrs);
        let head = self.by_hash.get(&hash).copied().unwrap_or(NONE);
        let mut at = head;
        while at != NONE {
            let set = &mut self.sets[at as usize];
            if same_attrs(&set.attrs, attrs) {
                set.refs += 1;
                return at;
            }
            at = set.next;
        }
        let set = AttrSet { attrs: attrs.into(), refs: 1, hash, next: head };
        let id = match self.free.pop() {
            Some(id) => {
                self.sets[id as usize] = set;
                id
            }
            None => {
                self.sets.push(set);
                u32::try_from(self.sets.len() - 1).expect("fewer than 2^32 distinct attribute lists")
            }
        };
        self.by_hash.insert(hash, id);
        id
    }

    /// One more user of the live set `id` (an id [`AttrSets::intern`] gave).
    pub(crate) fn retain(&mut self, id: u32) {
        if id != 0 {
            self.sets[id as usize].refs += 1;
        }
    }

    /// One user less of set `id`; the last one frees it.
    pub(crate) fn release(&mut self, id: u32) {
        if id == 0 {
            return;
        }
        let set = &mut self.sets[id as usize];
        set.refs -= 1;
        if set.refs > 0 {
            return;
        }
        let (hash, next) = (set.hash, set.next);
        set.attrs = Box::default();
        let head = self.by_hash[&hash];
        if head == id {
            if next == NONE {
                self.by_hash.remove(&hash);
            } else {
                self.by_hash.insert(hash, next);
            }
        } else {
            let mut at = head;
            while self.sets[at as usize].next != id {
                at = self.sets[at as usize].next;
            }
            self.sets[at as usize].next = next;
        }
        self.free.push(id);
    }
}

/// A vertex's adjacency list: up to [`INLINE`] entries in the vertex
/// record itself (the vertex is read anyway, so a vertex of degree two,
/// most vertices of a curve, costs no further cache miss), then a block of
/// [`AdjPool`].
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Adj {
    /// The entries while inline; then `items[0]` is the block's start.
    items: [u32; INLINE as usize],
    pub(crate) len: u32,
    /// Log2 of the block's size; 0 while inline.
    block: u8,
    /// Whether a self-loop was ever added (its positions are always kept,
    /// see [`Edge::adj_pos`]); cleared when the vertex is removed.
    looped: bool,
}

/// Entries a list holds in its vertex record.
const INLINE: u32 = 2;

/// Adjacency lists of at most this many entries are scanned for an edge
/// being removed (one or two cache lines) instead of keeping every listed
/// edge's position in its record.
const SCANNED: u32 = 16;

impl Adj {
    fn cap(self) -> u32 {
        if self.block == 0 { INLINE } else { 1 << self.block }
    }

    /// Whether the records of the edges in this list keep their positions
    /// in it ([`Edge::adj_pos`]): in long lists, where scanning would cost
    /// more than the records' upkeep.
    fn tracked(self) -> bool {
        self.cap() > SCANNED
    }
}

/// The blocks of every adjacency list longer than [`INLINE`], in one array
/// of power-of-two blocks (free blocks reused per size), instead of one
/// heap allocation per vertex: a separate `Vec` would cost 24 bytes plus an
/// allocation each.
#[derive(Clone, Debug, Default)]
pub(crate) struct AdjPool {
    data: Vec<u32>,
    /// Free block starts per log2 of the block size.
    free: Vec<Vec<u32>>,
}

impl AdjPool {
    /// The list `a`.
    pub(crate) fn list<'a>(&'a self, a: &'a Adj) -> &'a [u32] {
        if a.block == 0 {
            &a.items[..a.len as usize]
        } else {
            let start = a.items[0] as usize;
            &self.data[start..start + a.len as usize]
        }
    }

    /// The list `a`, to edit.
    fn list_mut<'a>(&'a mut self, a: &'a mut Adj) -> &'a mut [u32] {
        let len = a.len as usize;
        if a.block == 0 {
            &mut a.items[..len]
        } else {
            let start = a.items[0] as usize;
            &mut self.data[start..start + len]
        }
    }

    fn push(&mut self, a: &mut Adj, id: u32) {
        if a.len == a.cap() {
            self.grow(a);
        }
        a.len += 1;
        *self.list_mut(a).last_mut().expect("just grown") = id;
    }

    fn grow(&mut self, a: &mut Adj) {
        let class = a.block.max(1) + 1;
        let cap = 1usize << class;
        let reused = self.free.get_mut(usize::from(class)).and_then(Vec::pop);
        let start = match reused {
            Some(s) => s,
            None => {
                let s = self.data.len();
                self.data.resize(s + cap, NONE);
                u32::try_from(s).expect("fewer than 2^32 adjacency entries")
            }
        };
        let len = a.len as usize;
        if a.block == 0 {
            self.data[start as usize..start as usize + len].copy_from_slice(&a.items[..len]);
        } else {
            let old = a.items[0];
            self.data.copy_within(old as usize..old as usize + len, start as usize);
            let class = usize::from(a.block);
            if self.free.len() <= class {
                self.free.resize_with(class + 1, Vec::new);
            }
            self.free[class].push(old);
        }
        a.items[0] = start;
        a.block = class;
    }

    /// Removes position `pos` as `Vec::swap_remove` does; returns the entry
    /// moved into it, if any.
    fn swap_remove(&mut self, a: &mut Adj, pos: u32) -> Option<u32> {
        let list = self.list_mut(a);
        let last = list.len() - 1;
        let moved = list[last];
        list[pos as usize] = moved;
        a.len -= 1;
        (pos < a.len).then_some(moved)
    }
}

/// The ids of `(birth, id)` pairs in birth order; births are unique and
/// below `next_birth`, and there are at most `most` pairs. Elements are
/// visited in slot (memory) order: through the index's lists they came at
/// random, a cache miss each on a large graph. When most births are alive
/// each id is placed at its birth, a sort in linear time (the array then
/// costs at most as much as sorted pairs); else the pairs are sorted.
pub(crate) fn by_birth(next_birth: u64, most: usize, pairs: impl Iterator<Item = (u64, u32)>) -> Vec<u32> {
    if next_birth <= 4 * most as u64 + 1024 {
        let mut at = vec![u32::MAX; next_birth as usize];
        for (birth, id) in pairs {
            at[birth as usize] = id;
        }
        at.retain(|&id| id != u32::MAX);
        at
    } else {
        let mut pairs: Vec<(u64, u32)> = pairs.collect();
        pairs.sort_unstable_by_key(|&(birth, _)| birth);
        pairs.into_iter().map(|(_, id)| id).collect()
    }
}

/// The attributed graph being rewritten.
#[derive(Clone, Debug)]
pub struct Graph {
    /// Shared with the grammar until a template makes a new label.
    pub(crate) labels: Arc<Interner>,
    pub(crate) attr_names: Arc<Interner>,
    pub(crate) vertices: Vec<Vertex>,
    pub(crate) edges: Vec<Edge>,
    pub(crate) adj: AdjPool,
    pub(crate) attr_sets: AttrSets,
    free_vertices: Vec<u32>,
    free_edges: Vec<u32>,
    pub(crate) vindex: Index,
    pub(crate) eindex: Index,
    pub(crate) track_generations: bool,
    next_birth: u64,
}

/// A read-only view of one vertex.
#[derive(Clone, Copy)]
pub struct VertexRef<'g> {
    g: &'g Graph,
    id: u32,
}

/// A read-only view of one edge.
#[derive(Clone, Copy)]
pub struct EdgeRef<'g> {
    g: &'g Graph,
    id: u32,
}

impl<'g> VertexRef<'g> {
    fn v(&self) -> &'g Vertex {
        &self.g.vertices[self.id as usize]
    }

    /// The vertex's slot id (stable while it lives; reused after deletion).
    pub fn id(&self) -> u32 {
        self.id
    }

    /// The label (`""` when it has none).
    pub fn label(&self) -> &'g str {
        self.g.labels.name(self.v().c.label)
    }

    /// The position (x, y).
    pub fn pos(&self) -> [f64; 2] {
        self.v().pos
    }

    /// The generation: 0 for host elements, else the match's largest + 1.
    pub fn generation(&self) -> u32 {
        self.v().c.generation
    }

    /// Number of incident edges (a self-loop counts twice).
    pub fn degree(&self) -> usize {
        self.v().adj.len as usize
    }

    /// The attributes, in the grammar's attribute order.
    pub fn attrs(&self) -> impl Iterator<Item = (&'g str, &'g Value)> + 'g {
        let g = self.g;
        g.attr_sets.get(self.v().c.attrs).iter().map(move |(a, v)| (g.attr_names.name(*a), v))
    }

    /// The value of attribute `name`.
    pub fn attr(&self, name: &str) -> Option<&'g Value> {
        self.g.attr_names.get(name).and_then(|id| self.g.attr(&self.v().c, id))
    }
}

impl<'g> EdgeRef<'g> {
    fn e(&self) -> &'g Edge {
        &self.g.edges[self.id as usize]
    }

    /// The edge's slot id.
    pub fn id(&self) -> u32 {
        self.id
    }

    /// The label (`""` when it has none).
    pub fn label(&self) -> &'g str {
        self.g.labels.name(self.e().c.label)
    }

    /// The source vertex id.
    pub fn from(&self) -> u32 {
        self.e().from
    }

    /// The target vertex id.
    pub fn to(&self) -> u32 {
        self.e().to
    }

    /// Whether the edge is directed.
    pub fn directed(&self) -> bool {
        self.e().directed
    }

    /// The generation.
    pub fn generation(&self) -> u32 {
        self.e().c.generation
    }

    /// The attributes, in the grammar's attribute order.
    pub fn attrs(&self) -> impl Iterator<Item = (&'g str, &'g Value)> + 'g {
        let g = self.g;
        g.attr_sets.get(self.e().c.attrs).iter().map(move |(a, v)| (g.attr_names.name(*a), v))
    }

    /// The value of attribute `name`.
    pub fn attr(&self, name: &str) -> Option<&'g Value> {
        self.g.attr_names.get(name).and_then(|id| self.g.attr(&self.e().c, id))
    }
}

/// The data of a new element; `attrs` (sorted by id) is copied into the
/// graph's shared lists and cleared, so the caller's buffer keeps its
/// capacity.
pub(crate) struct NewCommon<'a> {
    pub(crate) label: u32,
    pub(crate) generation: u32,
    pub(crate) attrs: NewAttrs<'a>,
}

/// The attributes of a new element.
pub(crate) enum NewAttrs<'a> {
    /// A list sorted by attribute id (emptied on use).
    List(&'a mut Vec<(u32, Value)>),
    /// A live set of the graph's (it gains a user).
    Interned(u32),
}

impl AttrSets {
    /// The id of `new` for one more user.
    fn take(&mut self, new: NewAttrs) -> u32 {
        match new {
            NewAttrs::List(list) => {
                let id = self.intern(list);
                list.clear();
                id
            }
            NewAttrs::Interned(id) => {
                self.retain(id);
                id
            }
        }
    }
}

impl Graph {
    /// An empty graph over the given name tables.
    pub(crate) fn empty(labels: Interner, attr_names: Arc<Interner>, track_generations: bool) -> Graph {
        Graph {
            labels: Arc::new(labels),
            attr_names,
            vertices: Vec::new(),
            edges: Vec::new(),
            adj: AdjPool::default(),
            attr_sets: AttrSets::new(),
            free_vertices: Vec::new(),
            free_edges: Vec::new(),
            vindex: Index::default(),
            eindex: Index::default(),
            track_generations,
            next_birth: 0,
        }
    }

    /// Room for `vertices` and `edges` more elements, when the address space
    /// allows (the arrays grow as needed otherwise).
    pub(crate) fn reserve(&mut self, vertices: usize, edges: usize) {
        let _ = self.vertices.try_reserve(vertices);
        let _ = self.edges.try_reserve(edges);
    }

    /// Becomes a copy of `host`, keeping this graph's allocations: a
    /// derivation started from a graph an earlier one returned does not
    /// allocate, and first touch, its memory again.
    pub(crate) fn reset_from(&mut self, host: &Graph) {
        let Graph {
            labels,
            attr_names,
            vertices,
            edges,
            adj,
            attr_sets,
            free_vertices,
            free_edges,
            vindex,
            eindex,
            track_generations,
            next_birth,
        } = self;
        labels.clone_from(&host.labels);
        attr_names.clone_from(&host.attr_names);
        vertices.clone_from(&host.vertices);
        edges.clone_from(&host.edges);
        adj.data.clone_from(&host.adj.data);
        adj.free.clone_from(&host.adj.free);
        attr_sets.sets.clone_from(&host.attr_sets.sets);
        attr_sets.free.clone_from(&host.attr_sets.free);
        attr_sets.by_hash.clone_from(&host.attr_sets.by_hash);
        free_vertices.clone_from(&host.free_vertices);
        free_edges.clone_from(&host.free_edges);
        vindex.reset_from(&host.vindex);
        eindex.reset_from(&host.eindex);
        *track_generations = host.track_generations;
        *next_birth = host.next_birth;
    }

    /// The generations with live elements, in order (with
    /// `track_generations`).
    pub(crate) fn live_generations(&self) -> impl Iterator<Item = u32> + '_ {
        let mut v = self.vindex.gen_all.generations().peekable();
        let mut e = self.eindex.gen_all.generations().peekable();
        std::iter::from_fn(move || {
            let next = match (v.peek(), e.peek()) {
                (Some(&a), Some(&b)) => a.min(b),
                (a, b) => *a.or(b)?,
            };
            v.next_if_eq(&next);
            e.next_if_eq(&next);
            Some(next)
        })
    }

    /// Number of live vertices.
    pub fn vertex_count(&self) -> usize {
        self.vindex.all.len()
    }

    /// Number of live edges.
    pub fn edge_count(&self) -> usize {
        self.eindex.all.len()
    }

    /// One more than the last birth given: births are `0..next_birth()`.
    pub(crate) fn next_birth(&self) -> u64 {
        self.next_birth
    }

    /// Vertices plus edges, the paper's element count.
    pub fn element_count(&self) -> usize {
        self.vertex_count() + self.edge_count()
    }

    /// The live vertices in creation order.
    pub fn vertices(&self) -> impl Iterator<Item = VertexRef<'_>> {
        let live = self.vertices.iter().enumerate().filter(|(_, v)| v.c.alive());
        let ids = by_birth(self.next_birth, self.vertex_count(), live.map(|(id, v)| (v.c.birth, id as u32)));
        ids.into_iter().map(move |id| VertexRef { g: self, id })
    }

    /// The live edges in creation order.
    pub fn edges(&self) -> impl Iterator<Item = EdgeRef<'_>> {
        self.edge_ids().into_iter().map(move |id| EdgeRef { g: self, id })
    }

    /// The live edges' slot ids in creation order.
    pub(crate) fn edge_ids(&self) -> Vec<u32> {
        let live = self.edges.iter().enumerate().filter(|(_, e)| e.c.alive());
        by_birth(self.next_birth, self.edge_count(), live.map(|(id, e)| (e.c.birth, id as u32)))
    }

    /// The vertex in slot `id`, if it is live.
    pub fn vertex(&self, id: u32) -> Option<VertexRef<'_>> {
        self.vertices.get(id as usize).filter(|v| v.c.alive()).map(|_| VertexRef { g: self, id })
    }

    /// The edge in slot `id`, if it is live.
    pub fn edge(&self, id: u32) -> Option<EdgeRef<'_>> {
        self.edges.get(id as usize).filter(|e| e.c.alive()).map(|_| EdgeRef { g: self, id })
    }

    /// The value of attribute `id` of an element.
    pub(crate) fn attr(&self, c: &Common, id: u32) -> Option<&Value> {
        self.attr_sets.get(c.attrs).iter().find(|(a, _)| *a == id).map(|(_, v)| v)
    }

    /// Sets the given attributes (sorted by id, drained) of an element,
    /// keeping its others; `buf` is scratch space.
    pub(crate) fn set_attrs(
        &mut self,
        vertex: bool,
        id: u32,
        new: &mut Vec<(u32, Value)>,
        buf: &mut Vec<(u32, Value)>,
    ) {
        if new.is_empty() {
            return;
        }
        let old = if vertex { self.vertices[id as usize].c.attrs } else { self.edges[id as usize].c.attrs };
        buf.clear();
        buf.extend_from_slice(self.attr_sets.get(old));
        for (a, val) in new.drain(..) {
            match buf.binary_search_by_key(&a, |(b, _)| *b) {
                Ok(i) => buf[i].1 = val,
                Err(i) => buf.insert(i, (a, val)),
            }
        }
        // The new list first, so an unchanged list is never freed between.
        let set = self.attr_sets.intern(buf);
        self.attr_sets.release(old);
        buf.clear();
        if vertex {
            self.vertices[id as usize].c.attrs = set;
        } else {
            self.edges[id as usize].c.attrs = set;
        }
    }

    fn take_birth(&mut self) -> u64 {
        let b = self.next_birth;
        self.next_birth += 1;
        b
    }

    /// Adds a vertex; returns its id.
    pub(crate) fn add_vertex(&mut self, pos: [f64; 2], new: NewCommon) -> u32 {
        let birth = self.take_birth();
        let id = match self.free_vertices.pop() {
            Some(id) => id,
            None => {
                self.vertices.push(Vertex { c: Common::new(), pos: [0.0; 2], adj: Adj::default() });
                self.vertices.len() as u32 - 1
            }
        };
        let attrs = self.attr_sets.take(new.attrs);
        let v = &mut self.vertices[id as usize];
        v.c.label = new.label;
        v.c.generation = new.generation;
        v.c.birth = birth;
        v.c.attrs = attrs;
        v.pos = pos;
        // A reused slot keeps its (empty) adjacency block.
        debug_assert_eq!(v.adj.len, 0);
        index_insert(&mut self.vindex, &mut v.c, id, self.track_generations);
        id
    }

    /// Adds an edge between live vertices; returns its id.
    pub(crate) fn add_edge(&mut self, from: u32, to: u32, directed: bool, new: NewCommon) -> u32 {
        let birth = self.take_birth();
        let id = match self.free_edges.pop() {
            Some(id) => id,
            None => {
                self.edges.push(Edge { c: Common::new(), from: 0, to: 0, directed: false, adj_pos: [NONE; 2] });
                self.edges.len() as u32 - 1
            }
        };
        let short = [from, to].map(|v| !self.vertices[v as usize].adj.tracked());
        let pf = self.vertices[from as usize].adj.len;
        self.adj.push(&mut self.vertices[from as usize].adj, id);
        let pt = self.vertices[to as usize].adj.len;
        self.adj.push(&mut self.vertices[to as usize].adj, id);
        if from == to {
            self.vertices[from as usize].adj.looped = true;
        }
        let attrs = self.attr_sets.take(new.attrs);
        let e = &mut self.edges[id as usize];
        e.c.label = new.label;
        e.c.generation = new.generation;
        e.c.birth = birth;
        e.c.attrs = attrs;
        e.from = from;
        e.to = to;
        e.directed = directed;
        e.adj_pos = [pf, pt];
        index_insert(&mut self.eindex, &mut e.c, id, self.track_generations);
        for (v, short) in [from, to].into_iter().zip(short) {
            // This edge made the list long: its records start keeping
            // their positions.
            if short && self.vertices[v as usize].adj.tracked() {
                self.record_positions(v);
            }
        }
        id
    }

    /// Writes every non-loop edge's position in `v`'s list into its record
    /// (self-loops' are always kept).
    fn record_positions(&mut self, v: u32) {
        let adj = self.vertices[v as usize].adj;
        for (i, &e) in self.adj.list(&adj).iter().enumerate() {
            let e = &mut self.edges[e as usize];
            if e.from != e.to {
                e.adj_pos[usize::from(e.from != v)] = i as u32;
            }
        }
    }

    /// The position of non-loop edge `id` in `v`'s list: `recorded` where
    /// the list keeps positions, else found by scanning.
    fn position(&self, v: u32, id: u32, recorded: u32) -> u32 {
        let adj = self.vertices[v as usize].adj;
        if adj.tracked() {
            return recorded;
        }
        let list = self.adj.list(&adj);
        list.iter().position(|&e| e == id).expect("a live edge is in its vertices' lists") as u32
    }

    /// Deletes a live edge.
    pub(crate) fn remove_edge(&mut self, id: u32) {
        let (from, to, [pf, pt]) = {
            let e = &self.edges[id as usize];
            debug_assert!(e.c.alive());
            (e.from, e.to, e.adj_pos)
        };
        if from == to {
            // The later position first keeps the earlier one valid.
            for pos in [pf.max(pt), pf.min(pt)] {
                self.adj_remove(from, pos);
            }
        } else {
            let (pt, pf) = (self.position(to, id, pt), self.position(from, id, pf));
            self.adj_remove(to, pt);
            self.adj_remove(from, pf);
        }
        let tg = self.track_generations;
        let edges = &mut self.edges;
        let mut c = std::mem::replace(&mut edges[id as usize].c, Common::new());
        index_remove(&mut self.eindex, &mut c, tg, |w, moved, pos| {
            *slot_of(&mut edges[moved as usize].c.slots, w) = pos;
        });
        self.attr_sets.release(c.attrs);
        c.attrs = 0;
        self.edges[id as usize].c = c;
        self.free_edges.push(id);
    }

    /// Removes position `pos` from `v`'s adjacency list, updating the
    /// position record of the edge moved into it where the list keeps
    /// positions or may hold a self-loop.
    fn adj_remove(&mut self, v: u32, pos: u32) {
        let adj = &mut self.vertices[v as usize].adj;
        let last = adj.len - 1;
        let keep = adj.tracked() || adj.looped;
        if let Some(moved) = self.adj.swap_remove(adj, pos)
            && keep
        {
            let e = &mut self.edges[moved as usize];
            // The moved entry was at `last`: a self-loop's side is the one
            // that recorded it there.
            let side = if e.from == e.to { usize::from(e.adj_pos[0] != last) } else { usize::from(e.from != v) };
            e.adj_pos[side] = pos;
        }
    }

    /// Deletes a live vertex and every edge still attached to it
    /// (single-pushout: no dangling edges).
    pub(crate) fn remove_vertex(&mut self, id: u32) {
        while let Some(&e) = self.adj.list(&self.vertices[id as usize].adj).last() {
            self.remove_edge(e);
        }
        self.vertices[id as usize].adj.looped = false;
        let tg = self.track_generations;
        let vertices = &mut self.vertices;
        let mut c = std::mem::replace(&mut vertices[id as usize].c, Common::new());
        index_remove(&mut self.vindex, &mut c, tg, |w, moved, pos| {
            *slot_of(&mut vertices[moved as usize].c.slots, w) = pos;
        });
        self.attr_sets.release(c.attrs);
        c.attrs = 0;
        self.vertices[id as usize].c = c;
        self.free_vertices.push(id);
    }

    /// Changes a live vertex's label, moving it between index sets.
    pub(crate) fn relabel_vertex(&mut self, id: u32, label: u32) {
        if self.vertices[id as usize].c.label == label {
            return;
        }
        let tg = self.track_generations;
        let vertices = &mut self.vertices;
        let mut c = std::mem::replace(&mut vertices[id as usize].c, Common::new());
        relabel(&mut self.vindex, &mut c, id, label, tg, |w, moved, pos| {
            *slot_of(&mut vertices[moved as usize].c.slots, w) = pos;
        });
        self.vertices[id as usize].c = c;
    }

    /// Changes a live edge's label, moving it between index sets.
    pub(crate) fn relabel_edge(&mut self, id: u32, label: u32) {
        if self.edges[id as usize].c.label == label {
            return;
        }
        let tg = self.track_generations;
        let edges = &mut self.edges;
        let mut c = std::mem::replace(&mut edges[id as usize].c, Common::new());
        relabel(&mut self.eindex, &mut c, id, label, tg, |w, moved, pos| {
            *slot_of(&mut edges[moved as usize].c.slots, w) = pos;
        });
        self.edges[id as usize].c = c;
    }

    /// Re-points a live edge at the same two vertices in the given order.
    pub(crate) fn orient_edge(&mut self, id: u32, from: u32, to: u32, directed: bool) {
        let e = &mut self.edges[id as usize];
        if e.from == to && e.to == from && from != to {
            e.adj_pos.swap(0, 1);
        }
        e.from = from;
        e.to = to;
        e.directed = directed;
    }

    /// The label id of `name`, interning it.
    pub(crate) fn intern_label(&mut self, name: &str) -> u32 {
        match self.labels.get(name) {
            Some(id) => id,
            None => Arc::make_mut(&mut self.labels).intern(name),
        }
    }

    /// Checks every internal invariant (tests only).
    #[cfg(test)]
    pub(crate) fn check(&self) {
        let live_v: Vec<u32> =
            (0..self.vertices.len() as u32).filter(|&i| self.vertices[i as usize].c.alive()).collect();
        let live_e: Vec<u32> = (0..self.edges.len() as u32).filter(|&i| self.edges[i as usize].c.alive()).collect();
        assert_eq!(live_v.len(), self.vindex.all.len());
        assert_eq!(live_e.len(), self.eindex.all.len());
        for &e in &live_e {
            let ed = &self.edges[e as usize];
            for (side, v) in [ed.from, ed.to].into_iter().enumerate() {
                assert!(self.vertices[v as usize].c.alive(), "edge {e} dangles");
                let adj = self.vertices[v as usize].adj;
                if adj.tracked() || ed.from == ed.to {
                    assert_eq!(self.adj.list(&adj)[ed.adj_pos[side] as usize], e);
                } else {
                    assert!(self.adj.list(&adj).contains(&e), "edge {e} is in its list");
                }
            }
        }
        for &v in &live_v {
            for &e in self.adj.list(&self.vertices[v as usize].adj) {
                assert!(self.edges[e as usize].c.alive());
            }
            let n = self.vertices[v as usize].adj.len as usize;
            let deg: usize = live_e
                .iter()
                .map(|&e| {
                    let ed = &self.edges[e as usize];
                    usize::from(ed.from == v) + usize::from(ed.to == v)
                })
                .sum();
            assert_eq!(n, deg);
        }
        for (index, elems) in [(&self.vindex, &live_v), (&self.eindex, &live_e)] {
            let common = |id: u32| {
                if std::ptr::eq(index, &self.vindex) {
                    &self.vertices[id as usize].c
                } else {
                    &self.edges[id as usize].c
                }
            };
            for &id in elems.iter() {
                let c = common(id);
                assert_eq!(index.all[c.slots.all as usize], id);
                assert_eq!(index.by_label[c.label as usize][c.slots.label as usize], id);
                if self.track_generations {
                    assert_eq!(index.gen_all.get(c.generation)[c.slots.gen_all as usize], id);
                    assert_eq!(index.gen_label[c.label as usize].get(c.generation)[c.slots.gen_label as usize], id);
                }
            }
            let labelled: usize = index.by_label.iter().map(Vec::len).sum();
            assert_eq!(labelled, elems.len());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::grown;

    fn new(label: u32, generation: u32, attrs: &mut Vec<(u32, Value)>) -> NewCommon<'_> {
        NewCommon { label, generation, attrs: NewAttrs::List(attrs) }
    }

    fn graph(track: bool) -> Graph {
        let mut labels = Interner::default();
        labels.intern("a");
        labels.intern("b");
        Graph::empty(labels, Arc::new(Interner::default()), track)
    }

    #[test]
    fn deleting_a_vertex_deletes_its_edges() {
        let mut none = Vec::new();
        for track in [false, true] {
            let mut g = graph(track);
            let v: Vec<u32> = (0..4).map(|i| g.add_vertex([i as f64, 0.0], new(1, 0, &mut none))).collect();
            g.add_edge(v[0], v[1], false, new(1, 0, &mut none));
            g.add_edge(v[1], v[2], true, new(2, 1, &mut none));
            g.add_edge(v[1], v[1], false, new(2, 1, &mut none));
            g.add_edge(v[2], v[1], false, new(1, 0, &mut none));
            let keep = g.add_edge(v[2], v[3], false, new(1, 0, &mut none));
            g.check();
            assert_eq!(g.vertex(v[1]).unwrap().degree(), 5);
            g.remove_vertex(v[1]);
            g.check();
            assert_eq!((g.vertex_count(), g.edge_count()), (3, 1));
            assert!(g.edge(keep).is_some());
            assert_eq!(g.vertex(v[2]).unwrap().degree(), 1);
            // Freed slots are reused, last freed first.
            let again = g.add_vertex([9.0, 9.0], new(2, 3, &mut none));
            assert_eq!(again, v[1]);
            g.check();
        }
    }

    #[test]
    fn equal_attribute_lists_share_one_entry_until_the_last_user_goes() {
        let mut g = graph(false);
        let text = |t: &str| Value::Text(t.into());
        let list = || vec![(1, Value::Num(0.5)), (2, text("round"))];
        let a = g.add_vertex([0.0; 2], new(1, 0, &mut list()));
        let b = g.add_vertex([1.0, 0.0], new(1, 0, &mut list()));
        let (sa, sb) = (g.vertices[a as usize].c.attrs, g.vertices[b as usize].c.attrs);
        assert_eq!(sa, sb);
        assert_eq!(g.vertex(b).unwrap().attr("missing"), None);
        // 0.0 and -0.0 compare equal but print differently: not shared.
        let z = g.add_vertex([0.0; 2], new(1, 0, &mut vec![(1, Value::Num(0.0))]));
        let nz = g.add_vertex([0.0; 2], new(1, 0, &mut vec![(1, Value::Num(-0.0))]));
        assert_ne!(g.vertices[z as usize].c.attrs, g.vertices[nz as usize].c.attrs);
        // Changing one element's list leaves the other's alone.
        let mut buf = Vec::new();
        g.set_attrs(true, a, &mut vec![(2, text("square"))], &mut buf);
        assert_eq!(g.attr_sets.get(g.vertices[b as usize].c.attrs), list().as_slice());
        assert_eq!(g.attr_sets.get(g.vertices[a as usize].c.attrs), [(1, Value::Num(0.5)), (2, text("square"))]);
        // The last user of a list frees it; its id is reused.
        g.remove_vertex(b);
        assert!(g.attr_sets.get(sb).is_empty());
        let c = g.add_vertex([0.0; 2], new(1, 0, &mut vec![(3, text("x"))]));
        assert_eq!(g.vertices[c as usize].c.attrs, sb);
        g.check();
    }

    #[test]
    fn adjacency_blocks_grow_and_are_reused() {
        let mut none = Vec::new();
        let mut g = graph(false);
        // A vertex of degree two keeps its list in its record.
        let (a, b) = (g.add_vertex([0.0; 2], new(1, 0, &mut none)), g.add_vertex([0.0; 2], new(1, 0, &mut none)));
        g.add_edge(a, b, true, new(1, 0, &mut none));
        g.add_edge(b, a, true, new(1, 0, &mut none));
        assert!(g.adj.data.is_empty());
        // Four self-loops: 8 entries, the hub's list grows 2 (inline) → 4 → 8.
        let hub = g.add_vertex([0.0; 2], new(1, 0, &mut none));
        let loops: Vec<u32> = (0..4).map(|_| g.add_edge(hub, hub, false, new(1, 0, &mut none))).collect();
        g.check();
        assert_eq!(g.vertex(hub).unwrap().degree(), 8);
        assert_eq!(g.adj.data.len(), 4 + 8);
        g.remove_edge(loops[1]);
        g.check();
        // Its outgrown block of 4 went to the free lists: a new vertex with
        // 4 entries takes it instead of growing the pool.
        let x = g.add_vertex([0.0; 2], new(1, 0, &mut none));
        g.add_edge(x, x, false, new(1, 0, &mut none));
        g.add_edge(x, x, false, new(1, 0, &mut none));
        g.check();
        assert_eq!(g.adj.data.len(), 4 + 8);
        assert_eq!(g.vertex(x).unwrap().degree(), 4);
        // A removed vertex's slot is reused with its (empty) block.
        g.remove_vertex(hub);
        let y = g.add_vertex([0.0; 2], new(1, 0, &mut none));
        assert_eq!(y, hub);
        for _ in 0..5 {
            g.add_edge(y, a, false, new(1, 0, &mut none));
        }
        g.check();
        // y kept the hub's block of 8; a's list left its record for a new
        // block of 4, then a new one of 8.
        assert_eq!(g.vertices[y as usize].adj.block, 3);
        assert_eq!(g.adj.data.len(), 4 + 8 + 4 + 8);
    }

    /// Adjacency lists as plain vectors, edited as the graph's are meant to
    /// be: a push per endpoint, and a swap-remove at the edge's exact
    /// position (a self-loop's later occurrence first).
    fn model_remove(lists: &mut [Vec<u32>], (from, to): (u32, u32), e: u32) {
        for v in if from == to { vec![from, from] } else { vec![to, from] } {
            let list = &mut lists[v as usize];
            let at = list.iter().rposition(|&x| x == e).unwrap();
            list.swap_remove(at);
        }
    }

    #[test]
    fn short_and_long_adjacency_lists_keep_the_order_of_exact_positions() {
        let mut none = Vec::new();
        let mut rng = genform_core::Rng::from_seed(5);
        let mut g = graph(false);
        // Few vertices and many edges: lists grow past the scanned size and
        // shrink back, with self-loops and parallel edges among them.
        let vs: Vec<u32> = (0..5).map(|_| g.add_vertex([0.0; 2], new(1, 0, &mut none))).collect();
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); 5];
        // Each edge's (from, to), by id.
        let mut ends: Vec<(u32, u32)> = Vec::new();
        let mut long = 0;
        for step in 0..4000 {
            let grow = if step % 1000 < 600 { 3 } else { 1 };
            if rng.index(4) < grow {
                let (a, b) = (vs[rng.index(5)], vs[if rng.bernoulli(0.15) { 0 } else { rng.index(5) }]);
                let e = g.add_edge(a, b, true, new(1, 0, &mut none));
                lists[a as usize].push(e);
                lists[b as usize].push(e);
                *grown(&mut ends, e as usize) = (a, b);
            } else if g.edge_count() > 0 {
                let e = g.eindex.all[rng.index(g.edge_count())];
                let (a, b) = ends[e as usize];
                if rng.bernoulli(0.2) {
                    g.orient_edge(e, b, a, true);
                    ends[e as usize] = (b, a);
                } else {
                    g.remove_edge(e);
                    model_remove(&mut lists, (a, b), e);
                }
            }
            g.check();
            for &v in &vs {
                assert_eq!(g.adj.list(&g.vertices[v as usize].adj), lists[v as usize].as_slice(), "step {step}");
            }
            long += usize::from(vs.iter().any(|&v| g.vertices[v as usize].adj.tracked()));
        }
        assert!(long > 1000, "long lists were exercised ({long} steps)");
        // Removing a vertex removes its edges, last listed first.
        g.remove_vertex(vs[0]);
        while let Some(&e) = lists[0].last() {
            model_remove(&mut lists, ends[e as usize], e);
        }
        g.check();
        for &v in &vs[1..] {
            assert_eq!(g.adj.list(&g.vertices[v as usize].adj), lists[v as usize].as_slice());
        }
    }

    #[test]
    fn random_edits_keep_every_index_consistent() {
        let mut none = Vec::new();
        let mut rng = genform_core::Rng::from_seed(11);
        let mut g = graph(true);
        for _ in 0..2000 {
            let nv = g.vertex_count();
            match rng.index(6) {
                0 | 1 => {
                    g.add_vertex([0.0; 2], new(rng.index(3) as u32, rng.index(4) as u32, &mut none));
                }
                2 | 3 if nv > 0 => {
                    let a = g.vindex.all[rng.index(nv)];
                    let b = g.vindex.all[rng.index(nv)];
                    g.add_edge(a, b, rng.bernoulli(0.5), new(rng.index(3) as u32, rng.index(4) as u32, &mut none));
                }
                4 if g.edge_count() > 0 => {
                    let e = g.eindex.all[rng.index(g.edge_count())];
                    if rng.bernoulli(0.5) {
                        g.remove_edge(e);
                    } else {
                        g.relabel_edge(e, rng.index(3) as u32);
                        let (f, t) = (g.edges[e as usize].from, g.edges[e as usize].to);
                        g.orient_edge(e, t, f, true);
                    }
                }
                5 if nv > 0 => {
                    let v = g.vindex.all[rng.index(nv)];
                    if rng.bernoulli(0.5) {
                        g.remove_vertex(v);
                    } else {
                        g.relabel_vertex(v, rng.index(3) as u32);
                    }
                }
                _ => {}
            }
            g.check();
        }
        let counted: usize = [&g.vindex, &g.eindex]
            .iter()
            .flat_map(|index| index.gen_all.generations().map(|g| index.gen_all.get(g).len()))
            .sum();
        assert_eq!(counted, g.element_count());
        let live: Vec<u32> = g.live_generations().collect();
        let mut expected: Vec<u32> = g.vindex.gen_all.generations().chain(g.eindex.gen_all.generations()).collect();
        expected.sort_unstable();
        expected.dedup();
        assert_eq!(live, expected);
    }
}
