//! Candidate indexes: swap-remove sets of element ids — all live elements,
//! per label, and (for "oldest" matching) per label and generation. Each
//! element stores its position in every set it belongs to, so inserting,
//! removing and relabelling are O(1) (generation sets: O(1) for the two
//! generations met last, else O(log generations)).

use crate::element::{Common, NONE, Slots};
use crate::table::grown;
use std::collections::BTreeMap;

/// Swap-remove sets of element ids: all live elements, per label, and
/// (optionally) per generation.
#[derive(Clone, Debug, Default)]
pub(crate) struct Index {
    pub(crate) all: Vec<u32>,
    pub(crate) by_label: Vec<Vec<u32>>,
    pub(crate) gen_all: GenSets,
    pub(crate) gen_label: Vec<GenSets>,
}

impl Index {
    /// Becomes a copy of `other`, reusing this index's allocations.
    pub(crate) fn reset_from(&mut self, other: &Index) {
        self.all.clone_from(&other.all);
        self.by_label.clone_from(&other.by_label);
        self.gen_all.clone_from(&other.gen_all);
        self.gen_label.clone_from(&other.gen_label);
    }
}

/// One swap-remove set per generation with live elements. A step adds to
/// the newest generation and ("oldest" matching) takes from the oldest, so
/// the two generations met last are remembered in front of the ordered
/// map. Emptied sets are kept (cleared) for the next new generation: a new
/// generation grows while an old one empties, and without them the one's
/// memory went back to the allocator while the other's was allocated and
/// first touched afresh.
#[derive(Debug)]
pub(crate) struct GenSets {
    /// Generation → its set in `sets`.
    map: BTreeMap<u32, u32>,
    sets: Vec<Vec<u32>>,
    /// Entries of `sets` no generation uses (empty).
    free: Vec<u32>,
    /// (generation, set) of the two generations met last; `NONE` for none.
    recent: [(u32, u32); 2],
}

impl Default for GenSets {
    fn default() -> GenSets {
        GenSets { map: BTreeMap::new(), sets: Vec::new(), free: Vec::new(), recent: [(NONE, NONE); 2] }
    }
}

impl Clone for GenSets {
    fn clone(&self) -> GenSets {
        let mut copy = GenSets::default();
        copy.clone_from(self);
        copy
    }

    /// Keeps this one's sets' allocations (a derivation reusing a graph).
    fn clone_from(&mut self, other: &GenSets) {
        self.map.clone_from(&other.map);
        self.sets.clone_from(&other.sets);
        self.free.clone_from(&other.free);
        self.recent = other.recent;
    }
}

impl GenSets {
    /// The set of generation `g`, if it has live elements.
    fn find(&mut self, g: u32) -> Option<u32> {
        match self.recent {
            [(r, set), _] if r == g && set != NONE => Some(set),
            [first, (r, set)] if r == g && set != NONE => {
                self.recent = [(r, set), first];
                Some(set)
            }
            _ => {
                let set = *self.map.get(&g)?;
                self.recent = [(g, set), self.recent[0]];
                Some(set)
            }
        }
    }

    /// Generation `g`'s elements.
    #[cfg(test)]
    pub(crate) fn get(&self, g: u32) -> &[u32] {
        self.map.get(&g).map_or(&[], |&set| &self.sets[set as usize])
    }

    /// The generations with live elements, in order.
    pub(crate) fn generations(&self) -> impl Iterator<Item = u32> + '_ {
        self.map.keys().copied()
    }

    /// The sets of the generations up to `max`, in order.
    pub(crate) fn up_to(&self, max: u32) -> impl Iterator<Item = &[u32]> + '_ {
        self.map.range(..=max).map(|(_, &set)| self.sets[set as usize].as_slice())
    }

    fn insert(&mut self, g: u32, id: u32, slots: &mut Slots, w: Which) {
        let set = match self.find(g) {
            Some(set) => set,
            None => {
                let set = self.free.pop().unwrap_or_else(|| {
                    self.sets.push(Vec::new());
                    u32::try_from(self.sets.len() - 1).expect("fewer than 2^32 generations")
                });
                self.map.insert(g, set);
                self.recent = [(g, set), self.recent[0]];
                set
            }
        };
        set_insert(&mut self.sets[set as usize], id, slots, w);
    }

    /// Removes an element of generation `g`, releasing the generation's
    /// set when it empties so that range scans only meet live generations.
    fn remove(&mut self, g: u32, slots: &mut Slots, w: Which, moved: &mut impl FnMut(Which, u32, u32)) {
        let set = self.find(g).expect("an element is in its generation's set");
        set_remove(&mut self.sets[set as usize], slots, w, |m, p| moved(w, m, p));
        if self.sets[set as usize].is_empty() {
            self.map.remove(&g);
            self.free.push(set);
            let [a, b] = self.recent.map(|r| if r.0 == g { (NONE, NONE) } else { r });
            self.recent = if a.0 == NONE { [b, a] } else { [a, b] };
        }
    }
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

pub(crate) fn index_insert(index: &mut Index, c: &mut Common, id: u32, track: bool) {
    let label = c.label as usize;
    set_insert(&mut index.all, id, &mut c.slots, Which::All);
    set_insert(grown(&mut index.by_label, label), id, &mut c.slots, Which::Label);
    if track {
        let g = c.generation;
        index.gen_all.insert(g, id, &mut c.slots, Which::GenAll);
        grown(&mut index.gen_label, label).insert(g, id, &mut c.slots, Which::GenLabel);
    }
}

pub(crate) fn index_remove(index: &mut Index, c: &mut Common, track: bool, mut moved: impl FnMut(Which, u32, u32)) {
    let label = c.label as usize;
    set_remove(&mut index.all, &mut c.slots, Which::All, |m, p| moved(Which::All, m, p));
    set_remove(&mut index.by_label[label], &mut c.slots, Which::Label, |m, p| moved(Which::Label, m, p));
    if track {
        let g = c.generation;
        index.gen_all.remove(g, &mut c.slots, Which::GenAll, &mut moved);
        index.gen_label[label].remove(g, &mut c.slots, Which::GenLabel, &mut moved);
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
        index.gen_label[old].remove(c.generation, &mut c.slots, Which::GenLabel, &mut moved);
    }
    c.label = label;
    let l = label as usize;
    set_insert(grown(&mut index.by_label, l), id, &mut c.slots, Which::Label);
    if track {
        grown(&mut index.gen_label, l).insert(c.generation, id, &mut c.slots, Which::GenLabel);
    }
}
