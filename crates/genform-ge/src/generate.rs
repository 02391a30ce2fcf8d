//! Sensible initialisation: genomes written from random derivation trees.
//!
//! Random codon strings map to whatever the first few codons happen to
//! choose; PonyGE2's *sensible* (ramped half-and-half) initialisation
//! instead grows a derivation tree under a depth limit — *grow* picks any
//! production that fits under the limit, *full* prefers recursive ones so
//! every branch reaches it — and then "unmaps" it: each choice `c` among
//! `n` becomes the codon `c + k·n` for a random `k`, so mapping the codons
//! gives that tree back. Ramping the limit over a population spreads
//! generation 0 over small and large trees.
//!
//! The generator runs the mapper itself with a codon source that answers
//! each decision as it is asked ([`Genes`]), so Genr8's extensions
//! (repetition counters, edge IDs and their binding, the depth rule,
//! repair) are unmapped exactly as they map; a generated genome never
//! wraps. Repetitions, options and edge IDs are drawn as random codons
//! draw them (a group too deep for the limit is left out); only
//! production choices follow the grow/full policy.

use crate::mapper::{Ask, Genes, Mapper, State};
use crate::outcome::Failure;
use crate::program::{Program, Sym};
use genform_core::Rng;

/// How a derivation tree is grown under its depth limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Growth {
    /// Any production whose shallowest expansion fits under the limit.
    Grow,
    /// Recursive productions while they fit, so branches reach the limit.
    Full,
}

/// One sensible genome to write ([`Mapper::generate`]).
#[derive(Clone, Copy, Debug)]
pub struct Sensible {
    /// Grow or full.
    pub growth: Growth,
    /// Deepest non-terminal of the tree (root = 1), raised to the
    /// grammar's [`Mapper::min_tree_depth`] when below it.
    pub max_depth: u32,
    /// Codons lie in `0..codon_range`.
    pub codon_range: u32,
    /// Most codons the derivation may read; a longer one is given up.
    pub max_codons: usize,
}

/// Depths and recursion of a grammar's productions, for the policy.
struct Tables {
    /// Per production: levels of non-terminals its shallowest expansion
    /// takes, itself included (1: terminals and skippable groups only).
    prod_depth: Vec<u32>,
    /// Per group: levels below its items' depth its mandatory
    /// non-terminals take (0: none).
    group_depth: Vec<u32>,
    /// Per production: it holds a non-terminal that leads back to its rule.
    recursive: Vec<bool>,
    /// Per rule: its shallowest production's depth.
    rule_depth: Vec<u32>,
}

const INF: u32 = u32::MAX / 4;

impl Tables {
    fn new(p: &Program) -> Tables {
        let mut rule_depth = vec![INF; p.rules.len()];
        // Mandatory non-terminals: groups may be left out (a repetition
        // stops, an option is skipped), so only the range's own count.
        let deepest = |range: &crate::program::Range, rule_depth: &[u32]| {
            p.syms[range.start as usize..range.end as usize]
                .iter()
                .filter_map(|s| match s {
                    Sym::Nt(r) => Some(rule_depth[*r as usize]),
                    _ => None,
                })
                .max()
                .unwrap_or(0)
        };
        loop {
            let mut changed = false;
            for (r, rule) in p.rules.iter().enumerate() {
                let best = (rule.first..rule.first + rule.n)
                    .map(|i| 1 + deepest(&p.prods[i as usize], &rule_depth).min(INF))
                    .min()
                    .unwrap_or(INF);
                if best < rule_depth[r] {
                    rule_depth[r] = best;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let prod_depth = p.prods.iter().map(|r| (1 + deepest(r, &rule_depth)).min(INF)).collect();
        let group_depth = p.groups.iter().map(|g| deepest(g, &rule_depth)).collect();
        // reach[a][b]: rule b is reachable from rule a (groups included).
        let n = p.rules.len();
        let mut reach = vec![vec![false; n]; n];
        let mentions = |range: &crate::program::Range, out: &mut Vec<bool>| {
            let mut stack = vec![*range];
            while let Some(r) = stack.pop() {
                for s in &p.syms[r.start as usize..r.end as usize] {
                    match s {
                        Sym::Nt(b) => out[*b as usize] = true,
                        Sym::Repeat(g) | Sym::Option(g) => stack.push(p.groups[*g as usize]),
                        _ => {}
                    }
                }
            }
        };
        for (a, rule) in p.rules.iter().enumerate() {
            for i in rule.first..rule.first + rule.n {
                mentions(&p.prods[i as usize], &mut reach[a]);
            }
        }
        for k in 0..n {
            let via = reach[k].clone();
            for row in reach.iter_mut().filter(|row| row[k]) {
                for (r, &v) in row.iter_mut().zip(&via) {
                    *r |= v;
                }
            }
        }
        let mut recursive = vec![false; p.prods.len()];
        for (a, rule) in p.rules.iter().enumerate() {
            for i in rule.first..rule.first + rule.n {
                let mut direct = vec![false; n];
                mentions(&p.prods[i as usize], &mut direct);
                recursive[i as usize] = (0..n).any(|b| direct[b] && (b == a || reach[b][a]));
            }
        }
        Tables { prod_depth, group_depth, recursive, rule_depth }
    }
}

/// The codon source that answers each decision by the policy.
struct Writer<'a> {
    p: &'a Program,
    t: &'a Tables,
    spec: Sensible,
    rng: &'a mut Rng,
    codons: Vec<u32>,
    /// Reused list of open choices.
    open: Vec<u32>,
}

impl Writer<'_> {
    /// A codon that maps to `choice` among `n`: `choice + k·n`.
    fn codon(&mut self, choice: u32, n: u32) -> Result<u32, Failure> {
        if choice >= self.spec.codon_range {
            // The range cannot say it (a huge edge ID): give up this genome.
            return Err(Failure::WrapLimit);
        }
        let k = (self.spec.codon_range - 1 - choice) / n;
        Ok(choice + n * self.rng.below(u64::from(k) + 1) as u32)
    }

    /// Whether a group whose items lie at `depth` fits under the limit.
    fn group_fits(&self, group: u32, depth: u32) -> bool {
        let d = self.t.group_depth[group as usize];
        d == 0 || depth + d - 1 <= self.spec.max_depth
    }
}

impl Genes for Writer<'_> {
    fn next(&mut self, s: &mut State, _: u32, n: u32, ask: Ask) -> Result<(usize, u32), Failure> {
        if self.codons.len() >= self.spec.max_codons {
            return Err(Failure::WrapLimit);
        }
        let choice = match ask {
            Ask::Rule { rule, depth, limited } => {
                let r = self.p.rules[rule as usize];
                // Local choice index → production index.
                let prod = |k: u32| {
                    if limited { r.first + self.p.limited[(r.limited_first + k) as usize] } else { r.first + k }
                };
                let fits = |k: u32| depth + self.t.prod_depth[prod(k) as usize] - 1 <= self.spec.max_depth;
                self.open.clear();
                self.open.extend((0..n).filter(|&k| fits(k)));
                if self.spec.growth == Growth::Full && self.open.iter().any(|&k| self.t.recursive[prod(k) as usize]) {
                    let t = self.t;
                    self.open.retain(|&k| t.recursive[prod(k) as usize]);
                }
                if self.open.is_empty() {
                    // Nothing fits: the shallowest production.
                    let shallowest = (0..n).min_by_key(|&k| self.t.prod_depth[prod(k) as usize]).unwrap_or(0);
                    self.open.push(shallowest);
                }
                self.open[self.rng.index(self.open.len())]
            }
            Ask::Repeat { group, depth, count } => {
                if self.group_fits(group, depth) {
                    self.rng.below(u64::from(n)) as u32
                } else {
                    // A choice ≤ count stops the repetition.
                    self.rng.below(u64::from(count) + 1) as u32
                }
            }
            Ask::Option { group, depth } => {
                if self.group_fits(group, depth) {
                    self.rng.below(2) as u32
                } else {
                    0
                }
            }
            Ask::Edge => self.rng.below(u64::from(n)) as u32,
        };
        let codon = self.codon(choice, n)?;
        self.codons.push(codon);
        Ok((s.append(), codon))
    }

