//! What each vertex and edge stores about itself: its label, generation,
//! birth, attribute list and its positions in the candidate indexes. Below
//! both the graph and the indexes, which read and update it.

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

/// What vertices and edges share. An element is live while it is in the
/// index of all live elements (`slots.all` is set).
#[derive(Clone, Debug)]
pub(crate) struct Common {
    pub(crate) label: u32,
    pub(crate) generation: u32,
    /// Creation order, for drawing and writing in a stable order.
    pub(crate) birth: u64,
    /// The element's attribute list, an id in [`AttrSets`](crate::graph::AttrSets) (0: none).
    pub(crate) attrs: u32,
    pub(crate) slots: Slots,
}

impl Common {
    pub(crate) fn new() -> Common {
        Common { label: 0, generation: 0, birth: 0, attrs: 0, slots: Slots::EMPTY }
    }

    /// Whether the element is live.
    pub(crate) fn alive(&self) -> bool {
        self.slots.all != NONE
    }
}
