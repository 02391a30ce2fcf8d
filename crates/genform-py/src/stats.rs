//! Per-generation statistics as Python dicts (pandas-ready rows).

use genform_evolve::GenerationStats;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One generation's row: the columns of `stats.csv` plus `best` (the best
/// fitness so far) and, when given, `seconds` since the run began.
pub fn row<'py>(
    py: Python<'py>,
    s: &GenerationStats,
    best: Option<f64>,
    seconds: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("generation", s.generation)?;
    d.set_item("best", best.unwrap_or(f64::NAN))?;
    d.set_item("max", s.max)?;
    d.set_item("avg", s.avg)?;
    d.set_item("min", s.min)?;
    d.set_item("invalid", s.invalid)?;
    d.set_item("evaluations", s.evaluations)?;
    d.set_item("total_evaluations", s.total_evaluations)?;
    d.set_item("eval_seconds", s.eval_time.as_secs_f64())?;
    d.set_item("reproduction_seconds", s.reproduction_time.as_secs_f64())?;
    d.set_item("len_min", s.len_min)?;
    d.set_item("len_avg", s.len_avg)?;
    d.set_item("len_max", s.len_max)?;
    d.set_item("best_len", s.best_len)?;
    d.set_item("ess", s.ess)?;
    d.set_item("distinct", s.distinct)?;
    if let Some(t) = seconds {
        d.set_item("seconds", t)?;
    }
    Ok(d)
}
