//! Ranged constants: `define name = value in [min, max]` (real) or `in
//! min..max` (whole numbers). They read as their written value, except in a
//! generator, where each is a gene of the root (see `generator.rs`): the
//! system is then recompiled with the genome's values (`recompile.rs`), so
//! every place that reads a constant — conditions, successor formulas, the
//! axiom, settings such as `angle:` — sees the gene. This file holds the
//! constant, its checks at compile time and what recompiling needs.

use crate::syntax::{self, Define, Range};
use genform_core::Mesh;
use genform_core::diag::Diagnostic;
use std::sync::Arc;

/// A constant whose value is a gene: its name, kind, written value and
/// bounds (both included).
#[derive(Clone, Debug, PartialEq)]
pub struct RangedConstant {
    /// The constant's name.
    pub name: String,
    /// Whole numbers only (`in min..max`; an L-Py `Integer` or `Bool`).
    pub integer: bool,
    /// The written value, what a derivation without a genome reads.
    pub value: f64,
    /// The lower bound.
    pub min: f64,
    /// The upper bound.
    pub max: f64,
}

impl RangedConstant {
    /// `v` as the constant's value: rounded to a whole number for an
    /// integer range, or why it cannot be (not finite, outside the range).
    pub fn admit(&self, v: f64) -> Result<f64, String> {
        let v = if self.integer { v.round() } else { v };
        if !v.is_finite() {
            return Err(format!("the constant `{}` has no finite value ({v})", self.name));
        }
        if v < self.min || v > self.max {
            return Err(format!("the constant `{}` = {v} is outside its range {}", self.name, self.range_text()));
        }
        Ok(v)
    }

    /// The range as written: `[min, max]` or `min..max`.
    pub fn range_text(&self) -> String {
        range_text(self.integer, self.min, self.max)
    }
}

/// A range as `.ls` writes it: `min..max` (whole numbers) or `[min, max]`.
pub(crate) fn range_text(integer: bool, min: f64, max: f64) -> String {
    if integer { format!("{min}..{max}") } else { format!("[{min}, {max}]") }
}

/// What recompiling with other constant values needs: the parsed file and
/// the surfaces already loaded (so no file is read again).
#[derive(Debug)]
pub(crate) struct Recipe {
    pub(crate) file: syntax::File,
    pub(crate) surfaces: Vec<(String, Arc<Mesh>)>,
}

/// Checks a ranged `define`'s written value `v` against its bounds
/// `(min, max)` (`None` where a formula already failed). Returns the
/// constant, or pushes an error at the offending part.
pub(crate) fn check(
    d: &Define,
    r: &Range,
    v: Option<f64>,
    bounds: (Option<f64>, Option<f64>),
    errors: &mut Vec<Diagnostic>,
) -> Option<RangedConstant> {
    let name = &d.name;
    let (v, min, max) = (v?, bounds.0?, bounds.1?);
    let value_span = d.expr.ast.span.shift(d.expr.at);
    let example = if r.integer { "`in 0..9`" } else { "`in [0, 90]`" };
    let mut fail = |span, message: String, hint: String| {
        errors.push(Diagnostic::error(span, message).with_hint(hint));
        None
    };
    if !min.is_finite() || !max.is_finite() {
        return fail(
            r.span,
            format!("the range of `{name}` has a bound that is not a finite number ({min}, {max})"),
            format!("bounds are finite numbers, e.g. {example}"),
        );
    }
    if min > max {
        return fail(
            r.span,
            format!("the range of `{name}` is empty: its min {min} is above its max {max}"),
            format!("write the smaller bound first: `in {}`", range_text(r.integer, max, min)),
        );
    }
    if r.integer && (min.fract() != 0.0 || max.fract() != 0.0) {
        return fail(
            r.span,
            format!("the whole-number range of `{name}` has a bound that is not whole ({min}, {max})"),
            format!("write whole bounds, or a real range `in [{min}, {max}]`"),
        );
    }
    if v.is_nan() {
        return fail(value_span, format!("`{name}` is not a number (NaN)"), "give it a value inside its range".into());
    }
    if r.integer && v.fract() != 0.0 {
        return fail(
            value_span,
            format!("`{name}` = {v} is not a whole number, but its range `{min}..{max}` is"),
            format!("write a whole value, or a real range `in [{min}, {max}]`"),
        );
    }
    if v < min || v > max {
        return fail(
            value_span,
            format!("`{name}` = {v} is outside its range {} (bounds included)", range_text(r.integer, min, max)),
            "widen the range or change the value".into(),
        );
    }
    Some(RangedConstant { name: name.clone(), integer: r.integer, value: v, min, max })
}
