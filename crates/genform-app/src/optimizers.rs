//! The optimizer table: every search algorithm a door can ask for
//! ([`OPTIMIZERS`]: its name, what it is, the genomes it searches, the
//! scene section holding its settings, whether `compare` runs it by
//! default, its plot colour) and every settings section of a scene
//! ([`SECTIONS`]: how it is read and checked, with positions, and what
//! memory it asks for). The command line's `--algorithm` values, the
//! studio's lists, `compare`'s defaults, Python's keyword sections and the
//! memory checks all read these two tables.
//!
//! Adding an optimizer of genform-evolve is one row of [`OPTIMIZERS`] (and
//! a row of [`SECTIONS`] when it brings a settings table).

use anyhow::{Result, anyhow};
use genform_evolve::{
    CodonAlgorithm, ConfigError, GaConfig, GeConfig, HybridConfig, MapElitesConfig, MhConfig, SmcConfig,
};
use genform_score::Descriptor;
use serde::Serialize;

use crate::memory::{GENE_BYTES, INDIVIDUAL_BYTES, Size, estimate, human};
use crate::toml_doc::{Doc, Value};

/// The genomes an optimizer searches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Searches {
    /// Derivation trees over a generator graph.
    Trees,
    /// Codon lists.
    Codons,
}

/// Which optimizer of genform-evolve a row starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// A derivation-tree optimizer.
    Tree(genform_evolve::Algorithm),
    /// A codon optimizer.
    Codon(CodonAlgorithm),
}

/// A row of the optimizer table.
#[derive(Debug)]
pub struct OptimizerRow {
    pub(crate) kind: Kind,
    /// One line on what it is (help texts, the studio).
    pub about: &'static str,
    /// The scene table holding its settings.
    pub section: &'static str,
    /// Whether `compare` runs it when no algorithms are named.
    pub compare: bool,
    /// Its colour in comparison plots.
    pub color: &'static str,
}

impl OptimizerRow {
    /// The name on the command line and in `run.json`.
    pub fn name(&self) -> &'static str {
        match self.kind {
            Kind::Tree(a) => a.name(),
            Kind::Codon(a) => a.name(),
        }
    }

    /// The genomes it searches.
    pub fn searches(&self) -> Searches {
        match self.kind {
            Kind::Tree(_) => Searches::Trees,
            Kind::Codon(_) => Searches::Codons,
        }
    }
}

/// Every optimizer. A name may appear once per kind of genome (`random`
/// searches either).
pub static OPTIMIZERS: &[OptimizerRow] = &[
    OptimizerRow {
        kind: Kind::Tree(genform_evolve::Algorithm::Ga),
        about: "The ShapeGenetics genetic algorithm",
        section: "ga",
        compare: true,
        color: "#1f77b4",
    },
    OptimizerRow {
        kind: Kind::Tree(genform_evolve::Algorithm::Mh),
        about: "RJMCMC with parallel tempering, delayed rejection and annealing",
        section: "mh",
        compare: true,
        color: "#2ca02c",
    },
    OptimizerRow {
        kind: Kind::Tree(genform_evolve::Algorithm::Smc),
        about: "Sequential Monte Carlo, fixed (depth-first) growth order",
        section: "smc",
        compare: true,
        color: "#d62728",
    },
    OptimizerRow {
        kind: Kind::Tree(genform_evolve::Algorithm::Sosmc),
        about: "Stochastically-ordered SMC",
        section: "smc",
        compare: true,
        color: "#ff7f0e",
    },
    OptimizerRow {
        kind: Kind::Tree(genform_evolve::Algorithm::Hybrid),
        about: "SOSMC seeds a GA, MH polishes its best",
        section: "hybrid",
        compare: false,
        color: "#9467bd",
    },
    OptimizerRow {
        kind: Kind::Tree(genform_evolve::Algorithm::MapElites),
        about: "MAP-Elites: the best individual per cell of a grid over two descriptors (quality-diversity)",
        section: "map_elites",
        compare: false,
        color: "#7f7f7f",
    },
    OptimizerRow {
        kind: Kind::Tree(genform_evolve::Algorithm::Random),
        about: "Random search: fresh random individuals, keep the best (a baseline)",
        section: "ga",
        compare: false,
        color: "#7f7f7f",
    },
    OptimizerRow {
        kind: Kind::Codon(CodonAlgorithm::Ge),
        about: "Grammatical evolution over codon genomes (codon scenes: .bnf, .bsg, .gg.yaml grammars)",
        section: "ge",
        compare: true,
        color: "#17becf",
    },
    OptimizerRow {
        kind: Kind::Codon(CodonAlgorithm::Random),
        about: "Random search: fresh random individuals, keep the best (a baseline)",
        section: "ge",
        compare: true,
        color: "#7f7f7f",
    },
];