    /// Every codon is written at the end, none wraps.
    fn extent(&self, s: &State) -> usize {
        s.pos
    }
}

impl Mapper {
    /// The shallowest derivation tree of the grammar: the fewest levels of
    /// non-terminals (root = 1) any complete phenotype takes.
    pub fn min_tree_depth(&self) -> u32 {
        Tables::new(&self.prog).rule_depth.first().copied().unwrap_or(1)
    }

    /// Writes the codons of a random derivation tree grown by `spec`
    /// (see the [module](self) documentation): exactly the codons the
    /// mapping reads, no tail, never wrapping. `None` when the tree reads
    /// more than `spec.max_codons`, cannot be written in the codon range,
    /// or breaks a limit of the mapping (then [`Mapper::phenotype`] is
    /// `None` too). On success the mapper holds the phenotype, as after
    /// [`Mapper::map`] of the codons.
    pub fn generate(&mut self, spec: &Sensible, rng: &mut Rng) -> Option<Vec<u32>> {
        let tables = Tables::new(&self.prog);
        let mut spec = *spec;
        spec.max_depth = spec.max_depth.max(tables.rule_depth.first().copied().unwrap_or(1));
        // Leave room for the mapping's own depth limit (a non-terminal at
        // `max_tree_depth` is invalid).
        spec.max_depth = spec.max_depth.min(self.cfg.max_tree_depth.saturating_sub(1).max(1));
        let prog = self.prog.clone();
        let mut writer = Writer { p: &prog, t: &tables, spec, rng, codons: Vec::new(), open: Vec::new() };
        let out = self.run_with::<false, _>(&mut writer);
        out.valid().then_some(writer.codons)
    }

    /// Generation-0 genome `index` of PonyGE2's ramped half-and-half
    /// initialisation: even indices grow, odd ones are full; the depth
    /// limit steps through [`Mapper::min_tree_depth`]`..=max_depth` every
    /// two indices. The derivation's codons are followed by a random tail
    /// half as long (at least one codon), as PonyGE2 adds, so crossover
    /// and mutation have unread material too; at most `max_length` codons
    /// in all. Tries up to 16 trees; `None` if none fits `max_length`.
    pub fn ramped(
        &mut self,
        index: usize,
        max_depth: u32,
        codon_range: u32,
        max_length: usize,
        rng: &mut Rng,
    ) -> Option<Vec<u32>> {
        let low = self.min_tree_depth();
        let high = max_depth.max(low);
        let depths = (high - low + 1) as usize;
        let spec = Sensible {
            growth: if index.is_multiple_of(2) { Growth::Grow } else { Growth::Full },
            max_depth: low + ((index / 2) % depths) as u32,
            codon_range,
            max_codons: max_length,
        };
        for _ in 0..16 {
            if let Some(mut codons) = self.generate(&spec, rng) {
                let tail = (codons.len() / 2).max(1);
                let tail = tail.min(max_length.saturating_sub(codons.len()));
                codons.extend((0..tail).map(|_| rng.below(u64::from(codon_range)) as u32));
                return Some(codons);
            }
        }
        None
    }
}
