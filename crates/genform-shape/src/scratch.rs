//! Per-thread scratch buffers, so that repeated runs allocate nothing.
//!
//! [`Generator::express`](genform_core::Generator::express) takes `&self`
//! and optimizers call it from several threads at once, tens of thousands
//! of times a second. One set of buffers per thread needs no locking and
//! keeps the trait unchanged. A run takes the thread's set out of the
//! thread-local and puts it back when done, so a nested run (or one on a
//! thread being torn down) simply starts from fresh buffers.

use crate::interp::Stacks;
use std::cell::Cell;

/// Buffers larger than this (bytes) are freed after a run, so one huge
/// derivation does not pin its memory for the thread's lifetime.
const KEEP_BYTES: usize = 4 << 20;

/// The reusable buffers of one thread.
#[derive(Default)]
pub(crate) struct Scratch {
    /// The interpreter's stacks.
    pub stacks: Stacks,
    /// Expression: grammar tag → scene tag.
    pub tags: Vec<u32>,
    /// Expression: grammar mesh → scene mesh.
    pub meshes: Vec<u32>,
    /// Genome check: which words start a gene.
    pub starts: Vec<bool>,
}

impl Scratch {
    fn capacity_bytes(&self) -> usize {
        self.stacks.capacity_bytes() + (self.tags.capacity() + self.meshes.capacity()) * 4 + self.starts.capacity()
    }
}

thread_local! {
    static SCRATCH: Cell<Scratch> = Cell::new(Scratch::default());
}

/// Runs `f` with this thread's scratch buffers.
pub(crate) fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    let mut scratch = SCRATCH.try_with(Cell::take).unwrap_or_default();
    let r = f(&mut scratch);
    if scratch.capacity_bytes() <= KEEP_BYTES {
        // Fails only while the thread is being torn down: then drop them.
        let _ = SCRATCH.try_with(|c| c.set(scratch));
    }
    r
}
