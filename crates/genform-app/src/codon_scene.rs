//! Codon scenes: scene configs whose grammar is driven by a GE codon genome.
//!
//! A scene is a *codon scene* when its `grammar` is
//!
//! - a `.bnf` file (grammatical evolution): codons are mapped through the
//!   BNF (`genform-ge`) into phenotype text in the language `phenotype`
//!   names — `"gr8"` (a HEMLS rewrite system, grown in `environment` for
//!   `steps` steps and scored by the `[surface]` criteria) or `"ls"` (an
//!   L-system, derived and drawn, scored by `[volume]`/`[[image]]`);
//! - a `.bsg` box-split grammar (derived in `box`) or a `.gg.yaml` graph
//!   grammar: codons are the grammar's choice source
//!   ([`genform_core::CodonSource`]), scored by `[volume]`/`[[image]]`.
//!
//! Every other grammar makes a tree scene ([`crate::scene_config`]). Both
//! kinds share `[volume]`, `[[image]]`, `[fitness]` and `[run]`; codon
//! scenes add `[ge]` ([`genform_evolve::GeConfig`]), `[mapper]` and
//! `[limits]` (their own keys), and refuse the tree scenes' `[ga]`, `[mh]`,
//! `[smc]` and `[hybrid]` as unknown keys, with the file and line.

use anyhow::{Context, Result, bail};
use genform_evolve::GeConfig;
use genform_score::SurfaceObjective;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use crate::formalism::ends_with_any;
use crate::scene_config::{FitnessConfig, ImageConfig, RunConfig, SceneConfig, VolumeConfig, read_scene};

/// Grammar endings that make a codon scene.
pub const CODON_GRAMMARS: &[&str] = &[".bnf", ".bsg", ".gg.yaml"];

/// The language a `.bnf` grammar writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Phenotype {
    /// A HEMLS rewrite system (`.gr8`), grown into a surface.
    Gr8,
    /// An L-system (`.ls`), derived and drawn with the turtle.
    Ls,
}

impl Phenotype {
    /// The file ending of the phenotype, e.g. `gr8`.
    pub fn extension(self) -> &'static str {
        match self {
            Phenotype::Gr8 => "gr8",
            Phenotype::Ls => "ls",
        }
    }
}

/// What turns codons into a model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CodonKind {
    /// Grammatical evolution: a `.bnf` mapped into phenotype text.
    Ge(Phenotype),
    /// A box-split grammar with codons as its choices.
    BoxSplit,
    /// A graph grammar with codons as its choices.
    Graph,
}

/// `[mapper]`: how codons are read.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MapperConfig {
    /// How often reading may wrap back to the first codon (GE default: 4
    /// with Genr8's extensions, else 2; box-split and graph grammars: 2).
    #[serde(default)]
    pub max_wraps: Option<u32>,
    /// GE only. With Genr8's extensions: the derivation-tree depth from
    /// which only productions without non-terminals are chosen (default 8);
    /// without them: the depth past which an individual is invalid
    /// (default none).
    #[serde(default)]
    pub max_depth: Option<u32>,
    /// GE only: Genr8's mapping extensions (`{ }` and `[ ]` decided by
    /// codons, Edge IDs, EdgeX/Y/Z binding, depth-limited choice, repair,
    /// spaced tokens). Default: on for `phenotype = "gr8"`, off for `"ls"`.
    #[serde(default)]
    pub genr8: Option<bool>,
    /// GE only: which codon each decision reads, `"sequential"` (standard
    /// GE, the default) or `"per-choice"` (one interleaved stream per
    /// non-terminal, group and edge IDs; [`genform_ge::CodonLayout`]).
    #[serde(default)]
    pub layout: Option<genform_ge::CodonLayout>,
}

/// `[limits]` of a codon scene: what an individual may grow to before it
/// is invalid (`element_limit`). Each replaces the default when given.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CodonLimits {
    /// gr8: most surface vertices (default: the environment file's).
    #[serde(default)]
    pub vertices: Option<usize>,
    /// gr8: most surface edges (default: the environment file's).
    #[serde(default)]
    pub edges: Option<usize>,
    /// gr8: most surface faces (default: the environment file's).
    #[serde(default)]
    pub faces: Option<usize>,
    /// ls: longest module string (default 200,000).
    #[serde(default)]
    pub modules: Option<usize>,
    /// ls: most drawn primitives (default 20,000).
    #[serde(default)]
    pub primitives: Option<usize>,
    /// Graph grammars: most vertices + edges (default 20,000).
    #[serde(default)]
    pub elements: Option<usize>,
}