/// Every algorithm name once, in table order, with what it is.
pub fn algorithm_names() -> Vec<(&'static str, &'static str)> {
    let mut out: Vec<(&'static str, &'static str)> = Vec::new();
    for row in OPTIMIZERS {
        if !out.iter().any(|(n, _)| *n == row.name()) {
            out.push((row.name(), row.about));
        }
    }
    out
}

/// The names of the algorithms that search `genomes`, in table order.
pub fn names_for(genomes: Searches) -> Vec<&'static str> {
    OPTIMIZERS.iter().filter(|r| r.searches() == genomes).map(|r| r.name()).collect()
}

/// The optimizer called `name` (`map_elites` and `map-elites` both work)
/// that searches `genomes`; an unknown name lists them all, a name of the
/// other kind says which it searches.
pub(crate) fn find(name: &str, genomes: Searches, scene: &std::path::Path) -> Result<&'static OptimizerRow> {
    let wanted = name.replace('_', "-").to_ascii_lowercase();
    if let Some(row) = OPTIMIZERS.iter().find(|r| r.name() == wanted && r.searches() == genomes) {
        return Ok(row);
    }
    if OPTIMIZERS.iter().any(|r| r.name() == wanted) {
        let ours = names_for(genomes).join(", ");
        return Err(match genomes {
            Searches::Trees => anyhow!(
                "--algorithm {wanted} evolves codon genomes, but {} is a tree scene (its grammar's genomes are \
                 derivation trees); use {ours}, or a scene whose grammar is .bnf, .bsg or .gg.yaml",
                scene.display()
            ),
            Searches::Codons => anyhow!(
                "--algorithm {wanted} searches derivation trees, but {} is a codon scene (its genomes are codon \
                 lists); use --algorithm {}",
                scene.display(),
                names_for(genomes).join(" or ")
            ),
        });
    }
    check_name(name)?;
    Err(anyhow!("no optimizer `{wanted}` searches these genomes"))
}

/// Refuses a name that is no algorithm, listing the algorithms.
pub fn check_name(name: &str) -> Result<()> {
    let wanted = name.replace('_', "-").to_ascii_lowercase();
    if OPTIMIZERS.iter().any(|r| r.name() == wanted) {
        return Ok(());
    }
    let names: Vec<&str> = algorithm_names().into_iter().map(|(n, _)| n).collect();
    Err(anyhow!("unknown algorithm `{name}`; use one of {}", names.join(", ")))
}

/// The default algorithm of a scene searching `genomes` (the first row).
pub(crate) fn default_for(genomes: Searches) -> &'static OptimizerRow {
    OPTIMIZERS.iter().find(|r| r.searches() == genomes).expect("every kind of genome has an optimizer")
}

/// Plot colour of an algorithm by name.
pub(crate) fn color(name: &str) -> &'static str {
    OPTIMIZERS.iter().find(|r| r.name() == name).map_or("#7f7f7f", |r| r.color)
}

/// The optimizer settings of a scene: every section of [`SECTIONS`].
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct OptimizerSettings {
    /// `[ga]` (also random search and MAP-Elites' lengths and operators).
    pub ga: GaConfig,
    /// `[mh]`; absent, the chains take their lengths from `[ga]`.
    pub mh: Option<MhConfig>,
    /// `[smc]`; absent, `max_length` follows `[ga]`.
    pub smc: Option<SmcConfig>,
    /// `[hybrid]`.
    pub hybrid: HybridConfig,
    /// `[map_elites]`; unset descriptor ranges take their defaults.
    pub map_elites: MapElitesConfig,
    /// `[ge]` (codon scenes; random search takes its batch size, lengths
    /// and codon range from here too).
    pub ge: GeConfig,
}

