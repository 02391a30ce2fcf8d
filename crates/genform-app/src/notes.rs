//! Warnings the application has for the user outside a run (a grammar's
//! compile warnings, a truncated sample, missing terrain regions), handed
//! to the front door that installed a sink: the command line prints them on
//! stderr, Python hands them to its own stderr. Without a sink they are
//! dropped: the library itself never prints. (Inside a run, notes go to
//! the run's [`crate::run::Watch`].)

use std::sync::OnceLock;

/// What a door does with a note.
pub type Sink = Box<dyn Fn(&str) + Send + Sync>;

static SINK: OnceLock<(Sink, bool)> = OnceLock::new();

/// Installs the process's sink (once; later calls are ignored, the first
/// door to start owns the process); `colour`: whether diagnostics (notes
/// and errors) are rendered with terminal colours.
pub fn set_sink(sink: Sink, colour: bool) {
    let _ = SINK.set((sink, colour));
}

/// Whether the door wants diagnostics in terminal colours.
pub fn colour() -> bool {
    SINK.get().is_some_and(|(_, c)| *c)
}

/// Hands `text` (one or more lines, no trailing newline needed) to the sink.
pub fn warn(text: &str) {
    if let Some((sink, _)) = SINK.get() {
        sink(text.trim_end());
    }
}
