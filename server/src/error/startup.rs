//! [`StartupError`]: what stops a server from starting or serving. A request never meets
//! one of these ([`super::ServerError`] holds what a request can meet), so none has a
//! status code or an error reason.

use gymfleet_batch::BatchError;

/// Why a server could not start, or stopped serving.
#[derive(Debug, thiserror::Error)]
pub enum StartupError {
    /// The listener (or the metrics or dashboard listener) could not be bound.
    #[error("cannot listen on {addr}: {reason}")]
    Bind {
        /// The address, `host:port` or `unix:/path`.
        addr: String,
        /// The operating system's reason.
        reason: String,
    },
    /// The TLS certificate, key or client CA is unusable.
    #[error("TLS: {0}")]
    Tls(String),
    /// The model library (`--models`) could not be loaded.
    #[error("--models: {}: {reason}", path.display())]
    ModelLibrary {
        /// The directory or file at fault.
        path: std::path::PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// The simulation pool's threads could not start.
    #[error(transparent)]
    Pool(#[from] BatchError),
    /// Reflection could not be set up (a bad descriptor set: a build bug).
    #[error("reflection: {0}")]
    Reflection(#[from] tonic_reflection::server::Error),
    /// The listener failed (e.g. its address could not be read).
    #[error("io: {0}")]
    Io(#[from] std::io::Error),
    /// The transport failed while serving.
    #[error("transport: {0}")]
    Transport(#[from] tonic::transport::Error),
    /// The serving task panicked (a server bug).
    #[error(
        "internal error: the server's task panicked ({0}); this is a server bug, please report it"
    )]
    Panicked(String),
    /// The server stopped before it served, without saying why.
    #[error("the server stopped before it started serving")]
    Stopped,
}
