//! Where the rasterizers' held spans go: the scratch's rows, the tallies
//! in and outside the grid and, when caching, the span record.

use super::scratch::VolumeScratch;
use crate::grid::Lattice;
use crate::span_cache::Span;

/// Per-instance tallies of held voxels in and outside the grid.
#[derive(Default)]
pub(super) struct Tally {
    pub(super) in_grid: u64,
    pub(super) outside: u64,
}

/// Where an instance's spans go.
pub(super) struct Out<'a> {
    pub(super) s: &'a mut VolumeScratch,
    pub(super) tally: &'a mut Tally,
    pub(super) target: &'a [u64],
    /// Where the marked spans are recorded too, if they are.
    pub(super) record: Option<&'a mut Vec<Span>>,
}

/// Adds the held span `lo..=hi` of lattice row `(j, k)`.
#[inline(always)]
pub(super) fn emit(lat: &Lattice, out: &mut Out, j: i64, k: i64, lo: i64, hi: i64) {
    let len = (hi - lo + 1) as u64;
    match lat.row(j, k) {
        Some(r) => {
            let (a, b) = (lo.max(0), hi.min(lat.dims[0] - 1));
            if a <= b {
                out.s.write(r, a as usize, b as usize, out.target);
                if let Some(rec) = &mut out.record {
                    rec.push((r as u32, a as u32, b as u32));
                }
                let n = (b - a + 1) as u64;
                out.tally.in_grid += n;
                out.tally.outside += len - n;
            } else {
                out.tally.outside += len;
            }
        }
        None => out.tally.outside += len,
    }
}
