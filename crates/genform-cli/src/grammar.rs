//! Loading a grammar file into a generator, by extension.

use anyhow::{Context, Result, bail};
use genform_core::{Diagnostics, Generator, Limits, Mesh, SourceFile};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

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

/// Compiles the grammar at `path`; warnings go to stderr, errors become the
/// returned error with every diagnostic rendered.
pub fn load(path: &Path) -> Result<Loaded> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read grammar {}", path.display()))?;
    let file = SourceFile::new(path.display().to_string(), text);
    match ext {
        "sg" => {
            let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
            match genform_shape::compile(&file, &FileAssets { base }) {
                Ok((g, warnings)) => {
                    if !warnings.items.is_empty() {
                        eprint!("{}", render(&warnings));
                    }
                    Ok(Loaded { name: g.name().to_string(), limits: g.limits(), generator: Box::new(g) })
                }
                Err(errors) => {
                    let n = errors.error_count();
                    bail!("{}{} error{} in {}", render(&errors), n, if n == 1 { "" } else { "s" }, path.display())
                }
            }
        }
        _ => bail!(
            "don't know the grammar format of {} (extension `.{ext}`); supported: .sg (shape grammar)",
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
