//! Gaussian parameter drift: small steps around the current values instead
//! of fresh draws. Shared by the GA's drift mutation and MH's diffusion, so
//! both scale their steps the same way.

use genform_core::genome::GenePos;
use genform_core::graph::Distribution;
use genform_core::{GeneratorGraph, Genome, Rng};

/// Standard deviation of a drift step for a component drawn from `d`:
/// `scale` times its range (uniform) or standard deviation (normal).
/// `None` for discrete components (choices, integer ranges), which are
/// redrawn instead.
pub(crate) fn drift_sd(d: &Distribution, scale: f64) -> Option<f64> {
    match d {
        Distribution::Uniform { min, max } => Some(scale * (max - min)),
        Distribution::Normal { sd, .. } => Some(scale * sd),
        _ => None,
    }
}

/// `v` folded back into `[min, max]` by reflection at the bounds (the
/// identity inside; infinite bounds never reflect). Reflection keeps a
/// symmetric step symmetric near the bounds, unlike clamping, which would
/// pile values up on them.
pub(crate) fn reflect(v: f64, min: f64, max: f64) -> f64 {
    if min.is_nan() || max.is_nan() || min > max || !v.is_finite() {
        return v;
    }
    let width = max - min;
    if width == 0.0 {
        return min;
    }
    if v >= min && v <= max {
        return v;
    }
    if !width.is_finite() {
        return if v < min { 2.0 * min - v } else { 2.0 * max - v };
    }
    // Unfold onto a period of twice the width, then mirror the second half.
    let t = (v - min).rem_euclid(2.0 * width);
    if t <= width { min + t } else { max - (t - width) }
}

/// The GA's drift mutation: every continuous parameter of one gene, chosen
/// uniformly among the genes with parameters, moves by a Gaussian step of
/// `scale` times its range (uniform) or standard deviation (normal),
/// reflected into the distribution's bounds; discrete parameters are
/// redrawn. The structure never changes. Returns the gene's position,
/// `None` when no gene has parameters.
pub fn drift(genome: &mut Genome, graph: &GeneratorGraph, scale: f64, rng: &mut Rng) -> Option<GenePos> {
    let with_params = genome.iter().filter(|g| g.param_len() > 0).count();
    if with_params == 0 {
        return None;
    }
    let g = genome.iter().filter(|g| g.param_len() > 0).nth(rng.index(with_params))?;
    let pos = g.pos;
    let old: Vec<f64> = g.params().collect();
    let mut new = Vec::with_capacity(old.len());
    for (d, &v) in graph.symbol(g.symbol()).components().zip(&old) {
        let w = match (drift_sd(d, scale), d) {
            (Some(sd), Distribution::Uniform { min, max } | Distribution::Normal { min, max, .. }) => {
                reflect(rng.normal(v, sd), *min, *max)
            }
            _ => d.sample(rng),
        };
        new.push(w);
    }
    genome.set_params(pos, &new);
    Some(pos)
}
