//! Box-split grammars (`.bsg`) with observer rules and backtracking.
//!
//! A box-split grammar (Eger, FDG 2022) refines an axis-aligned box of a
//! block world: rules split scopes into labelled sub-boxes, reorient them,
//! and fill them with blocks, weighted mixes or air. Observer constraints
//! (Baron & Eger 2023) let alternatives look at the pre-existing world in
//! their box — `FULL(SOLID)`, `NONEMPTY(LIQUID)`, `EMPTY(group)` — and
//! backtracking recovers when a choice leads to a rule that cannot apply.
//!
//! - [`compile`] reads a `.bsg` file (every error at once, with positions).
//! - [`BoxGrammar::derive`] derives it in a box, observing a [`BlockGrid`],
//!   with every random choice drawn through core's
//!   [`Draws`](genform_core::rng::Draws); the result is a
//!   grid of the blocks placed, written only after the derivation
//!   succeeded, with an optional JSON [`Trace`].
//! - [`split::split_lengths`] is the split arithmetic on its own.
//!
//! The language is documented in `docs/box-split.md`.
//!
//! ```
//! use genform_core::{Rng, SourceFile};
//! use genform_boxsplit::{DeriveOptions, compile};
//! use glam::IVec3;
//! let src = "axiom Slab;\nSlab { split y [1, -1] { fill stone, void } }\n";
//! let (grammar, _warnings) = compile(&SourceFile::new("slab.bsg", src)).unwrap();
//! let d = grammar
//!     .derive(None, IVec3::ZERO, IVec3::new(4, 3, 4), &mut Rng::from_seed(1), &DeriveOptions::default())
//!     .unwrap();
//! assert_eq!(d.blocks.get(IVec3::new(2, 0, 2)).unwrap().id(), "stone");
//! assert_eq!(d.blocks.get(IVec3::new(2, 1, 2)).unwrap().id(), "air");
//! assert_eq!(d.stats.filled, 48);
//! ```

mod compile;
mod connect;
mod derive;
mod dialect;
mod formula;
mod grammar;
mod known_blocks;
mod lex;
mod observe;
mod site;
pub mod split;
mod support;
mod syntax;
mod trace;

pub use compile::compile;
pub use derive::{
    Derivation, DeriveFailure, DeriveOptions, DeriveStats, FailureKind, FailurePoint, MAX_VOLUME, SiteReport,
};
pub use grammar::{BoxGrammar, DeriveLimits};
pub use split::Round;
pub use trace::{Trace, TraceEvent, TraceScope};

pub use genform_core::BlockGrid;