/// The whole codon scene file, as written.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CodonSceneConfig {
    /// `.bnf`, `.bsg` or `.gg.yaml`, relative to the scene.
    pub grammar: PathBuf,
    /// A one-line description.
    #[serde(default)]
    pub description: String,
    /// `.bnf` only: the language the grammar writes.
    #[serde(default)]
    pub phenotype: Option<Phenotype>,
    /// gr8: the growth environment (settings, charges, boundaries, limits).
    #[serde(default)]
    pub environment: Option<PathBuf>,
    /// gr8: growth steps (overrides the environment's); graph grammars:
    /// the derivation's step limit (overrides the grammar's `steps:`).
    #[serde(default)]
    pub steps: Option<u32>,
    /// Box-split grammars: the box to derive in, two opposite corners
    /// (inclusive) `[x0, y0, z0, x1, y1, z1]`.
    #[serde(default, rename = "box")]
    pub box_corners: Option<[i32; 6]>,
    /// The GE optimizer's settings (random search takes its batch size,
    /// lengths and codon range from here too).
    #[serde(default)]
    pub ge: GeConfig,
    /// How codons are read.
    #[serde(default)]
    pub mapper: MapperConfig,
    /// gr8: Genr8's six surface criteria.
    #[serde(default)]
    pub surface: Option<SurfaceObjective>,
    /// ls, box-split, graph: a voxel target.
    #[serde(default)]
    pub volume: Option<VolumeConfig>,
    /// ls, box-split, graph: silhouette targets.
    #[serde(default)]
    pub image: Vec<ImageConfig>,
    /// ls, box-split, graph: fitness constants; the length term counts codons.
    #[serde(default)]
    pub fitness: FitnessConfig,
    /// Growth limits.
    #[serde(default)]
    pub limits: CodonLimits,
    /// When to stop (flags override it).
    #[serde(default)]
    pub run: RunConfig,
}

/// A loaded codon scene with its paths resolved.
#[derive(Clone, Debug)]
pub struct LoadedCodonScene {
    /// The scene file.
    pub path: PathBuf,
    /// What decodes its genomes.
    pub kind: CodonKind,
    /// Its contents, paths resolved against the scene's folder.
    pub config: CodonSceneConfig,
}

/// Whether the scene at `path` is a codon scene (its `grammar` ends with
/// one of [`CODON_GRAMMARS`]). A file that cannot be read or parsed is
/// not: the tree-scene loader then reports the problem.
pub fn is_codon_scene(path: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(path) else { return false };
    let Ok(table) = text.parse::<toml::Table>() else { return false };
    table.get("grammar").and_then(|g| g.as_str()).is_some_and(|g| ends_with_any(Path::new(g), CODON_GRAMMARS))
}

/// The flat `.bsg` box `[x0, y0, z0, x1, y1, z1]` as `min..max_exclusive`.
pub fn box_bounds(c: [i32; 6]) -> (glam::IVec3, glam::IVec3) {
    let a = glam::IVec3::new(c[0], c[1], c[2]);
    let b = glam::IVec3::new(c[3], c[4], c[5]);
    (a.min(b), a.max(b) + glam::IVec3::ONE)
}

impl CodonSceneConfig {
    /// Reads, parses and checks the codon scene at `path`.
    pub fn load(path: &Path) -> Result<LoadedCodonScene> {
        let (config, base) = read_scene::<CodonSceneConfig>(path)?;
        CodonSceneConfig::checked(path, base, config)
    }

    /// [`CodonSceneConfig::load`] with a settings patch applied first (the
    /// scene as written is checked first, so its own mistakes keep their
    /// positions).
    pub fn load_patched(path: &Path, patch: &[crate::sweep::set::Axis]) -> Result<LoadedCodonScene> {
        let loaded = CodonSceneConfig::load(path)?;
        if patch.is_empty() {
            return Ok(loaded);
        }
        let text = crate::source_text::read_text(path, "scene")?;
        let text = crate::sweep::set::patched_text::<CodonSceneConfig>(path, &text, patch)?;
        let config = crate::scene_config::parse_toml(path, &text)?;
        CodonSceneConfig::checked(path, path.parent().unwrap_or(Path::new(".")), config)
    }

    /// `config` read from `path` with its paths resolved against `base`, checked.
    fn checked(path: &Path, base: &Path, mut config: CodonSceneConfig) -> Result<LoadedCodonScene> {
        config.resolve(base);
        let kind = config.check().with_context(|| format!("in scene {}", path.display()))?;
        crate::memory::check_sizes(path, None, &config.memory_sizes())?;
        Ok(LoadedCodonScene { path: path.to_path_buf(), kind, config })
    }

    fn resolve(&mut self, base: &Path) {
        self.grammar = base.join(&self.grammar);
        if let Some(env) = &mut self.environment {
            *env = base.join(&*env);
        }
        // The shared target sections resolve like a tree scene's.
        let mut view = self.targets_view();
        view.resolve(base);
        self.volume = view.volume;
        self.image = view.image;
    }

