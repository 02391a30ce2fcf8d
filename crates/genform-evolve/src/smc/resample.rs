//! Resampling weights and systematic resampling.

use crate::config::Weighting;
use genform_core::Rng;

/// Resampling weight of each particle. Invalid particles (non-finite
/// fitness) get 0; when every weight would be 0 (all invalid, or all equal
/// under [`Weighting::Shifted`]) the valid particles — or all, when none is
/// valid — get equal weights.
///
/// [`Weighting::Boltzmann`] computes `exp((f − f_max) / T)` (the shift by
/// the best fitness cancels in normalization and avoids overflow). `T` is
/// `temperature` or, when unset, the standard deviation of the valid
/// fitness values.
pub fn weights(fitness: &[f64], weighting: Weighting, temperature: Option<f64>) -> Vec<f64> {
    let valid: Vec<f64> = fitness.iter().copied().filter(|f| f.is_finite()).collect();
    let mut w: Vec<f64> = match weighting {
        Weighting::Boltzmann => {
            let best = valid.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let t = temperature.or_else(|| std_dev(&valid)).filter(|t| *t > 0.0);
            fitness
                .iter()
                .map(|&f| match t {
                    _ if !f.is_finite() => 0.0,
                    Some(t) => ((f - best) / t).exp(),
                    None => 1.0,
                })
                .collect()
        }
        Weighting::Shifted => {
            let worst = valid.iter().copied().fold(f64::INFINITY, f64::min);
            fitness.iter().map(|&f| if f.is_finite() { f - worst } else { 0.0 }).collect()
        }
    };
    if !w.iter().any(|x| *x > 0.0) {
        let none_valid = valid.is_empty();
        for (x, f) in w.iter_mut().zip(fitness) {
            *x = if none_valid || f.is_finite() { 1.0 } else { 0.0 };
        }
    }
    w
}

/// Population standard deviation; `None` for fewer than two values.
pub(crate) fn std_dev(values: &[f64]) -> Option<f64> {
    if values.len() < 2 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / values.len() as f64;
    Some(var.sqrt()).filter(|s| s.is_finite())
}

/// Effective sample size `(Σw)² / Σw²`.
pub fn effective_size(weights: &[f64]) -> f64 {
    let sum: f64 = weights.iter().sum();
    let sq: f64 = weights.iter().map(|w| w * w).sum();
    if sq > 0.0 { sum * sum / sq } else { 0.0 }
}

/// Systematic resampling: `n` indices, particle `i` chosen
/// `⌊n wᵢ/W⌋` or `⌈n wᵢ/W⌉` times and `n wᵢ/W` times in expectation (one
/// uniform offset, `n` evenly spaced points). Indices come out in
/// increasing order. `weights` must have a positive sum.
pub fn systematic(weights: &[f64], n: usize, rng: &mut Rng) -> Vec<usize> {
    let total: f64 = weights.iter().sum();
    assert!(total > 0.0 && total.is_finite(), "resampling needs a positive finite weight sum");
    let step = total / n as f64;
    let mut point = rng.next_f64() * step;
    let mut out = Vec::with_capacity(n);
    let mut cumulative = 0.0;
    let last = weights.iter().rposition(|w| *w > 0.0).expect("a positive weight");
    for (i, &w) in weights.iter().enumerate() {
        cumulative += w;
        // The last positive particle takes every remaining point, so
        // rounding never leaves a point unassigned.
        while out.len() < n && (point < cumulative || i == last) {
            out.push(i);
            point += step;
        }
        if out.len() == n {
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn systematic_resampling_is_unbiased_and_low_variance() {
        let weights = [0.05, 0.3, 0.0, 0.125, 0.4, 0.125];
        let n = 10;
        let runs = 20_000;
        let mut totals = [0u64; 6];
        let mut rng = Rng::from_seed(1);
        for _ in 0..runs {
            let picks = systematic(&weights, n, &mut rng);
            assert_eq!(picks.len(), n);
            assert!(picks.windows(2).all(|p| p[0] <= p[1]));
            for (i, &w) in weights.iter().enumerate() {
                let count = picks.iter().filter(|&&p| p == i).count() as f64;
                let expected = n as f64 * w;
                assert!(count == expected.floor() || count == expected.ceil(), "particle {i}: {count} vs {expected}");
                totals[i] += count as u64;
            }
        }
        for (i, &w) in weights.iter().enumerate() {
            let mean = totals[i] as f64 / runs as f64;
            let expected = n as f64 * w;
            // Each count is floor or ceil, so its variance is at most 1/4.
            let se = 0.5 / (runs as f64).sqrt();
            assert!((mean - expected).abs() < 4.0 * se, "particle {i}: mean {mean} vs {expected}");
        }
    }

    #[test]
    fn boltzmann_and_shifted_weights() {
        let f = [1.0, 3.0, f64::NAN, 2.0];
        let w = weights(&f, Weighting::Boltzmann, Some(1.0));
        assert_eq!(w[1], 1.0);
        assert!((w[0] - (-2.0f64).exp()).abs() < 1e-15 && w[2] == 0.0);
        let auto = weights(&f, Weighting::Boltzmann, None);
        let sd = (2.0f64 / 3.0).sqrt();
        assert!((auto[3] - (-1.0 / sd).exp()).abs() < 1e-12);
        assert_eq!(weights(&f, Weighting::Shifted, None), vec![0.0, 2.0, 0.0, 1.0]);
        assert_eq!(weights(&[2.0, 2.0, f64::NAN], Weighting::Shifted, None), vec![1.0, 1.0, 0.0]);
        assert_eq!(weights(&[f64::NAN; 2], Weighting::Boltzmann, None), vec![1.0, 1.0]);
        assert!((effective_size(&[1.0, 1.0, 0.0]) - 2.0).abs() < 1e-12);
        // Scores far below the best must not underflow the best to 0.
        let w = weights(&[-1e6, -1e6 + 5.0], Weighting::Boltzmann, Some(1.0));
        assert_eq!(w[1], 1.0);
    }
}
