//! Writing result files: models in the format their extension names, and
//! atomic writes, so an interrupted run never leaves a half-written file
//! where a good one was.

use anyhow::{Context, Result};
use genform_core::Scene;
use genform_export::{ExportOptions, Format};
use std::io::Write;
use std::path::Path;

/// Refuses a command whose output (flag name, path) would overwrite one of
/// its inputs: the same file reached by two spellings counts (paths are
/// compared after resolving the existing folder part).
pub fn refuse_overwriting_inputs(inputs: &[&Path], outputs: &[(&str, Option<&Path>)]) -> Result<()> {
    let real = |p: &Path| -> Option<std::path::PathBuf> {
        if let Ok(c) = p.canonicalize() {
            return Some(c);
        }
        let dir = p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        Some(dir.canonicalize().ok()?.join(p.file_name()?))
    };
    for &(flag, out) in outputs {
        let Some(out) = out else { continue };
        let Some(o) = real(out) else { continue };
        if let Some(input) = inputs.iter().find(|i| real(i).as_deref() == Some(o.as_path())) {
            anyhow::bail!(
                "{flag} {} is an input of this command ({}); writing it would destroy it: choose another file",
                out.display(),
                input.display()
            );
        }
    }
    Ok(())
}

/// The export format `path`'s extension names.
pub fn output_format(path: &Path) -> Result<Format> {
    Format::from_path(path).ok_or_else(|| unknown_format(path, &[]))
}

/// The error for an output path whose format is unknown: it lists the
/// export formats and `extra` (extensions, with the dot, that the caller
/// writes itself).
pub fn unknown_format(path: &Path, extra: &[&str]) -> anyhow::Error {
    let known = Format::extensions().iter().map(|e| format!(".{e}"));
    let all: Vec<String> = known.chain(extra.iter().map(|e| e.to_string())).collect();
    anyhow::anyhow!("cannot tell the output format of {}; use one of the extensions: {}", path.display(), all.join(" "))
}

/// Exports `scene` to `path` in the format its extension names.
pub fn write_model(scene: &Scene, path: &Path) -> Result<()> {
    write_model_with(scene, path, &ExportOptions::default())
}

/// [`write_model`] with explicit export options.
pub fn write_model_with(scene: &Scene, path: &Path, options: &ExportOptions) -> Result<()> {
    let format = output_format(path)?;
    let bytes =
        genform_export::export(scene, format, options).with_context(|| format!("cannot export {}", path.display()))?;
    write_atomic(path, &bytes)
}

/// Writes `bytes` to `path` through a temporary file in the same folder
/// and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create folder {}", dir.display()))?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write {}", path.display()))
}
