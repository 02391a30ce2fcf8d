//! How the matcher visits candidates: in an order drawn from the
//! derivation's [`Draws`] (core's one source of random decisions) or in
//! index order.

use genform_core::rng::Draws;

/// How the search visits candidates: randomly (derivations) or in index
/// order (enumeration).
pub(crate) trait Pick {
    /// The first of `n` (≥ 1) candidates to try.
    fn first(&mut self, n: usize) -> usize;
    /// A step coprime with `n`, to visit the others after the first.
    fn stride(&mut self, n: usize) -> usize;
    /// Which of two orientations to try first.
    fn coin(&mut self) -> bool;
}

/// Random visiting order drawn from a [`Draws`].
pub(crate) struct Random<'c, C: Draws>(pub(crate) &'c mut C);

impl<C: Draws> Pick for Random<'_, C> {
    fn first(&mut self, n: usize) -> usize {
        if n <= 1 { 0 } else { self.0.below(n) }
    }

    fn stride(&mut self, n: usize) -> usize {
        if n <= 2 {
            return 1;
        }
        // A random unit of Z/n: a few tries suffice (φ(n)/n ≥ ~0.2 for
        // practical n); fall back to 1.
        for _ in 0..16 {
            let s = 1 + self.0.below(n - 1);
            if gcd(s, n) == 1 {
                return s;
            }
        }
        1
    }

    fn coin(&mut self) -> bool {
        self.0.below(2) == 1
    }
}

/// Index order, for deterministic enumeration.
pub(crate) struct InOrder;

impl Pick for InOrder {
    fn first(&mut self, _n: usize) -> usize {
        0
    }
    fn stride(&mut self, _n: usize) -> usize {
        1
    }
    fn coin(&mut self) -> bool {
        false
    }
}

fn gcd(mut a: usize, mut b: usize) -> usize {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Visits `0..n` starting at `first`, then every `stride` (coprime with
/// `n`), each index once; the stride is drawn only when a second index is
/// needed.
pub(crate) struct Order {
    n: usize,
    first: usize,
    stride: usize,
    k: usize,
}

impl Order {
    pub(crate) fn new(n: usize, pick: &mut impl Pick) -> Order {
        Order { n, first: if n == 0 { 0 } else { pick.first(n) }, stride: 0, k: 0 }
    }

    pub(crate) fn next(&mut self, pick: &mut impl Pick) -> Option<usize> {
        if self.k >= self.n {
            return None;
        }
        if self.k == 1 {
            self.stride = pick.stride(self.n);
        }
        let i = ((self.first as u128 + self.k as u128 * self.stride as u128) % self.n as u128) as usize;
        self.k += 1;
        Some(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::Rng;

    #[test]
    fn orders_visit_everything_once() {
        let mut rng = Rng::from_seed(3);
        for n in [0usize, 1, 2, 3, 10, 12, 97, 360] {
            for _ in 0..20 {
                let mut pick = Random(&mut rng);
                let mut o = Order::new(n, &mut pick);
                let mut seen = vec![false; n];
                while let Some(i) = o.next(&mut pick) {
                    assert!(!seen[i]);
                    seen[i] = true;
                }
                assert!(seen.iter().all(|s| *s));
            }
        }
    }

    #[test]
    fn the_first_candidate_is_uniform() {
        let mut rng = Rng::from_seed(5);
        let mut counts = [0u32; 6];
        for _ in 0..60_000 {
            let mut pick = Random(&mut rng);
            let mut o = Order::new(6, &mut pick);
            counts[o.next(&mut pick).unwrap()] += 1;
        }
        for c in counts {
            assert!((c as f64 - 10_000.0).abs() < 400.0, "{counts:?}");
        }
    }
}
