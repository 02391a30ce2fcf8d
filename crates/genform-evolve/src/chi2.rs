//! Pearson's χ² goodness-of-fit test, for the statistical tests of the
//! samplers.

/// The χ² statistic and degrees of freedom of `observed` counts against
/// `expected` probabilities (summing to 1) over `n` samples. Bins whose
/// expected count is below 5 are pooled into one, as the test requires.
pub(crate) fn statistic(observed: &[u64], expected: &[f64]) -> (f64, usize) {
    let n: u64 = observed.iter().sum();
    let n = n as f64;
    let (mut chi2, mut bins) = (0.0, 0usize);
    let (mut pooled_o, mut pooled_e) = (0.0, 0.0);
    for (&o, &p) in observed.iter().zip(expected) {
        let e = p * n;
        if e < 5.0 {
            pooled_o += o as f64;
            pooled_e += e;
        } else {
            chi2 += (o as f64 - e).powi(2) / e;
            bins += 1;
        }
    }
    if pooled_e > 0.0 {
        chi2 += (pooled_o - pooled_e).powi(2) / pooled_e.max(1e-12);
        bins += 1;
    }
    (chi2, bins.saturating_sub(1))
}

/// Upper critical value of χ² with `df` degrees of freedom at the normal
/// quantile `z` (3.29 ≈ p = 0.0005), by the Wilson–Hilferty approximation.
pub(crate) fn critical(df: usize, z: f64) -> f64 {
    let k = df.max(1) as f64;
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + z * a.sqrt()).powi(3)
}

/// Asserts that `observed` fits `expected` at p ≈ 0.0005.
pub(crate) fn assert_fits(what: &str, observed: &[u64], expected: &[f64]) {
    let (chi2, df) = statistic(observed, expected);
    let crit = critical(df, 3.29);
    assert!(chi2 < crit, "{what}: χ² = {chi2:.1} with {df} degrees of freedom exceeds {crit:.1}");
}

#[test]
fn detects_a_skewed_die_and_accepts_a_fair_one() {
    let fair = [1.0 / 6.0; 6];
    assert_fits("fair", &[1010, 980, 1003, 995, 1020, 992], &fair);
    let (chi2, df) = statistic(&[1200, 980, 1003, 995, 1020, 802], &fair);
    assert!(chi2 > critical(df, 3.29));
    assert!((critical(10, 1.645) - 18.31).abs() < 0.1, "{}", critical(10, 1.645));
}
