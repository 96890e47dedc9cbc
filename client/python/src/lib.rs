//! `gymfleet._core`, the extension module of the Python package `gymfleet`: a thin layer
//! over `gymfleet-client` (and, for `server=None`, the server crate's `LocalServer`), so
//! Python reaches the simulator through the same client as every Rust program. It owns
//! the conversions at the Python boundary: option checks, numpy arrays in and out (built
//! from the replies' packed floats), the GIL released while a call is on the network, and
//! client errors raised as the package's exception classes.
//!
//! The gymnasium classes, the spaces and the registration are plain Python in
//! `python/gymfleet/`; this crate knows nothing of gymnasium.
//!
//! # Modules
//!
//! - `runtime.rs`: one tokio runtime; `wait` runs a client call with the GIL released and
//!   an optional deadline. Without a deadline it runs inside
//!   `gymfleet_server::run_jobs_here`, so the embedded server's pool work for the call runs
//!   on the calling thread.
//! - `servers.rs`: `server=None` is the process's embedded `LocalServer`, started on first
//!   use and called in-process through `LocalServer::in_process` (no socket); `"host:port"`
//!   one server; a comma list a `Fleet`. One `Client` is cached per address. The `Server`
//!   class runs more servers inside the process, each on a loopback port.
//! - `env.rs` and `batch.rs`: the `EnvHandle` and `BatchHandle` classes: numpy in, numpy
//!   out, observations taken over from the reply's vector; a batch is always a
//!   `FleetBatch`, of one shard on one server. `stream.rs`: `StepStream`, one server's
//!   batch's `BatchStream` for the asynchronous API. `rows.rs`: a step's rows as numpy
//!   arrays, for both.
//! - `options.rs` (option checks at the boundary), `errors.rs` (a `ClientError` → the
//!   `gymfleet.errors` class of its status), `info.rs`, `render.rs`, and `models.rs` (the
//!   seed models, compiled in).
//!
//! The crate is a workspace member, so fmt and clippy cover it, but it has no Rust tests (a
//! Python extension does not link on its own): `client/python/tests/` is pytest, run by
//! `.ci/run` against the package pip installs. The Python side is described in
//! docs/internals.md. It knows no physics and no proto types.

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
