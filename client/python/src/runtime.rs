//! The extension's tokio runtime, and [`wait`]: how every Python call that goes on the
//! network blocks, with the GIL released and an optional deadline.

use std::future::Future;
use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use gymfleet_client::ClientError;
use pyo3::prelude::*;
use tokio::runtime::Runtime;

use crate::errors::to_py_err;

/// The process's runtime: a few I/O threads shared by every client connection and the
/// embedded servers' gRPC handling. Simulation never runs here (it runs on the servers'
/// rayon pools); the threads only move bytes.
pub(crate) fn runtime() -> &'static Runtime {
    static RUNTIME: OnceLock<Runtime> = OnceLock::new();
    RUNTIME.get_or_init(|| {
        tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .thread_name("gymfleet-io")
            .enable_all()
            .build()
            // Without threads or timers the extension cannot work at all; the OS said no.
            .expect("gymfleet: cannot start the tokio runtime")
    })
}

/// Runs the future `call()` makes to completion on the runtime with the GIL released, so
/// other Python threads run meanwhile. With a `timeout`, a call with no result by then is
/// abandoned and fails with `DeadlineExceeded` (what the server did with it is unknown).
pub(crate) fn wait<T, F, Fut>(py: Python<'_>, timeout: Option<Duration>, call: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce() -> Fut + Send,
    Fut: Future<Output = Result<T, ClientError>>,
{
    let result = py.detach(move || {
        let call = call();
        match timeout {
            // Nothing can abandon a call without a deadline, so the embedded server's
            // pool work for it runs on this thread, which would only wait for it (two
            // thread wake-ups fewer a call); a remote server's is not affected.
            None => gymfleet_server::run_jobs_here(|| runtime().block_on(call)),
            // The server hears of the deadline too (`grpc-timeout`), so it does not
            // start work nobody waits for.
            Some(limit) => runtime().block_on(async move {
                match tokio::time::timeout(limit, gymfleet_client::with_deadline(limit, call)).await
                {
                    // The server may say so first (it read the same deadline): one
                    // message either way.
                    Ok(Err(ClientError::DeadlineExceeded { .. })) | Err(_) => {
                        Err(ClientError::DeadlineExceeded {
                            message: format!(
                                "no reply within the timeout of {} s",
                                limit.as_secs_f64()
                            ),
                        })
                    }
                    Ok(result) => result,
                }
            }),
        }
    });
    result.map_err(to_py_err)
}

/// A handle's per-call deadline, which Python may change between calls.
#[derive(Debug, Default)]
pub(crate) struct Deadline(Mutex<Option<Duration>>);

impl Deadline {
    pub(crate) fn new(timeout: Option<Duration>) -> Self {
        Deadline(Mutex::new(timeout))
    }

    /// The deadline of the next call.
    pub(crate) fn get(&self) -> Option<Duration> {
        *self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Sets it from Python's seconds (checked as at creation).
    pub(crate) fn set_seconds(&self, seconds: Option<f64>) -> PyResult<()> {
        *self.0.lock().unwrap_or_else(|p| p.into_inner()) = crate::options::timeout(seconds)?;
        Ok(())
    }

    /// In seconds, for Python.
    pub(crate) fn seconds(&self) -> Option<f64> {
        self.get().map(|d| d.as_secs_f64())
    }
}
