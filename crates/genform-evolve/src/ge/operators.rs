//! Operators on codon strings: random genomes, variable-length one-point
//! crossover and per-codon mutation.

use super::codons::Codons;
use genform_core::Rng;

/// A genome of `int_inclusive(a, b)` codons, each uniform in
/// `0..codon_range` (which must be > 0).
pub fn random_codons([a, b]: [usize; 2], codon_range: u32, rng: &mut Rng) -> Codons {
    let len = rng.int_inclusive(a as i64, b as i64) as usize;
    (0..len).map(|_| rng.below(codon_range as u64) as u32).collect()
}

/// Variable-length one-point crossover, as standard GE does it: a cut point
/// is drawn independently in each parent, `i` uniform in `1..=a.len()` and
/// `j` in `1..=b.len()`, and the tails are swapped:
/// `[a[..i] + b[j..], b[..j] + a[i..]]`. Heads are never empty, so children
/// of non-empty parents are non-empty; the two children together hold
/// exactly the parents' codons. A child longer than `max_length` keeps its
/// first `max_length` codons (the mapper reads left to right, so the cut
/// removes what it would read last). An empty parent cuts at 0.
pub fn crossover(a: &[u32], b: &[u32], max_length: usize, rng: &mut Rng) -> [Codons; 2] {
    let i = cut_point(a.len(), rng);
    let j = cut_point(b.len(), rng);
    [splice(&a[..i], &b[j..], max_length), splice(&b[..j], &a[i..], max_length)]
}

/// [`crossover`] with each cut inside the parent's expressed region: `i`
/// uniform in `1..=ea` and `j` in `1..=eb` (each clamped to the parent's
/// length; 0 counts as the whole genome). Also returns the length of each
/// child's inherited expressed part, `i + (eb − j)` and `j + (ea − i)`,
/// where mutation then acts.
pub fn effective_crossover(
    (a, ea): (&[u32], usize),
    (b, eb): (&[u32], usize),
    max_length: usize,
    rng: &mut Rng,
) -> ([Codons; 2], [usize; 2]) {
    let region = |len: usize, e: usize| if e == 0 { len } else { e.min(len) };
    let (ea, eb) = (region(a.len(), ea), region(b.len(), eb));
    let i = cut_point(ea, rng);
    let j = cut_point(eb, rng);
    let children = [splice(&a[..i], &b[j..], max_length), splice(&b[..j], &a[i..], max_length)];
    let reach = [(i + eb.saturating_sub(j)).min(children[0].len()), (j + ea.saturating_sub(i)).min(children[1].len())];
    (children, reach)
}

fn cut_point(len: usize, rng: &mut Rng) -> usize {
    if len == 0 { 0 } else { 1 + rng.index(len) }
}

/// `head + tail`, cut to `max_length` codons.
fn splice(head: &[u32], tail: &[u32], max_length: usize) -> Codons {
    let len = (head.len() + tail.len()).min(max_length);
    let mut child = Vec::with_capacity(len);
    child.extend_from_slice(&head[..head.len().min(len)]);
    child.extend_from_slice(&tail[..len - child.len()]);
    child
}

/// Integer mutation: every codon, with probability `rate`, is replaced by
/// a codon uniform in `0..codon_range` (possibly the same value). Returns
/// how many codons changed value.
pub fn mutate(codons: &mut [u32], rate: f64, codon_range: u32, rng: &mut Rng) -> usize {
    let mut changed = 0;
    if rate <= 0.0 {
        return 0;
    }
    for c in codons {
        if rng.bernoulli(rate) {
            let new = rng.below(codon_range as u64) as u32;
            changed += usize::from(new != *c);
            *c = new;
        }
    }
    changed
}

#[cfg(test)]
mod tests {
    use super::*;
    use genform_core::Rng;
    use proptest::prelude::*;

    fn codons(max_len: usize) -> impl Strategy<Value = Vec<u32>> {
        prop::collection::vec(0u32..1000, 1..=max_len)
    }

