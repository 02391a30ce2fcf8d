//! Automatic placement of daughter vertices without explicit positions.
//!
//! A production's drawing (the `at:` layout positions of its mother and
//! daughter vertices) is mapped onto the match by a similarity:
//!
//! p = bary(H) + s · R(θ) · (p_D − bary(M))
//!
//! where M are the mother vertices' layout positions, H their matched host
//! positions (same order), θ the angle from M's principal direction to H's
//! and s the ratio of their extents. The mother's barycentre (not the
//! daughter's) is subtracted, so a daughter vertex drawn where a mother
//! vertex is lands on that vertex's match whenever the match is a
//! similar copy of the mother.

/// Relative eigenvalue gap below which a point set has no principal
/// direction (a circle, a square, a single point).
const ISOTROPIC: f64 = 1e-9;

/// The principal direction (unit vector) of `points`, from the 2×2
/// covariance matrix, or `None` when it is undefined.
pub(crate) fn principal_direction(points: &[[f64; 2]]) -> Option<[f64; 2]> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let [cx, cy] = barycentre(points);
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for p in points {
        let (dx, dy) = (p[0] - cx, p[1] - cy);
        sxx += dx * dx;
        syy += dy * dy;
        sxy += dx * dy;
    }
    let (sxx, syy, sxy) = (sxx / n, syy / n, sxy / n);
    let trace = sxx + syy;
    // Eigenvalue gap: sqrt((sxx − syy)² + 4 sxy²).
    let gap = (sxx - syy).hypot(2.0 * sxy);
    // Written so that NaN sums also count as undefined.
    if trace.is_nan() || trace <= 0.0 || gap.is_nan() || gap <= ISOTROPIC * trace {
        return None;
    }
    let phi = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    Some([phi.cos(), phi.sin()])
}

pub(crate) fn barycentre(points: &[[f64; 2]]) -> [f64; 2] {
    if points.is_empty() {
        return [0.0; 2];
    }
    let n = points.len() as f64;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(x, y), p| (x + p[0], y + p[1]));
    [sx / n, sy / n]
}

/// The larger side of the bounding box.
pub(crate) fn extent(points: &[[f64; 2]]) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if points.is_empty() { 0.0 } else { (hi[0] - lo[0]).max(hi[1] - lo[1]) }
}

/// The similarity taking the mother's layout onto its match.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Similarity {
    from: [f64; 2],
    to: [f64; 2],
    /// s·cos θ, s·sin θ.
    a: f64,
    b: f64,
}

impl Similarity {
    /// Fits the similarity from mother layout points `m` to host points `h`
    /// (same length and order). `hints` are index pairs (i, j) whose vector
    /// p_j − p_i fixes the sign of the principal direction, best first (the
    /// pattern's directed edges, then vertex pairs); the first one not
    /// orthogonal to the mother's direction decides, on both sides.
    pub(crate) fn fit(m: &[[f64; 2]], h: &[[f64; 2]], hints: &[(usize, usize)]) -> Similarity {
        let (bm, bh) = (barycentre(m), barycentre(h));
        let em = extent(m);
        let s = if em > 0.0 { extent(h) / em } else { 1.0 };
        let theta = match (principal_direction(m), principal_direction(h)) {
            (Some(dm), Some(dh)) => {
                let along = |d: [f64; 2], p: &[[f64; 2]], (i, j): (usize, usize)| {
                    d[0] * (p[j][0] - p[i][0]) + d[1] * (p[j][1] - p[i][1])
                };
                let scale = em.max(f64::MIN_POSITIVE);
                match hints.iter().find(|&&hint| along(dm, m, hint).abs() > 1e-9 * scale) {
                    Some(&hint) => {
                        let dm = if along(dm, m, hint) < 0.0 { [-dm[0], -dm[1]] } else { dm };
                        let dh = if along(dh, h, hint) < 0.0 { [-dh[0], -dh[1]] } else { dh };
                        dh[1].atan2(dh[0]) - dm[1].atan2(dm[0])
                    }
                    None => 0.0,
                }
            }
            _ => 0.0,
        };
        Similarity { from: bm, to: bh, a: s * theta.cos(), b: s * theta.sin() }
    }

    /// Where layout point `p` goes.
    pub(crate) fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let (dx, dy) = (p[0] - self.from[0], p[1] - self.from[1]);
        [self.to[0] + self.a * dx - self.b * dy, self.to[1] + self.b * dx + self.a * dy]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9
    }

    #[test]
    fn a_directed_edge_turned_and_scaled() {
        // Mother A(0,0) → B(1,0); daughter P at (0.5, 0.5), left of AB.
        // Host A'(2,2) → B'(2,4): turned +90°, twice as long. Then
        // bary(M) = (0.5, 0), bary(H) = (2, 3), P − bary(M) = (0, 0.5),
        // turned (−0.5, 0), scaled (−1, 0): P' = (1, 3), left of A'B'.
        let m = [[0.0, 0.0], [1.0, 0.0]];
        let h = [[2.0, 2.0], [2.0, 4.0]];
        let t = Similarity::fit(&m, &h, &[(0, 1)]);
        assert!(close(t.apply([0.5, 0.5]), [1.0, 3.0]), "{:?}", t.apply([0.5, 0.5]));
        // Mapped vertices land on their matches.
        assert!(close(t.apply(m[0]), h[0]) && close(t.apply(m[1]), h[1]));
        // The same edge matched backwards (B' below A'): turned −90°.
        let h2 = [[2.0, 4.0], [2.0, 2.0]];
        let t2 = Similarity::fit(&m, &h2, &[(0, 1)]);
        assert!(close(t2.apply([0.5, 0.5]), [3.0, 3.0]), "{:?}", t2.apply([0.5, 0.5]));
    }

    #[test]
    fn sign_from_the_hint_not_from_the_covariance() {
        // Covariance alone cannot tell (1, 0) from (−1, 0): a half turn of
        // the match must still be seen.
        let m = [[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]];
        let h = [[10.0, 0.0], [8.0, 0.0], [6.0, 0.0]];
        let t = Similarity::fit(&m, &h, &[(0, 2)]);
        assert!(close(t.apply([2.0, 1.0]), [8.0, -1.0]), "{:?}", t.apply([2.0, 1.0]));
    }

    #[test]
    fn no_direction_means_no_rotation() {
        // A square has no principal direction: only translate and scale.
        let m = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let h = [[5.0, 5.0], [5.0, 8.0], [2.0, 8.0], [2.0, 5.0]];
        assert_eq!(principal_direction(&m), None);
        let t = Similarity::fit(&m, &h, &[(0, 1)]);
        // bary 0.5,0.5 → 3.5,6.5; scale 3; (1,0.5) − bary = (0.5, 0) → (1.5, 0).
        assert!(close(t.apply([1.0, 0.5]), [5.0, 6.5]));
        // A single point: pure translation, scale 1.
        let t = Similarity::fit(&[[1.0, 1.0]], &[[4.0, -2.0]], &[]);
        assert!(close(t.apply([2.0, 3.0]), [5.0, 0.0]));
    }

    #[test]
    fn principal_direction_of_a_tilted_line() {
        let pts = [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.1]];
        let d = principal_direction(&pts).unwrap();
        assert!((d[1].atan2(d[0]).abs() - std::f64::consts::FRAC_PI_4).abs() < 0.02, "{d:?}");
        assert_eq!(extent(&pts), 3.1);
    }
}
