//! The gymfleet gRPC server. This crate owns the `gymfleet.v1.Simulator` service and
//! everything between the wire and the domain: the registry of open environments and
//! batches (ids `"sim_<n>"` and `"batch_<n>"`, one async lock each), the server's limits,
//! the hand-off of all CPU work to the `gymfleet-batch` step pool (through a oneshot,
//! never on tokio worker threads), idle reclaiming, panic containment, health and
//! reflection, graceful shutdown, bearer-token tenants ([`TokenTable`], each tenant
//! seeing only its own ids), TLS and mutual TLS, Prometheus metrics
//! (`--metrics-listen`), and the one mapping of domain errors to `tonic::Status`
//! ([`ServerError`]).
//!
//! It leaves documents to `gymfleet-assembly`, episodes to `gymfleet-env`, parallel
//! stepping to `gymfleet-batch`, and the wire types to `gymfleet-proto`; proto types are
//! converted at the edge and never reach those crates.
//!
//! Panic policy: a panic inside a pool job (a bug) is caught; the call gets INTERNAL
//! with the panic message, and the env or batch it ran on is closed (later calls get
//! NOT_FOUND), because its state may be half-updated. Everyone else keeps being served.

mod auth;
mod cli;
mod clock;
mod config;
mod convert;
mod dashboard;
mod direct;
mod domain;
mod error;
mod limit;
mod listen;
mod local;
mod metrics;
mod models;
mod pool;
mod registry;
mod serve;
mod service;
mod simulation;
mod tenant;

pub use cli::{init_tracing, Cli, LogFormat};
pub use clock::Clock;
pub use config::{ServerConfig, TlsConfig, DEFAULT_IDLE_TTL};
pub use direct::DirectService;
pub use error::{EntityKind, Result, ServerError, StartupError, MAX_STATUS_MESSAGE_BYTES};
/// For a thread that blocks on its calls to an in-process server
/// ([`LocalServer::in_process`]): inside it, the server's pool work for those calls runs
/// on that thread, which saves two thread wake-ups a call (the Python package's calls
/// without a deadline).
pub use gymfleet_batch::run_jobs_here;
pub use limit::{
    Limit, DEFAULT_MAX_BATCH_SIZE, DEFAULT_MAX_CONTACT_WORK, DEFAULT_MAX_DOCUMENT_BYTES,
    DEFAULT_MAX_DOFS, DEFAULT_MAX_END_EFFECTORS, DEFAULT_MAX_ENVS, DEFAULT_MAX_INSTANCES,
    DEFAULT_MAX_JOINTS, DEFAULT_MAX_MESSAGE_BYTES, DEFAULT_MAX_STEP_WORK,
};
pub use listen::{ListenAddr, Listener, SocketFile};
pub use local::LocalServer;
pub use models::{LibraryModel, ModelLibrary};
#[cfg(debug_assertions)]
#[doc(hidden)]
pub use pool::JobGate;
pub use serve::serve;
pub use tenant::{Tenant, TokenTable, MIN_TOKEN_CHARS};
