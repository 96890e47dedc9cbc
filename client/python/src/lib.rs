//! `gymfleet._core`, the extension module of the Python package `gymfleet`: a thin layer
//! over `gymfleet-client` (and, for `server=None`, the server crate's `LocalServer`), so
//! Python reaches the simulator through the same client as every Rust program. It owns
//! the conversions at the Python boundary: option checks, numpy arrays in and out (built
//! from the replies' packed floats), the GIL released while a call is on the network, and
//! client errors raised as the package's exception classes.
//!
//! The gymnasium classes, the spaces and the registration are plain Python in
//! `python/gymfleet/`; this crate knows nothing of gymnasium.

mod batch;
mod env;
mod errors;
mod info;
mod models;
mod options;
mod render;
mod rows;
mod runtime;
mod servers;
mod stream;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<env::ActionKind>()?;
    m.add_class::<env::EnvHandle>()?;
    m.add_class::<batch::BatchHandle>()?;
    m.add_class::<stream::StepStream>()?;
    m.add_class::<servers::Server>()?;
    m.add_function(wrap_pyfunction!(servers::embedded_address, m)?)?;
    m.add_function(wrap_pyfunction!(servers::stateful_set, m)?)?;
    m.add_function(wrap_pyfunction!(servers::server_info, m)?)?;
    m.add_function(wrap_pyfunction!(servers::convert_document, m)?)?;
    m.add_function(wrap_pyfunction!(servers::list_models, m)?)?;
    m.add_function(wrap_pyfunction!(models::seed_model, m)?)?;
    m.add_function(wrap_pyfunction!(errors::_raise_status, m)?)?;
    Ok(())
}
