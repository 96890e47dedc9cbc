//! [`to_py_err`]: a [`ClientError`] as the Python exception of its status class. The
//! classes live in plain Python (`gymfleet/errors.py`), so that each can also subclass
//! the builtin that fits (`ValueError`, `KeyError`, `TimeoutError`); this module only
//! picks one and fills it in.

use gymfleet_client::{ClientError, ErrorKind};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyList;

/// How a Python program points the package at another server, as connection errors say.
const POINT_THE_PACKAGE: &str =
    "pass its address as server=\"HOST:PORT\" (server=None runs one in this process)";

/// The name of the `gymfleet.errors` class for `err`, by its kind (an exhaustive match: a
/// kind added to the client fails to compile here until it has a class).
fn class_name(err: &ClientError) -> &'static str {
    match err.kind() {
        ErrorKind::NotFound => "NotFound",
        ErrorKind::InvalidArgument | ErrorKind::Fleet => "InvalidArgument",
        ErrorKind::FailedPrecondition => "FailedPrecondition",
        ErrorKind::ResourceExhausted => "ResourceExhausted",
        ErrorKind::Connect | ErrorKind::Unavailable => "Unavailable",
        ErrorKind::DeadlineExceeded => "DeadlineExceeded",
        ErrorKind::Unauthenticated => "Unauthenticated",
        ErrorKind::Internal | ErrorKind::Protocol => "Internal",
        ErrorKind::ServerLost => "ServerLost",
    }
}

/// The exception's text: the server's message, prefixed with what the class does not say
/// already (which server, for a fleet; what kind of failure, for the two catch-alls).
fn text(err: &ClientError) -> String {
    match err {
        ClientError::OnServer { .. } => return err.to_string(),
        ClientError::Connect { addr, reason } => {
            return gymfleet_client::cannot_connect(addr, reason, POINT_THE_PACKAGE)
        }
        _ => {}
    }
    match err.kind() {
        ErrorKind::Connect | ErrorKind::Protocol | ErrorKind::ServerLost => err.to_string(),
        ErrorKind::Fleet => format!("fleet: {}", err.message()),
        ErrorKind::NotFound
        | ErrorKind::InvalidArgument
        | ErrorKind::FailedPrecondition
        | ErrorKind::ResourceExhausted
        | ErrorKind::Unavailable
        | ErrorKind::DeadlineExceeded
        | ErrorKind::Unauthenticated
        | ErrorKind::Internal => err.message().to_string(),
    }
}

/// `err` as an instance of its `gymfleet.errors` class, with `server` (the server it
/// names, or `None`), `reason` (the server's `ErrorReason` as it travels, e.g.
/// `"ENV_NOT_FOUND"`, or `None`), `limit` (the flag that raises a refusing limit, or
/// `None`) and, for `ServerLost`, `envs` (the lost `(start, stop)` ranges).
pub(crate) fn to_py_err(err: ClientError) -> PyErr {
    Python::attach(|py| match build(py, &err) {
        Ok(exception) => exception,
        // The package's own module is missing or broken: say so, with the original error.
        Err(e) => PyRuntimeError::new_err(format!("{err} (and gymfleet.errors failed: {e})")),
    })
}

fn build(py: Python<'_>, err: &ClientError) -> PyResult<PyErr> {
    let module = py.import("gymfleet.errors")?;
    let class = module.getattr(class_name(err))?;
    let exception = class.call1((text(err),))?;
    exception.setattr("server", err.server())?;
    exception.setattr("reason", err.reason().map(|r| r.wire_name()))?;
    exception.setattr("limit", err.limit())?;
    if let ClientError::ServerLost { envs, .. } = err {
        let ranges: Vec<(usize, usize)> = envs.iter().map(|r| (r.start, r.end)).collect();
        exception.setattr("envs", PyList::new(py, ranges)?)?;
    }
    Ok(PyErr::from_value(exception))
}

/// Raises the exception a server status `code` (gRPC's number) with `message` becomes,
/// through the same mapping as every call: for the tests of statuses no server here can
/// be made to answer (e.g. `UNAUTHENTICATED` before auth exists, `INTERNAL`), with the
/// reason metadata entry `reason` when given.
#[pyfunction]
#[pyo3(signature = (code, message, reason=None))]
pub(crate) fn _raise_status(code: i32, message: String, reason: Option<String>) -> PyResult<()> {
    let mut status = tonic::Status::new(tonic::Code::from(code), message);
    if let Some(value) = reason.and_then(|r| r.parse().ok()) {
        status
            .metadata_mut()
            .insert(gymfleet_client::REASON_KEY, value);
    }
    Err(to_py_err(ClientError::from(status)))
}
