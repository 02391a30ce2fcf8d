//! Keyword settings from Python (`population=50`, or `ga={…}`, `mh={…}`)
//! as JSON, for the application library's settings patch (the same as
//! `--set`: every key the scene TOML accepts, with the same checks).

use crate::errors::error;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The keyword settings as a JSON object (empty without any).
pub fn keywords(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<serde_json::Map<String, serde_json::Value>> {
    let Some(kwargs) = kwargs else { return Ok(serde_json::Map::new()) };
    let json = kwargs.py().import("json")?;
    let text: String = json.call_method1("dumps", (kwargs,))?.extract()?;
    serde_json::from_str(&text).map_err(|e| error(format!("settings: {e}")))
}