impl OptimizerSettings {
    /// The settings of every tree algorithm: absent `[mh]` and `[smc]`
    /// take their defaults with the genome lengths of `[ga]`, unset
    /// `[map_elites]` ranges the descriptors' defaults (`box_size`: the
    /// volume grid's sides, if any).
    pub fn tree(&self, box_size: Option<[f64; 3]>) -> genform_evolve::Settings {
        let ga = &self.ga;
        let mh = self.mh.clone().unwrap_or_else(|| MhConfig {
            initial_length: ga.initial_length,
            min_length: ga.min_length,
            max_length: ga.max_length,
            ..Default::default()
        });
        let smc = self.smc.clone().unwrap_or_else(|| SmcConfig { max_length: ga.max_length, ..Default::default() });
        genform_evolve::Settings {
            ga: ga.clone(),
            mh,
            smc,
            hybrid: self.hybrid.clone(),
            map_elites: self.map_elites(box_size),
        }
    }

    /// `[map_elites]` with every unset descriptor range filled in by
    /// [`Descriptor::default_range`].
    pub fn map_elites(&self, box_size: Option<[f64; 3]>) -> MapElitesConfig {
        let mut config = self.map_elites.clone();
        for axis in &mut config.descriptors {
            if let (None, Some(d)) = (axis.range, Descriptor::from_name(&axis.name)) {
                axis.range = Some(d.default_range([self.ga.min_length, self.ga.max_length], box_size));
            }
        }
        config
    }

    /// The two descriptors `[map_elites]` names (checked when the scene
    /// loads).
    pub fn descriptors(&self) -> [Descriptor; 2] {
        self.map_elites.descriptors.each_ref().map(|d| Descriptor::from_name(&d.name).unwrap_or(Descriptor::Length))
    }

    /// The genome length bounds of the optimizers searching `genomes`
    /// (the `[fitness]` length range's default).
    pub fn lengths(&self, genomes: Searches) -> [f64; 2] {
        match genomes {
            Searches::Trees => [self.ga.min_length as f64, self.ga.max_length as f64],
            Searches::Codons => [self.ge.initial_length[0] as f64, self.ge.max_length as f64],
        }
    }

    /// The shortest genome the optimizers searching `genomes` make (for
    /// the fitness a run can reach).
    pub fn shortest(&self, genomes: Searches) -> usize {
        match genomes {
            Searches::Trees => self.ga.min_length,
            Searches::Codons => self.ge.initial_length[0],
        }
    }
}

/// A settings section of a scene: how it is read, checked and sized.
pub(crate) struct SettingsSection {
    /// Its name, e.g. `ga`.
    pub name: &'static str,
    /// The genomes its optimizers search.
    pub searches: Searches,
    /// Reads the section into the settings.
    read: fn(&Doc, &Value, &mut OptimizerSettings) -> Result<()>,
    /// Checks the settings it owns (with every other section read).
    check: fn(&OptimizerSettings) -> Result<(), ConfigError>,
    /// The sizes it asks for.
    memory: fn(&OptimizerSettings) -> Vec<Size<'static>>,
    /// The section as `run.json` echoes it.
    echo: fn(&OptimizerSettings) -> serde_json::Value,
}

