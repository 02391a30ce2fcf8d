//! Footprints: building lots given by a file instead of by `lot(…)`.
//!
//! A grammar can declare `footprints "lots.geojson";` (or a door can pass
//! a file): each polygon is then one lot, and the grammar is derived once
//! per lot, its axiom starting on the lot as if it began with
//! `lot(x0, z0, x1, z1, …)` at the world origin ([`ShapeGrammar::on_footprint`]).
//! Reading the file is the door's job ([`crate::AssetResolver::load_footprints`]);
//! this module checks what it read.

use crate::geom;
use crate::grammar::ShapeGrammar;
use crate::polygon::area2;
use glam::DVec2;
use std::sync::Arc;

pub use crate::lot_props::LotProps;

/// One lot of a footprint file.
#[derive(Clone, Debug)]
pub struct FootprintLot {
    /// World `(x, z)` corners, either winding.
    pub corners: Vec<[f64; 2]>,
    /// Its name in messages (`feature 12 ("way/123")`).
    pub label: String,
    /// What the file says of it.
    pub props: LotProps,
}

impl FootprintLot {
    /// The `k`-th (from 0) lot of a file that says nothing of its lots but
    /// their corners: named `"{kind} {k + 1}"` in messages, `lot.index` k.
    pub fn numbered(k: usize, kind: &str, corners: Vec<[f64; 2]>) -> FootprintLot {
        FootprintLot {
            corners,
            label: format!("{kind} {}", k + 1),
            props: LotProps { index: k as f64, ..LotProps::default() },
        }
    }
}

/// The lots of a footprint file.
#[derive(Clone, Debug, Default)]
pub struct FootprintSet {
    /// The lots, in file order.
    pub lots: Vec<FootprintLot>,
    /// Where the world origin lies in the file's coordinates, when the
    /// reader moved it (projected or far-off footprints).
    pub origin: Option<String>,
    /// The lots left out, each with why.
    pub skipped: Vec<String>,
}

/// Most corners of one footprint (as for `lot`).
pub const MAX_CORNERS: usize = 1024;

/// Whether `p` (at least 3 points) is a simple polygon with an area.
pub(crate) fn is_valid_outline(p: &[DVec2]) -> bool {
    p.len() >= 3 && geom::is_simple(p) && area2(p) != 0.0
}

/// Checks one footprint given as world `(x, z)` corners and turns it into
/// the outline a lot holds (`(x, −z)`, any winding).
pub(crate) fn outline(corners: &[[f64; 2]]) -> Result<Arc<[DVec2]>, String> {
    if corners.len() < 3 || corners.len() > MAX_CORNERS {
        return Err(format!("has {} corners (3 to {MAX_CORNERS} are allowed)", corners.len()));
    }
    if corners.iter().flatten().any(|v| !v.is_finite() || v.abs() > 1e9) {
        return Err("has a corner that is not a finite coordinate within ±10⁹".into());
    }
    let p: Vec<DVec2> = corners.iter().map(|&[x, z]| DVec2::new(x, -z)).collect();
    if !is_valid_outline(&p) {
        return Err("crosses itself, repeats a corner or has no area".into());
    }
    Ok(p.into())
}

impl ShapeGrammar {
    /// The footprints the grammar declares (`footprints "…";`), in file
    /// order; empty when it declares none.
    pub fn footprints(&self) -> &[Arc<[DVec2]>] {
        &self.footprints
    }

    /// The grammar set on the footprint with world `(x, z)` corners (either
    /// winding): sampling and expressing start on that lot. An invalid
    /// footprint is an error saying why.
    pub fn on_footprint(&self, corners: &[[f64; 2]]) -> Result<ShapeGrammar, String> {
        self.on_footprint_with(corners, LotProps::default())
    }

    /// [`ShapeGrammar::on_footprint`] with the lot's properties, which its
    /// rules read as `lot.height`, `lot.levels`, ….
    pub fn on_footprint_with(&self, corners: &[[f64; 2]], props: LotProps) -> Result<ShapeGrammar, String> {
        let lot = outline(corners)?;
        Ok(ShapeGrammar { start_lot: Some(lot), start_props: props, ..self.clone() })
    }

    /// The grammar set on its `k`-th declared footprint.
    pub fn on_declared_footprint(&self, k: usize) -> Option<ShapeGrammar> {
        let lot = self.footprints.get(k)?.clone();
        let props = self.footprint_props.get(k).copied().unwrap_or_default();
        Some(ShapeGrammar { start_lot: Some(lot), start_props: props, ..self.clone() })
    }

    /// Where the world origin of the declared footprints lies in their
    /// file's coordinates, when the reader moved it.
    pub fn footprint_origin(&self) -> Option<&str> {
        self.footprint_origin.as_deref()
    }
}
