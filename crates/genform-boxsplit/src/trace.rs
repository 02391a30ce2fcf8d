//! The derivation trace: every choice, failure and backtrack, serializable
//! to JSON.

use serde::{Deserialize, Serialize};
use std::fmt;

/// A scope as the trace shows it: its box in world coordinates and its
/// local axes (`"xyz"` unless reoriented; `"zyx"`: local x runs along world z).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct TraceScope {
    /// World position of the box's low corner.
    pub min: [i32; 3],
    /// Extent along world x, y, z.
    pub size: [i32; 3],
    /// World axis of local x, y and z.
    pub axes: String,
}

impl fmt::Display for TraceScope {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y, z] = self.min;
        let [a, b, c] = self.size;
        write!(f, "box at ({x}, {y}, {z}) of {a}×{b}×{c}")?;
        if self.axes != "xyz" {
            write!(f, " (local axes {})", self.axes)?;
        }
        Ok(())
    }
}

/// One step of a derivation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum TraceEvent {
    /// A rule was applied with one of its alternatives.
    Apply {
        /// The rule.
        rule: String,
        /// Where.
        scope: TraceScope,
        /// Index of the alternative in the rule (source order).
        alternative: usize,
        /// Source line of the alternative.
        line: u32,
        /// Alternatives that were applicable when the scope was expanded.
        candidates: usize,
        /// Alternatives still untried after this one.
        left: usize,
        /// Rule applications enclosing this one.
        depth: u32,
    },
    /// A rule could not be applied.
    Fail {
        /// The rule (for a failed split: the rule whose alternative made it).
        rule: String,
        /// Where.
        scope: TraceScope,
        /// Why.
        reason: String,
    },
    /// The derivation went back to an earlier application to try another
    /// alternative, forgetting everything derived below it.
    Backtrack {
        /// The rule whose choice is revisited.
        rule: String,
        /// Its scope.
        scope: TraceScope,
        /// Rule applications with alternatives left that were discarded.
        discarded: usize,
        /// Fills discarded.
        discarded_fills: usize,
    },
    /// Every alternative up to the axiom failed.
    Exhausted {
        /// The axiom.
        rule: String,
    },
    /// The derivation succeeded.
    Done {
        /// Rule applications.
        applications: u64,
        /// Backtracks.
        backtracks: u64,
    },
}

/// The events of one derivation, in order.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Trace {
    /// Events in the order they happened.
    pub events: Vec<TraceEvent>,
}

impl Trace {
    /// The trace as pretty-printed JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Number of backtrack events.
    pub fn backtracks(&self) -> usize {
        self.events.iter().filter(|e| matches!(e, TraceEvent::Backtrack { .. })).count()
    }
}
