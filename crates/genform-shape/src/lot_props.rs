//! What a footprint file says of a lot, readable in the grammar as
//! `lot.*` (a file of its own: the grammar keeps the start lot's, and the
//! footprint reader makes them).

/// What a footprint file says of one lot, read in a grammar as `lot.height`,
/// `lot.min_height`, `lot.levels`, `lot.use` and `lot.index` (0 where the
/// file says nothing, and in runs on no footprint).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LotProps {
    /// Height in metres (OSM `height`).
    pub height: f64,
    /// Height of the lowest floor's bottom in metres (OSM `min_height`).
    pub min_height: f64,
    /// Storeys above ground (OSM `building:levels`).
    pub levels: f64,
    /// Use class of OSM `building`: 0 unknown or `yes`, 1 residential, 2
    /// commercial, 3 industrial, 4 civic, 5 outbuilding.
    pub use_class: f64,
    /// The lot's number in its file (features from 0).
    pub index: f64,
}

impl LotProps {
    /// The values in the env order of the `lot.*` built-ins.
    pub(crate) fn to_array(self) -> [f64; 5] {
        [self.height, self.min_height, self.levels, self.use_class, self.index]
    }
}