/// Every settings section.
pub(crate) static SECTIONS: &[SettingsSection] = &[
    SettingsSection {
        name: "ga",
        searches: Searches::Trees,
        read: |doc, v, s| {
            s.ga = doc.read(v)?;
            Ok(())
        },
        check: |s| s.ga.validate(),
        memory: |s| vec![members("ga", "population", s.ga.population, tree_genome(s.ga.initial_length[1]))],
        // As a run ran it: `elitism` written out (a fifth of the population
        // when left out).
        echo: |s| {
            let mut ga = s.ga.clone();
            ga.elitism = Some(ga.elites());
            json(&ga)
        },
    },
    SettingsSection {
        name: "mh",
        searches: Searches::Trees,
        read: |doc, v, s| {
            s.mh = Some(doc.read(v)?);
            Ok(())
        },
        check: |s| s.tree(None).mh.validate(),
        memory: |s| {
            let mh = s.mh.iter();
            mh.map(|m| members("mh", "chains", m.chains, tree_genome(m.initial_length[1]))).collect()
        },
        echo: |s| json(&s.mh),
    },
    SettingsSection {
        name: "smc",
        searches: Searches::Trees,
        read: |doc, v, s| {
            s.smc = Some(doc.read(v)?);
            Ok(())
        },
        check: |s| s.tree(None).smc.validate(),
        memory: |s| s.smc.iter().map(|m| members("smc", "particles", m.particles, tree_genome(m.max_length))).collect(),
        echo: |s| json(&s.smc),
    },
    SettingsSection {
        name: "hybrid",
        searches: Searches::Trees,
        read: |doc, v, s| {
            s.hybrid = doc.read(v)?;
            Ok(())
        },
        check: |s| s.hybrid.validate(),
        memory: |_| Vec::new(),
        echo: |s| json(&s.hybrid),
    },
    SettingsSection {
        name: "map_elites",
        searches: Searches::Trees,
        read: |doc, v, s| {
            s.map_elites = doc.read(v)?;
            Ok(())
        },
        // Ranges left out are filled in from the GA's lengths (and the
        // volume grid, which a check cannot make them invalid for).
        check: |s| s.map_elites(None).validate_ranges(),
        memory: |s| {
            let me = &s.map_elites;
            let cells = me.descriptors.iter().fold(1u128, |n, d| n.saturating_mul(d.bins as u128));
            let cell_bytes = u128::from(tree_genome(s.ga.max_length));
            vec![
                Size {
                    section: "map_elites",
                    key: "descriptors",
                    value: cells,
                    bytes: cells.saturating_mul(cell_bytes),
                    what: format!("an archive of {cells} cells, each up to a genome of {}", human(cell_bytes as f64)),
                },
                members("map_elites", "initial", me.initial, tree_genome(s.ga.initial_length[1])),
                members("map_elites", "batch", me.batch, tree_genome(s.ga.max_length)),
            ]
        },
        echo: |s| json(&s.map_elites),
    },
    SettingsSection {
        name: "ge",
        searches: Searches::Codons,
        read: |doc, v, s| {
            s.ge = doc.read(v)?;
            Ok(())
        },
        check: |s| s.ge.validate(),
        memory: |s| {
            let ge = &s.ge;
            let each = INDIVIDUAL_BYTES.saturating_add((ge.initial_length[1] as u64).saturating_mul(4));
            vec![Size {
                section: "ge",
                key: "population",
                value: ge.population as u128,
                bytes: estimate(ge.population as u64, each).saturating_mul(2),
                what: format!("2 × {} codon genomes of about {} each", ge.population, human(each as f64)),
            }]
        },
        echo: |s| json(&s.ge),
    },
];

/// `value` as JSON.
fn json<T: Serialize>(value: &T) -> serde_json::Value {
    serde_json::to_value(value).unwrap_or_default()
}

/// Bytes of a tree genome of up to `genes` genes.
fn tree_genome(genes: usize) -> u64 {
    INDIVIDUAL_BYTES.saturating_add((genes as u64).saturating_mul(GENE_BYTES))
}

/// The size of `n` members of `each` bytes: each optimizer holds about two
/// genomes per member (parents and children, current and proposal,
/// particles and their resampling).
fn members(section: &'static str, key: &'static str, n: usize, each: u64) -> Size<'static> {
    Size {
        section,
        key,
        value: n as u128,
        bytes: estimate(n as u64, each).saturating_mul(2),
        what: format!(
            "2 × {n} genomes of up to {} genes, about {} each",
            (each - INDIVIDUAL_BYTES) / GENE_BYTES,
            human(each as f64)
        ),
    }
}

/// The sizes every settings section of `searches` asks for.
pub(crate) fn sizes(searches: Searches, settings: &OptimizerSettings) -> Vec<Size<'static>> {
    SECTIONS.iter().filter(|s| s.searches == searches).flat_map(|s| s.memory(settings)).collect()
}