    /// The scene's targets as a tree-scene config, for the shared target
    /// builder and checks; the fitness length range defaults to the GE
    /// genome lengths (initial minimum to `max_length`).
    pub fn targets_view(&self) -> SceneConfig {
        let mut fitness = self.fitness.clone();
        if fitness.length_range.is_none() {
            fitness.length_range = Some([self.ge.initial_length[0] as f64, self.ge.max_length as f64]);
        }
        SceneConfig {
            grammar: self.grammar.clone(),
            description: self.description.clone(),
            volume: self.volume.clone(),
            image: self.image.clone(),
            fitness,
            ga: Default::default(),
            mh: None,
            smc: None,
            hybrid: Default::default(),
            map_elites: Default::default(),
            run: self.run.clone(),
            limits: Default::default(),
        }
    }

    /// The sizes this scene asks for, checked against the memory budget
    /// (see [`crate::memory`]): the GE population (parents and children,
    /// each up to `initial_length`'s upper end of 4-byte codons; random
    /// search draws as many) and the targets.
    pub fn memory_sizes(&self) -> Vec<crate::memory::Size<'static>> {
        use crate::memory::{INDIVIDUAL_BYTES, Size, estimate, human};
        let ge = &self.ge;
        let each = INDIVIDUAL_BYTES.saturating_add((ge.initial_length[1] as u64).saturating_mul(4));
        let mut sizes = vec![Size {
            section: "ge",
            key: "population",
            value: ge.population as u128,
            bytes: estimate(ge.population as u64, each).saturating_mul(2),
            what: format!("2 × {} codon genomes of about {} each", ge.population, human(each as f64)),
        }];
        sizes.extend(crate::scene_config::target_sizes(self.volume.as_ref(), &self.image));
        let l = &self.limits;
        let primitive = crate::scene_config::PRIMITIVE_BYTES;
        sizes.extend(crate::memory::limit_sizes(&[
            ("vertices", l.vertices, 64, "surface vertices"),
            ("edges", l.edges, 64, "surface half-edge pairs"),
            ("faces", l.faces, 32, "surface faces"),
            ("modules", l.modules, 32, "L-system modules"),
            ("primitives", l.primitives, primitive, "primitives"),
            ("elements", l.elements, 64, "graph vertices and edges"),
        ]));
        sizes
    }

    /// Whether the scene scores by volume or image targets (not `[surface]`).
    fn has_targets(&self) -> bool {
        self.volume.is_some() || !self.image.is_empty()
    }

    /// Checks what belongs together and returns the decoder kind.
    fn check(&self) -> Result<CodonKind> {
        let g = &self.grammar;
        let kind = if ends_with_any(g, &[".bnf"]) {
            let Some(p) = self.phenotype else {
                bail!("a .bnf grammar needs `phenotype = \"gr8\"` or `phenotype = \"ls\"`: the language it writes");
            };
            CodonKind::Ge(p)
        } else if ends_with_any(g, &[".bsg"]) {
            CodonKind::BoxSplit
        } else if ends_with_any(g, &[".gg.yaml"]) {
            CodonKind::Graph
        } else {
            bail!("grammar {} is not a codon grammar ({})", g.display(), CODON_GRAMMARS.join(", "));
        };
        let refuse = |given: bool, key: &str, applies: &str| -> Result<()> {
            if given {
                bail!("`{key}` applies to {applies} only");
            }
            Ok(())
        };
        let gr8 = kind == CodonKind::Ge(Phenotype::Gr8);
        let ge = matches!(kind, CodonKind::Ge(_));
        refuse(!ge && self.phenotype.is_some(), "phenotype", "scenes with a .bnf grammar")?;
        refuse(!gr8 && self.environment.is_some(), "environment", "phenotype = \"gr8\" scenes")?;
        refuse(
            !gr8 && self.surface.is_some(),
            "[surface]",
            "phenotype = \"gr8\" scenes (the others use [volume] or [[image]])",
        )?;
        refuse(
            !(gr8 || kind == CodonKind::Graph) && self.steps.is_some(),
            "steps",
            "phenotype = \"gr8\" scenes and graph grammars (an .ls phenotype sets its own `derivation:`)",
        )?;
        refuse(kind != CodonKind::BoxSplit && self.box_corners.is_some(), "box", "box-split grammars (.bsg)")?;
        refuse(!ge && self.mapper.genr8.is_some(), "[mapper] genr8", "scenes with a .bnf grammar")?;
        refuse(!ge && self.mapper.max_depth.is_some(), "[mapper] max_depth", "scenes with a .bnf grammar")?;
        let l = &self.limits;
        refuse(
            !gr8 && (l.vertices.is_some() || l.edges.is_some() || l.faces.is_some()),
            "[limits] vertices/edges/faces",
            "phenotype = \"gr8\" scenes",
        )?;
        refuse(
            kind != CodonKind::Ge(Phenotype::Ls) && (l.modules.is_some() || l.primitives.is_some()),
            "[limits] modules/primitives",
            "phenotype = \"ls\" scenes",
        )?;
        refuse(kind != CodonKind::Graph && l.elements.is_some(), "[limits] elements", "graph grammars (.gg.yaml)")?;
        if gr8 {
            refuse(
                self.has_targets(),
                "[volume] and [[image]]",
                "ls, box-split and graph scenes; gr8 scenes are scored by [surface]",
            )?;
            let Some(surface) = &self.surface else {
                bail!(
                    "a phenotype = \"gr8\" scene is scored by Genr8's surface criteria: add a [surface] table, e.g. `size = {{ target = 10, weight = 1 }}`"
                );
            };
            genform_score::SurfaceScorer::new(*surface).map_err(|e| anyhow::anyhow!("[surface]: {e}"))?;
            if let Some(s) = self.steps
                && s > genform_hemls::envfile::MAX_STEPS
            {
                bail!("steps = {s} is more than {} (growth is exponential)", genform_hemls::envfile::MAX_STEPS);
            }
        } else {
            // [volume]/[[image]] required, fitness and stop rules checked as in tree scenes.
            self.targets_view().check()?;
        }
        if kind == CodonKind::BoxSplit && self.box_corners.is_none() {
            bail!(
                "a box-split scene derives in a box: add `box = [x0, y0, z0, x1, y1, z1]` (two opposite corners, inclusive)"
            );
        }
        for (k, v) in [
            ("vertices", l.vertices),
            ("edges", l.edges),
            ("faces", l.faces),
            ("modules", l.modules),
            ("primitives", l.primitives),
            ("elements", l.elements),
        ] {
            if v == Some(0) {
                bail!("[limits] {k} must be at least 1");
            }
        }
        self.run.check()?;
        self.ge.validate().map_err(|e| anyhow::anyhow!("[ge]: {e}"))?;
        Ok(kind)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(dir: &Path, text: &str) -> Result<LoadedCodonScene> {
        let p = dir.join("s.toml");
        std::fs::write(&p, text).unwrap();
        CodonSceneConfig::load(&p)
    }

    #[test]
    fn kinds_follow_the_grammar_and_phenotype() {
        let dir = tempfile::tempdir().unwrap();
        let s =
            load(dir.path(), "grammar = \"g.bnf\"\nphenotype = \"gr8\"\n[surface]\nsize = { target = 5 }\n").unwrap();
        assert_eq!(s.kind, CodonKind::Ge(Phenotype::Gr8));
        assert_eq!(s.config.grammar, dir.path().join("g.bnf"));
        assert!(is_codon_scene(&dir.path().join("s.toml")));
        let s = load(dir.path(), "grammar = \"h.bsg\"\nbox = [0, 0, 0, 3, 3, 3]\n[volume]\nmin = [0.0, 0.0, 0.0]\nmax = [4.0, 4.0, 4.0]\nvoxels = [4, 4, 4]\n[[volume.target]]\nmesh = \"t.obj\"\n").unwrap();
        assert_eq!(s.kind, CodonKind::BoxSplit);
        assert_eq!(box_bounds([3, 0, 5, 0, 2, 1]), (glam::IVec3::new(0, 0, 1), glam::IVec3::new(4, 3, 6)));
    }

    #[test]
    fn mistakes_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let err = |text: &str| format!("{:#}", load(dir.path(), text).unwrap_err());
        let e = err("grammar = \"g.bnf\"\nphenotype = \"gr8\"\n[ga]\npopulation = 3\n");
        assert!(e.contains("s.toml:3:2") && e.contains("unknown field `ga`"), "{e}");
        let e = err("grammar = \"g.bnf\"\nphenotype = \"gr8\"\n[surface]\nsize = { target = 5, wieght = 2 }\n");
        assert!(e.contains("s.toml:4:") && e.contains("wieght"), "{e}");
        assert!(err("grammar = \"g.bnf\"\nphenotype = \"obj\"\n").contains("unknown variant `obj`"));
        assert!(err("grammar = \"g.bnf\"\n").contains("phenotype"));
        assert!(err("grammar = \"g.bnf\"\nphenotype = \"gr8\"\n").contains("[surface]"));
        assert!(err("grammar = \"g.bnf\"\nphenotype = \"ls\"\n").contains("no target"));
        assert!(err("grammar = \"h.bsg\"\n[surface]\nsize = { target = 5 }\n").contains("`[surface]` applies to"));
        let e =
            err("grammar = \"g.bnf\"\nphenotype = \"gr8\"\n[ge]\npopulation = 1\n[surface]\nsize = { target = 5 }\n");
        assert!(e.contains("[ge]") && e.contains("population"), "{e}");
    }
}
