//! The `genform` Python package's native module (`genform._genform`): a
//! thin layer over the application library `genform-app`: grammars,
//! scenes, runs and ask/tell optimizers are its handles and requests; this
//! crate only converts between Rust and Python.

mod errors;
mod evolve;
mod grammar;
mod lpy;
mod mesh;
mod optimizer;
mod scene;
mod settings;
mod stats;

use pyo3::prelude::*;

#[pymodule]
fn _genform(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("GenformError", m.py().get_type::<errors::GenformError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // Compile warnings and the like go to the process's stderr, as the CLI's do.
    genform_app::set_sink(Box::new(|text| eprintln!("{text}")), false);
    m.add_class::<errors::Diagnostic>()?;
    m.add_class::<grammar::Grammar>()?;
    m.add_class::<grammar::Model>()?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<optimizer::Optimizer>()?;
    m.add_class::<evolve::RunResult>()?;
    m.add_class::<lpy::LpyRules>()?;
    m.add_function(wrap_pyfunction!(grammar::load, m)?)?;
    m.add_function(wrap_pyfunction!(grammar::formalisms, m)?)?;
    m.add_function(wrap_pyfunction!(grammar::tag_color, m)?)?;
    m.add_function(wrap_pyfunction!(grammar::derive_with_limits, m)?)?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(evolve::evolve, m)?)?;
    m.add_function(wrap_pyfunction!(lpy::lpy_step, m)?)?;
    Ok(())
}
