//! Codon genomes: how a row of the formalism table turns a list of codons
//! into a model ([`CodonDecoder`]), and why an individual can fail to
//! become one ([`Invalid`]).
//!
//! A GE grammar (`.bnf`) maps codons into phenotype text that another row
//! grows (a `.gr8` surface or an `.ls` drawing); box-split and graph
//! grammars take codons as the choices of their derivation
//! ([`genform_core::CodonSource`]). An individual that cannot become a
//! model is *invalid*: it scores `−∞` (genform-evolve's convention) and its
//! reason is counted, so a run reports why individuals fail instead of
//! failing itself.

use anyhow::{Context, Result, anyhow};
use genform_core::Scene;
use std::any::Any;
use std::fmt;

/// A decoder's per-thread working memory.
pub(crate) type DecodeScratch = Box<dyn Any + Send>;

/// The two phases of decoding, timed apart in `run.json`'s `eval_split`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Phase {
    /// Mapping codons (GE) or deriving with codon choices (box-split, graph).
    Mapping,
    /// Parsing and growing (gr8) or compiling, deriving and drawing (ls).
    Build,
}

/// What decoding read, beyond the model.
#[derive(Clone, Debug, Default)]
pub(crate) struct Decoded {
    /// Codon reads (re-reads after wrapping included).
    pub codons_read: usize,
    /// Times reading wrapped to the first codon.
    pub wraps: u32,
    /// The grammar file the model can be grown from again (`best.gr8`,
    /// `best.ls`), as `(extension, text)`; filled on the detailed path only.
    pub grammar_file: Option<(&'static str, String)>,
}

/// Turns codons into a model: what a codon row of the formalism table
/// builds for a scene ([`crate::formalism::Formalism::decoder`]).
pub(crate) trait CodonDecoder: Send + Sync {
    /// Fresh working memory for one thread.
    fn scratch(&self) -> DecodeScratch;

    /// Decodes `codons` into `scene` (empty on entry). `detail` fills the
    /// rejection's message and the grammar file; `lap` is called when each
    /// [`Phase`] ends, failed or not.
    fn decode(
        &self,
        codons: &[u32],
        scratch: &mut DecodeScratch,
        scene: &mut Scene,
        detail: bool,
        lap: &mut dyn FnMut(Phase),
    ) -> Result<Decoded, Rejection>;

    /// Adds what pictures of a finished model show besides it (an
    /// environment's guides); nothing by default.
    fn dress(&self, _scene: &mut Scene) {}

    /// The phenotype text of the last decoding (GE).
    fn phenotype<'s>(&self, _scratch: &'s DecodeScratch) -> Option<&'s str> {
        None
    }

    /// The GE mapper of this scratch, for the optimizer's grammar-aware
    /// operators (read prefix, phenotype keys, subtrees, sensible
    /// initialisation); `None` for decoders without a grammar to map.
    fn mapper<'s>(&self, _scratch: &'s mut DecodeScratch) -> Option<&'s mut genform_ge::Mapper> {
        None
    }
}

/// Why an individual is invalid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Invalid {
    /// The mapper needed a codon after its last wrap.
    WrapLimit,
    /// The derivation tree passed `[mapper] max_depth` (standard GE).
    DepthLimit,
    /// The genome has no codons.
    EmptyGenome,
    /// Genr8's repair needed too many rules.
    RepairLimit,
    /// The phenotype text does not parse (`.gr8` or `.ls` errors).
    Parse,
    /// Growth or drawing failed (a rule that cannot apply, a non-finite
    /// coordinate).
    Growth,
    /// The model grew past a `[limits]` element limit.
    ElementLimit,
    /// Box-split and graph grammars: the codons ran out (after the wraps).
    Exhausted,
    /// Box-split and graph grammars: the derivation itself failed.
    Derivation,
}

impl Invalid {
    /// Every reason, in report order.
    pub const ALL: [Invalid; 9] = [
        Invalid::WrapLimit,
        Invalid::DepthLimit,
        Invalid::EmptyGenome,
        Invalid::RepairLimit,
        Invalid::Parse,
        Invalid::Growth,
        Invalid::ElementLimit,
        Invalid::Exhausted,
        Invalid::Derivation,
    ];

    /// The name in logs, `stats.csv` and `run.json`, e.g. `wrap_limit`.
    pub fn name(self) -> &'static str {
        match self {
            Invalid::WrapLimit => "wrap_limit",
            Invalid::DepthLimit => "depth_limit",
            Invalid::EmptyGenome => "empty_genome",
            Invalid::RepairLimit => "repair_limit",
            Invalid::Parse => "parse",
            Invalid::Growth => "growth",
            Invalid::ElementLimit => "element_limit",
            Invalid::Exhausted => "exhausted",
            Invalid::Derivation => "derivation",
        }
    }

    /// Its position in [`Invalid::ALL`].
    pub(crate) fn index(self) -> usize {
        Invalid::ALL.iter().position(|r| *r == self).unwrap_or(0)
    }

    /// The reason of a failed GE mapping.
    pub(crate) fn of_mapping(f: genform_ge::Failure) -> Invalid {
        match f {
            genform_ge::Failure::WrapLimit => Invalid::WrapLimit,
            genform_ge::Failure::DepthLimit => Invalid::DepthLimit,
            genform_ge::Failure::EmptyGenome => Invalid::EmptyGenome,
            genform_ge::Failure::RepairLimit => Invalid::RepairLimit,
        }
    }
}

