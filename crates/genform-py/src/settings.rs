//! Algorithm names and settings from Python keyword arguments: the keys of
//! a scene config's sections (`population=50`, or `ga={…}`, `mh={…}`),
//! merged into the scene's (or the defaults') through serde, so every key
//! the TOML accepts is accepted here with the same checks.

use anyhow::{Context, Result, bail};
use genform_app::run::AlgorithmChoice;
use genform_evolve::{Algorithm, Settings};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};

/// The tree algorithm named `name` (`map_elites` and `map-elites` both work).
pub fn algorithm(name: &str) -> Result<Algorithm> {
    let choice = AlgorithmChoice::from_name(name)?;
    choice.tree().ok_or_else(|| anyhow::anyhow!("ask/tell runs tree algorithms; `{name}` evolves codon genomes"))
}

/// The scene-config section holding `algorithm`'s settings.
fn section_of(algorithm: Algorithm) -> &'static str {
    AlgorithmChoice::ALL.into_iter().find(|c| c.tree() == Some(algorithm)).map_or("ga", |c| c.section(false))
}

const SECTIONS: [&str; 5] = ["ga", "mh", "smc", "hybrid", "map_elites"];

/// `base` with `kwargs` applied: a key naming a section takes a dict for
/// that section; any other key belongs to `algorithm`'s section.
pub fn apply(base: Settings, algorithm: Algorithm, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Settings> {
    let Some(kwargs) = kwargs else { return Ok(base) };
    let json = kwargs.py().import("json")?;
    let text: String = json.call_method1("dumps", (kwargs,))?.extract()?;
    let updates: Map<String, Value> =
        serde_json::from_str(&text).map_err(|e| crate::errors::error(format!("settings: {e}")))?;
    crate::errors::OrRaise::or_raise(merge_all(base, algorithm, updates))
}

fn merge_all(mut s: Settings, algorithm: Algorithm, updates: Map<String, Value>) -> Result<Settings> {
    let mut by_section: Vec<(&str, Map<String, Value>)> = SECTIONS.iter().map(|n| (*n, Map::new())).collect();
    let own = section_of(algorithm);
    for (key, value) in updates {
        match (SECTIONS.iter().find(|n| **n == key), value) {
            (Some(name), Value::Object(m)) => by_section.iter_mut().find(|(n, _)| n == name).unwrap().1.extend(m),
            (Some(name), _) => bail!("settings: `{name}` takes a dict of the scene's [{name}] keys"),
            (None, value) => {
                by_section.iter_mut().find(|(n, _)| *n == own).unwrap().1.insert(key, value);
            }
        }
    }
    for (name, m) in by_section.into_iter().filter(|(_, m)| !m.is_empty()) {
        match name {
            "ga" => merge(&mut s.ga, name, m)?,
            "mh" => merge(&mut s.mh, name, m)?,
            "smc" => merge(&mut s.smc, name, m)?,
            "hybrid" => merge(&mut s.hybrid, name, m)?,
            _ => merge(&mut s.map_elites, name, m)?,
        }
    }
    Ok(s)
}

/// `section` with the keys of `updates` replaced, through its serde form.
fn merge<T: Serialize + DeserializeOwned>(section: &mut T, name: &str, updates: Map<String, Value>) -> Result<()> {
    let mut value = serde_json::to_value(&*section).context("settings")?;
    if let Value::Object(m) = &mut value {
        m.extend(updates);
    }
    *section = serde_json::from_value(value).with_context(|| format!("settings of [{name}]"))?;
    Ok(())
}
