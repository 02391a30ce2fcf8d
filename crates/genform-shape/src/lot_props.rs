//! What a footprint file says of a lot, readable in the grammar as
//! `lot.*` (a file of its own: the grammar keeps the start lot's, and the
//! footprint reader makes them).

/// What a footprint file says of one lot, read in a grammar as `lot.height`,
/// `lot.min_height`, `lot.levels`, `lot.use`, `lot.index`, `lot.street` and
/// `lot.street_edge` (0 where the file says nothing, and in runs on no
/// footprint; the street values −1 where no street was given or none is
/// near).
#[derive(Clone, Copy, Debug, PartialEq)]
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
    /// How far (metres) the street its street edge faces lies, along that
    /// edge's outward normal from its middle; −1 when none is known.
    pub street: f64,
    /// The edge that faces the street (edge `i` from corner `i` to `i + 1`
    /// as the file lists them), −1 when none: a lot started on it turns so
    /// that this edge is its `front`.
    pub street_edge: f64,
}

impl LotProps {
    /// How many `lot.*` built-ins there are.
    pub(crate) const COUNT: usize = 7;

    /// The values in the env order of the `lot.*` built-ins.
    pub(crate) fn to_array(self) -> [f64; Self::COUNT] {
        [self.height, self.min_height, self.levels, self.use_class, self.index, self.street, self.street_edge]
    }
}

impl Default for LotProps {
    fn default() -> Self {
        LotProps {
            height: 0.0,
            min_height: 0.0,
            levels: 0.0,
            use_class: 0.0,
            index: 0.0,
            street: -1.0,
            street_edge: -1.0,
        }
    }
}