/// The sizes the settings section `name` asks for.
pub(crate) fn section_sizes(name: &str, settings: &OptimizerSettings) -> Vec<Size<'static>> {
    SECTIONS.iter().filter(|s| s.name == name).flat_map(|s| s.memory(settings)).collect()
}

impl SettingsSection {
    /// Reads this section of `doc` into `settings`.
    pub(crate) fn read(&self, doc: &Doc, value: &Value, settings: &mut OptimizerSettings) -> Result<()> {
        (self.read)(doc, value, settings)
    }

    /// Checks this section's settings; a refusal names the refused key's
    /// position.
    pub(crate) fn check(&self, doc: &Doc, settings: &OptimizerSettings) -> Result<()> {
        if self.name == "map_elites" {
            check_descriptor_names(doc, &settings.map_elites)?;
        }
        (self.check)(settings).map_err(|e| {
            let key = e.key();
            let mut path = vec![self.name];
            path.extend(key.split('.'));
            doc.refuse(&path, format!("[{}] {e}", self.name))
        })
    }

    /// The sizes this section asks for.
    pub(crate) fn memory(&self, settings: &OptimizerSettings) -> Vec<Size<'static>> {
        (self.memory)(settings)
    }

    /// The section as `run.json` echoes it.
    pub(crate) fn echo(&self, settings: &OptimizerSettings) -> serde_json::Value {
        (self.echo)(settings)
    }
}

/// Refuses a `[map_elites]` descriptor that is not a [`Descriptor`], at
/// its position, with a did-you-mean.
fn check_descriptor_names(doc: &Doc, config: &MapElitesConfig) -> Result<()> {
    let names = Descriptor::ALL.map(|(n, _)| n);
    for (i, d) in config.descriptors.iter().enumerate() {
        if Descriptor::from_name(&d.name).is_none() {
            let index = i.to_string();
            let hint = genform_core::expr::did_you_mean(&d.name, names)
                .map(|n| format!("did you mean `{n}`? "))
                .unwrap_or_default();
            return Err(doc.refuse(
                &["map_elites", "descriptors", &index, "name"],
                format!(
                    "[map_elites] descriptor `{}` is unknown; {hint}the descriptors are {}",
                    d.name,
                    names.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_per_kind_of_genome_and_every_kind_has_a_default() {
        for (i, a) in OPTIMIZERS.iter().enumerate() {
            for b in &OPTIMIZERS[i + 1..] {
                assert!(a.name() != b.name() || a.searches() != b.searches(), "{} twice", a.name());
            }
            assert!(SECTIONS.iter().any(|s| s.name == a.section), "{}: no section [{}]", a.name(), a.section);
        }
        assert_eq!(default_for(Searches::Trees).name(), "ga");
        assert_eq!(default_for(Searches::Codons).name(), "ge");
        assert_eq!(names_for(Searches::Codons), ["ge", "random"]);
        let names: Vec<&str> = algorithm_names().into_iter().map(|(n, _)| n).collect();
        assert_eq!(names, ["ga", "mh", "smc", "sosmc", "hybrid", "map-elites", "random", "ge"]);
    }

    #[test]
    fn names_are_found_for_their_genomes_only() {
        let scene = std::path::Path::new("s.toml");
        assert_eq!(find("map_elites", Searches::Trees, scene).unwrap().name(), "map-elites");
        assert_eq!(find("random", Searches::Codons, scene).unwrap().searches(), Searches::Codons);
        let e = find("ge", Searches::Trees, scene).unwrap_err().to_string();
        assert!(e.contains("evolves codon genomes") && e.contains("s.toml is a tree scene"), "{e}");
        let e = find("mh", Searches::Codons, scene).unwrap_err().to_string();
        assert!(e.contains("use --algorithm ge or random"), "{e}");
        let e = find("gaa", Searches::Trees, scene).unwrap_err().to_string();
        assert!(e.starts_with("unknown algorithm `gaa`; use one of ga, mh"), "{e}");
    }
}