    proptest! {
        #[test]
        fn random_codons_respect_length_and_range(a in 1usize..30, extra in 0usize..30, range in 2u32..2000, seed: u64) {
            let g = random_codons([a, a + extra], range, &mut Rng::from_seed(seed));
            prop_assert!((a..=a + extra).contains(&g.len()));
            prop_assert!(g.iter().all(|&c| c < range));
        }

        #[test]
        fn crossover_children_are_parent_segments(a in codons(40), b in codons(40), cap in 1usize..100, seed: u64) {
            let [c0, c1] = crossover(&a, &b, cap, &mut Rng::from_seed(seed));
            prop_assert!(!c0.is_empty() && !c1.is_empty());
            prop_assert!(c0.len() <= cap && c1.len() <= cap);
            // Some pair of cut points (i, j), each ≥ 1, explains both children.
            let explained = (1..=a.len()).any(|i| {
                (1..=b.len()).any(|j| {
                    let full0: Vec<u32> = a[..i].iter().chain(&b[j..]).copied().collect();
                    let full1: Vec<u32> = b[..j].iter().chain(&a[i..]).copied().collect();
                    full0[..full0.len().min(cap)] == c0[..] && full1[..full1.len().min(cap)] == c1[..]
                })
            });
            prop_assert!(explained, "a {a:?}\nb {b:?}\n→ {c0:?} {c1:?}");
            if a.len().max(b.len()) * 2 <= cap {
                // Nothing cut: the codons are conserved.
                prop_assert_eq!(c0.len() + c1.len(), a.len() + b.len());
            }
        }

        #[test]
        fn mutation_keeps_length_and_range(g in codons(60), rate in 0.0f64..=1.0, range in 2u32..50, seed: u64) {
            let mut m: Vec<u32> = g.iter().map(|c| c % range).collect();
            let before = m.clone();
            let changed = mutate(&mut m, rate, range, &mut Rng::from_seed(seed));
            prop_assert_eq!(m.len(), before.len());
            prop_assert!(m.iter().all(|&c| c < range));
            prop_assert_eq!(changed, m.iter().zip(&before).filter(|(x, y)| x != y).count());
        }
    }

    #[test]
    fn effective_cuts_fall_inside_the_expressed_regions() {
        let a: Vec<u32> = (0..50).collect();
        let b: Vec<u32> = (100..180).collect();
        let mut rng = Rng::from_seed(9);
        for _ in 0..500 {
            let ([c0, c1], [r0, r1]) = effective_crossover((&a, 10), (&b, 4), 1000, &mut rng);
            let i = c0.iter().take_while(|&&c| c < 100).count();
            let j = c1.iter().take_while(|&&c| c >= 100).count();
            assert!((1..=10).contains(&i) && (1..=4).contains(&j), "cuts {i} {j}");
            assert_eq!((c0.len(), c1.len()), (i + 80 - j, j + 50 - i));
            assert_eq!((r0, r1), (i + 4 - j, j + 10 - i));
        }
        // 0: nothing known, the whole genome is the region.
        let ([c0, _], _) = effective_crossover((&a, 0), (&b, 0), 1000, &mut Rng::from_seed(1));
        assert!(!c0.is_empty());
    }

    #[test]
    fn cut_points_reach_both_ends() {
        // Over many draws, children of lengths 1 + 0 (a cut after a's first
        // codon, b cut after its last) and the full swap both appear.
        let (a, b) = (vec![1, 2, 3], vec![7, 8]);
        let mut rng = Rng::from_seed(1);
        let mut seen = std::collections::HashSet::new();
        for _ in 0..500 {
            seen.insert(crossover(&a, &b, 100, &mut rng));
        }
        assert!(seen.contains(&[vec![1], vec![7, 8, 2, 3]]));
        assert!(seen.contains(&[vec![1, 2, 3], vec![7, 8]]));
        assert_eq!(seen.len(), 6, "3 × 2 cut-point pairs");
    }

    #[test]
    fn mutation_rate_is_per_codon() {
        let mut rng = Rng::from_seed(2);
        let mut g = vec![0u32; 100_000];
        let changed = mutate(&mut g, 0.01, 1000, &mut rng);
        // Redrawn ≈ 1000 (sd ≈ 31), of which 1/1000 keep the value 0.
        assert!((900..1100).contains(&changed), "{changed}");
        assert_eq!(mutate(&mut g, 0.0, 1000, &mut rng), 0);
    }
}