/// An invalid individual: the reason and, when asked for, what exactly
/// went wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct Rejection {
    /// Why.
    pub reason: Invalid,
    /// The error in words (empty on the fast evaluation path).
    pub message: String,
}

/// A rejection for `reason`, its message made only when `detail`.
pub(crate) fn reject(reason: Invalid, detail: bool, message: impl FnOnce() -> String) -> Rejection {
    Rejection { reason, message: if detail { message() } else { String::new() } }
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.message.is_empty() {
            f.write_str(self.reason.name())
        } else {
            write!(f, "{}: {}", self.reason.name(), self.message)
        }
    }
}

/// Counts of invalid evaluations by [`Invalid`] reason.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InvalidCounts(pub [u64; 9]);

impl InvalidCounts {
    /// The count of `reason`.
    pub fn get(&self, reason: Invalid) -> u64 {
        self.0[reason.index()]
    }

    /// All of them.
    pub fn total(&self) -> u64 {
        self.0.iter().sum()
    }

    /// `(name, count)` of the reasons that occurred, in report order.
    pub fn nonzero(&self) -> impl Iterator<Item = (&'static str, u64)> + '_ {
        Invalid::ALL.iter().map(|r| (r.name(), self.get(*r))).filter(|(_, n)| *n > 0)
    }
}

impl std::ops::AddAssign for InvalidCounts {
    fn add_assign(&mut self, o: InvalidCounts) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }
}

impl fmt::Display for InvalidCounts {
    /// `parse 3, element_limit 2`, or `none`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self.nonzero().map(|(n, c)| format!("{n} {c}")).collect();
        if parts.is_empty() { f.write_str("none") } else { f.write_str(&parts.join(", ")) }
    }
}

/// The rejection of a derivation whose codons ran out (after their
/// wraps), if they did.
pub(crate) fn exhausted(codons: &[u32], source: &genform_core::CodonSource, detail: bool) -> Option<Rejection> {
    source.exhausted().then(|| {
        reject(Invalid::Exhausted, detail, || {
            format!("the {} codons ran out after {} wraps", codons.len(), source.wraps())
        })
    })
}

/// What a derivation that took its choices from `source` read.
pub(crate) fn read_from(source: &genform_core::CodonSource) -> Decoded {
    Decoded { codons_read: source.used(), wraps: source.wraps(), grammar_file: None }
}

/// Reads a codon genome: `best-codons.json` (an object with `codons`) or a
/// bare JSON array of codons.
pub fn read_codons(path: &std::path::Path) -> Result<Vec<u32>> {
    let text = crate::text::read_text(path, "genome")?;
    let value: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))?;
    let list = match &value {
        serde_json::Value::Array(_) => &value,
        serde_json::Value::Object(o) => o.get("codons").ok_or_else(|| {
            anyhow!("{} has no `codons` list (is it a best-codons.json of a codon scene?)", path.display())
        })?,
        _ => return Err(anyhow!("{}: expected a list of codons or an object with `codons`", path.display())),
    };
    serde_json::from_value(list.clone())
        .with_context(|| format!("{}: `codons` must be a list of non-negative integers below 2³²", path.display()))
}

/// The stem phenotypes are parsed under: it names the surface tag and the
/// L-system, as `genform sample best.gr8` / `best.ls` would.
pub(crate) const PHENOTYPE_STEM: &str = "best";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_counts_add_and_print() {
        let mut a = InvalidCounts::default();
        assert_eq!(a.to_string(), "none");
        a.0[Invalid::Parse.index()] = 3;
        let mut b = InvalidCounts::default();
        b.0[Invalid::WrapLimit.index()] = 2;
        b.0[Invalid::Parse.index()] = 1;
        a += b;
        assert_eq!((a.total(), a.get(Invalid::Parse)), (6, 4));
        assert_eq!(a.to_string(), "wrap_limit 2, parse 4");
        let names: Vec<&str> = Invalid::ALL.iter().map(|r| r.name()).collect();
        assert_eq!(names.len(), 9);
        assert!(names.iter().all(|n| names.iter().filter(|m| *m == n).count() == 1));
    }

    #[test]
    fn codons_are_read_from_an_object_or_a_list() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.json");
        std::fs::write(&p, r#"{"fitness": 1.5, "codons": [3, 999, 0]}"#).unwrap();
        assert_eq!(read_codons(&p).unwrap(), vec![3, 999, 0]);
        std::fs::write(&p, "[7, 8]").unwrap();
        assert_eq!(read_codons(&p).unwrap(), vec![7, 8]);
        std::fs::write(&p, r#"{"genome": []}"#).unwrap();
        assert!(read_codons(&p).unwrap_err().to_string().contains("no `codons`"));
        std::fs::write(&p, "[-1]").unwrap();
        assert!(format!("{:#}", read_codons(&p).unwrap_err()).contains("non-negative"));
    }
}
