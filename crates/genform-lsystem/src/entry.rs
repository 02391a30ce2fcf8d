//! Compiling a `.ls` file: parse, compile, name the system after its
//! file; the entry points [`crate::compile`] and [`crate::compile_with_assets`].

use crate::compile::{self, LSystem};
use crate::surface::{NoSurfaceAssets, SurfaceAssets};
use crate::syntax;
use genform_core::{Diagnostics, SourceFile};

/// Compiles a `.ls` file. Returns the system and its warnings, or every
/// error found. `surface` declarations are errors (no files are read); use
/// [`compile_with_assets`] to load them.
pub fn compile(file: &SourceFile) -> Result<(LSystem, Diagnostics), Diagnostics> {
    compile_with_assets(file, &NoSurfaceAssets)
}

/// Compiles a `.ls` file, loading the meshes of its `surface name =
/// "path"` declarations through `assets`.
pub fn compile_with_assets(
    file: &SourceFile,
    assets: &dyn SurfaceAssets,
) -> Result<(LSystem, Diagnostics), Diagnostics> {
    let (parsed, errors) = syntax::parse(&file.text);
    let mut diags = Diagnostics::new(file.clone());
    if !errors.is_empty() {
        for e in errors {
            diags.push(e);
        }
        return Err(diags);
    }
    match compile::compile(&parsed, assets) {
        Ok((mut system, warnings)) => {
            system.source = Some(file.clone());
            if system.settings.name.is_empty() {
                let stem = std::path::Path::new(&*file.name).file_stem().map(|s| s.to_string_lossy().into_owned());
                system.settings.name = stem.unwrap_or_default().trim_end_matches(".ls").to_string();
            }
            for w in warnings {
                diags.push(w);
            }
            Ok((system, diags))
        }
        Err(errors) => {
            for e in errors {
                diags.push(e);
            }
            Err(diags)
        }
    }
}
