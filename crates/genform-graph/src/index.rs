//! Candidate indexes: swap-remove sets of element ids — all live elements,
//! per label, and (for "oldest" matching) per label and generation. Each
//! element stores its position in every set it belongs to, so inserting,
//! removing and relabelling are O(1) (generation buckets: O(log buckets)).

use crate::graph::Common;
use std::collections::BTreeMap;

/// "No position": the marker of an element absent from an index set.
pub(crate) const NONE: u32 = u32::MAX;

/// Positions of one element in the index sets it belongs to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slots {
    pub(crate) all: u32,
    pub(crate) label: u32,
    pub(crate) gen_all: u32,
    pub(crate) gen_label: u32,
}

impl Slots {
    pub(crate) const EMPTY: Slots = Slots { all: NONE, label: NONE, gen_all: NONE, gen_label: NONE };
}

/// Swap-remove sets of element ids: all live elements, per label, and
/// (optionally) per generation.
#[derive(Clone, Debug, Default)]
pub(crate) struct Index {
    pub(crate) all: Vec<u32>,
    pub(crate) by_label: Vec<Vec<u32>>,
    pub(crate) gen_all: BTreeMap<u32, Vec<u32>>,
    pub(crate) gen_label: Vec<BTreeMap<u32, Vec<u32>>>,
    /// Emptied generation buckets, kept (cleared) for the next new one: a
    /// new generation grows while an old one empties, and without the pool
    /// the one's memory went back to the allocator while the other's was
    /// allocated and first touched afresh.
    spare: Vec<Vec<u32>>,
}

impl Index {
    /// Becomes a copy of `other`, reusing this index's allocations.
    pub(crate) fn reset_from(&mut self, other: &Index) {
        self.all.clone_from(&other.all);
        self.by_label.clone_from(&other.by_label);
        let spare = &mut self.spare;
        let mut refill = |mine: &mut BTreeMap<u32, Vec<u32>>, theirs: &BTreeMap<u32, Vec<u32>>| {
            for (_, mut set) in std::mem::take(mine) {
                set.clear();
                spare.push(set);
            }
            for (&g, set) in theirs {
                let mut copy = spare.pop().unwrap_or_default();
                copy.extend_from_slice(set);
                mine.insert(g, copy);
            }
        };
        refill(&mut self.gen_all, &other.gen_all);
        self.gen_label.resize_with(self.gen_label.len().max(other.gen_label.len()), BTreeMap::new);
        for (l, mine) in self.gen_label.iter_mut().enumerate() {
            refill(mine, other.gen_label.get(l).unwrap_or(&BTreeMap::new()));
        }
        self.gen_label.truncate(other.gen_label.len());
    }
}

/// The bucket of generation `g`, made (from a spare allocation if any) when
/// missing.
fn bucket<'a>(buckets: &'a mut BTreeMap<u32, Vec<u32>>, g: u32, spare: &mut Vec<Vec<u32>>) -> &'a mut Vec<u32> {
    buckets.entry(g).or_insert_with(|| spare.pop().unwrap_or_default())
}

/// Which of an element's index positions a set uses.
#[derive(Clone, Copy)]
pub(crate) enum Which {
    All,
    Label,
    GenAll,
    GenLabel,
}

pub(crate) fn slot_of(s: &mut Slots, w: Which) -> &mut u32 {
    match w {
        Which::All => &mut s.all,
        Which::Label => &mut s.label,
        Which::GenAll => &mut s.gen_all,
        Which::GenLabel => &mut s.gen_label,
    }
}

fn set_insert(set: &mut Vec<u32>, id: u32, slots: &mut Slots, w: Which) {
    *slot_of(slots, w) = set.len() as u32;
    set.push(id);
}

