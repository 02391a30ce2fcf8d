//! Loading a grammar file into a generator, by extension.

use anyhow::{Context, Result, bail};
use genform_core::{Diagnostics, Generator, Limits, Mesh, SourceFile};
use genform_lsystem::{LSystem, LsGenerator};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A compiled grammar of any formalism.
pub struct Loaded {
    /// The generator.
    pub generator: Box<dyn Generator>,
    /// Display name of the grammar.
    pub name: String,
    /// Limits declared by the grammar (or defaults), before CLI overrides.
    pub limits: Limits,
}

/// Reads mesh assets relative to the grammar file.
struct FileAssets {
    base: PathBuf,
}

impl genform_shape::AssetResolver for FileAssets {
    fn load_mesh(&self, path: &str) -> Result<Mesh, String> {
        let full = self.base.join(path);
        let text = std::fs::read_to_string(&full).map_err(|e| format!("cannot read {}: {e}", full.display()))?;
        let name = Path::new(path).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        Mesh::from_obj(&name, &text).map_err(|e| format!("{}: {e}", full.display()))
    }
}

fn render(d: &Diagnostics) -> String {
    if std::io::stderr().is_terminal() { d.render(true) } else { d.render(false) }
}

/// Whether `path` names an L-system (`.ls`).
pub fn is_lsystem(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "ls")
}

fn read_source(path: &Path) -> Result<SourceFile> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read grammar {}", path.display()))?;
    Ok(SourceFile::new(path.display().to_string(), text))
}

/// Prints warnings; turns errors into one error with every diagnostic.
fn diagnosed<T>(result: Result<(T, Diagnostics), Diagnostics>, path: &Path) -> Result<T> {
    match result {
        Ok((value, warnings)) => {
            if !warnings.items.is_empty() {
                eprint!("{}", render(&warnings));
            }
            Ok(value)
        }
        Err(errors) => {
            let n = errors.error_count();
            bail!("{}{} error{} in {}", render(&errors), n, if n == 1 { "" } else { "s" }, path.display())
        }
    }
}

/// Whether `path` names a box-split grammar (`.bsg`).
pub fn is_boxsplit(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "bsg")
}

/// Compiles the box-split grammar at `path`; warnings go to stderr.
pub fn load_boxsplit(path: &Path) -> Result<genform_boxsplit::BoxGrammar> {
    let file = read_source(path)?;
    diagnosed(genform_boxsplit::compile(&file), path)
}

/// Whether `path` names a graph grammar (`.gg.yaml`).
pub fn is_graph(path: &Path) -> bool {
    path.file_name().is_some_and(|n| n.to_string_lossy().to_ascii_lowercase().ends_with(".gg.yaml"))
}

/// Compiles the graph grammar at `path`; warnings go to stderr.
pub fn load_graph(path: &Path) -> Result<genform_graph::GraphGrammar> {
    let file = read_source(path)?;
    diagnosed(genform_graph::compile(&file), path)
}

/// Compiles the L-system at `path`; warnings go to stderr.
pub fn load_lsystem(path: &Path) -> Result<Arc<LSystem>> {
    let file = read_source(path)?;
    Ok(Arc::new(diagnosed(genform_lsystem::compile(&file), path)?))
}

/// Compiles the grammar at `path` into a generator; warnings go to stderr,
/// errors become the returned error with every diagnostic rendered.
pub fn load(path: &Path) -> Result<Loaded> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    match ext {
        "sg" => {
            let file = read_source(path)?;
            let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
            let g = diagnosed(genform_shape::compile(&file, &FileAssets { base }), path)?;
            Ok(Loaded { name: g.name().to_string(), limits: g.limits(), generator: Box::new(g) })
        }
        "ls" => {
            let system = load_lsystem(path)?;
            let g = LsGenerator::new(system)
                .with_context(|| format!("{} cannot be used as a generator", path.display()))?;
            Ok(Loaded { name: g.system().settings.name.clone(), limits: g.limits(), generator: Box::new(g) })
        }
        _ => bail!(
            "don't know the grammar format of {} (extension `.{ext}`); supported: .sg (shape grammar), .ls (L-system)",
            path.display()
        ),
    }
}

/// Limits given on the command line or in a scene config, each replacing
/// the grammar's own when set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LimitOverrides {
    /// Most genes.
    pub max_genes: Option<usize>,
    /// Deepest gene.
    pub max_depth: Option<usize>,
    /// Most primitives.
    pub max_primitives: Option<usize>,
}

impl LimitOverrides {
    /// `base` with the set overrides applied.
    pub fn apply(&self, base: Limits) -> Limits {
        Limits {
            max_genes: self.max_genes.unwrap_or(base.max_genes),
            max_depth: self.max_depth.unwrap_or(base.max_depth),
            max_primitives: self.max_primitives.unwrap_or(base.max_primitives),
        }
    }

    /// `self` where set, `other` elsewhere.
    pub fn or(self, other: LimitOverrides) -> LimitOverrides {
        LimitOverrides {
            max_genes: self.max_genes.or(other.max_genes),
            max_depth: self.max_depth.or(other.max_depth),
            max_primitives: self.max_primitives.or(other.max_primitives),
        }
    }
}
