//! Algorithm names and settings from Python keyword arguments: the keys of
//! a scene config's sections (`population=50`, or `ga={…}`, `mh={…}`),
//! applied as the same settings patch as `--set` (over the scene file, or
//! over the defaults for a bare grammar), so every key the TOML accepts is
//! accepted here with the same checks.

use crate::errors::OrRaise;
use anyhow::Result;
use genform_app::run::AlgorithmChoice;
use genform_evolve::{Algorithm, Settings};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The tree algorithm named `name` (`map_elites` and `map-elites` both work).
pub fn algorithm(name: &str) -> Result<Algorithm> {
    let choice = AlgorithmChoice::from_name(name)?;
    choice.tree().ok_or_else(|| anyhow::anyhow!("ask/tell runs tree algorithms; `{name}` evolves codon genomes"))
}

/// The scene-config section holding `algorithm`'s settings.
fn section_of(algorithm: Algorithm) -> &'static str {
    AlgorithmChoice::ALL.into_iter().find(|c| c.tree() == Some(algorithm)).map_or("ga", |c| c.section(false))
}

/// The settings of `scene` (`None`: the defaults) with the keyword
/// settings applied as a settings patch (`population=20` sets the
/// algorithm's table, `ga={...}` any table), as `genform.evolve` does.
pub fn apply(
    scene: Option<&std::path::Path>,
    algorithm: Algorithm,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Settings> {
    let patch = match kwargs {
        Some(kwargs) => {
            let json = kwargs.py().import("json")?;
            let text: String = json.call_method1("dumps", (kwargs,))?.extract()?;
            let updates: serde_json::Map<String, serde_json::Value> =
                serde_json::from_str(&text).map_err(|e| crate::errors::error(format!("settings: {e}")))?;
            genform_app::sweep::set::patch_from_json(section_of(algorithm), &updates).or_raise()?
        }
        None => Vec::new(),
    };
    let patch = genform_app::sweep::set::parse_patch(&patch).or_raise()?;
    genform_app::sweep::set::patched_settings(scene, &patch).or_raise()
}