/// Removes `id` (at `slots`' position) from `set`; the element moved into
/// its place gets its position updated through `moved`.
fn set_remove(set: &mut Vec<u32>, slots: &mut Slots, w: Which, mut moved: impl FnMut(u32, u32)) {
    let pos = std::mem::replace(slot_of(slots, w), NONE);
    let last = set.pop().expect("an indexed element is in its set");
    if (pos as usize) < set.len() {
        set[pos as usize] = last;
        moved(last, pos);
    }
}

pub(crate) fn index_insert(
    index: &mut Index,
    c: &mut Common,
    id: u32,
    track: bool,
    generations: &mut BTreeMap<u32, u32>,
) {
    let label = c.label as usize;
    if index.by_label.len() <= label {
        index.by_label.resize_with(label + 1, Vec::new);
    }
    set_insert(&mut index.all, id, &mut c.slots, Which::All);
    set_insert(&mut index.by_label[label], id, &mut c.slots, Which::Label);
    if track {
        if index.gen_label.len() <= label {
            index.gen_label.resize_with(label + 1, BTreeMap::new);
        }
        let g = c.generation;
        set_insert(bucket(&mut index.gen_all, g, &mut index.spare), id, &mut c.slots, Which::GenAll);
        set_insert(bucket(&mut index.gen_label[label], g, &mut index.spare), id, &mut c.slots, Which::GenLabel);
        *generations.entry(c.generation).or_default() += 1;
    }
}

pub(crate) fn index_remove(
    index: &mut Index,
    c: &mut Common,
    track: bool,
    generations: &mut BTreeMap<u32, u32>,
    mut moved: impl FnMut(Which, u32, u32),
) {
    let label = c.label as usize;
    set_remove(&mut index.all, &mut c.slots, Which::All, |m, p| moved(Which::All, m, p));
    set_remove(&mut index.by_label[label], &mut c.slots, Which::Label, |m, p| moved(Which::Label, m, p));
    if track {
        let g = c.generation;
        remove_from_bucket(&mut index.gen_all, g, &mut index.spare, &mut c.slots, Which::GenAll, &mut moved);
        remove_from_bucket(&mut index.gen_label[label], g, &mut index.spare, &mut c.slots, Which::GenLabel, &mut moved);
        if let Some(n) = generations.get_mut(&g) {
            *n -= 1;
            if *n == 0 {
                generations.remove(&g);
            }
        }
    }
}

/// Removes from a generation bucket, moving the bucket to `spare` when it
/// empties so that range scans only meet live generations.
fn remove_from_bucket(
    buckets: &mut BTreeMap<u32, Vec<u32>>,
    g: u32,
    spare: &mut Vec<Vec<u32>>,
    slots: &mut Slots,
    w: Which,
    moved: &mut impl FnMut(Which, u32, u32),
) {
    let set = buckets.get_mut(&g).expect("an element is in its generation bucket");
    set_remove(set, slots, w, |m, p| moved(w, m, p));
    if set.is_empty() {
        spare.extend(buckets.remove(&g));
    }
}

pub(crate) fn relabel(
    index: &mut Index,
    c: &mut Common,
    id: u32,
    label: u32,
    track: bool,
    mut moved: impl FnMut(Which, u32, u32),
) {
    let old = c.label as usize;
    set_remove(&mut index.by_label[old], &mut c.slots, Which::Label, |m, p| moved(Which::Label, m, p));
    if track {
        remove_from_bucket(
            &mut index.gen_label[old],
            c.generation,
            &mut index.spare,
            &mut c.slots,
            Which::GenLabel,
            &mut moved,
        );
    }
    c.label = label;
    let l = label as usize;
    if index.by_label.len() <= l {
        index.by_label.resize_with(l + 1, Vec::new);
    }
    set_insert(&mut index.by_label[l], id, &mut c.slots, Which::Label);
    if track {
        if index.gen_label.len() <= l {
            index.gen_label.resize_with(l + 1, BTreeMap::new);
        }
        set_insert(bucket(&mut index.gen_label[l], c.generation, &mut index.spare), id, &mut c.slots, Which::GenLabel);
    }
}
