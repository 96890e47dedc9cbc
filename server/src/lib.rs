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
//!
//! # Modules
//!
//! - `serve.rs`: `serve(listener, config, shutdown)`; `main.rs` is thin (clap flags in
//!   `cli.rs`, each with its `GYMFLEET_*` variable; SIGINT/SIGTERM through
//!   `tokio-graceful`). It listens on TCP or on a Unix-domain socket (`listen.rs`:
//!   `--listen unix:/path`). Health (also alone in plaintext on `--health-listen`, for
//!   probes that cannot do TLS), reflection (v1 and v1alpha), the idle sweeper and graceful
//!   shutdown are set up there. TLS is tonic's rustls (`tls-ring`).
//! - `local.rs`: `LocalServer` is *the* way to run one on `127.0.0.1:0` in-process
//!   (address, client address, stop, stop on drop): tests and the MCP adapter's and the
//!   load client's embedded servers all use it. `LocalServer::in_process` hands out the
//!   simulator service as the listener serves it (behind the authenticator, with the
//!   message limits) for a client in the same process to call with no socket
//!   (`ClientBuilder::in_process`): the Python package's embedded server is reached so.
//!   `direct.rs`: `DirectService` is the same service without a network, called with
//!   requests the caller decoded: the fuzz targets and the remote-vs-local benchmark use
//!   it.
//! - `clock.rs`: time comes from a `Clock` in the config (the system clock, or a manual one
//!   tests advance), so idle-TTL reclaiming is tested without sleeping.
//! - `service.rs`: the tonic handlers. Every unary RPC goes through one `unary` helper: the
//!   caller's tenant, the call's timing and status in the metrics, a refusal counted, the
//!   error mapped. It is the only place that converts proto messages, with `convert.rs`
//!   (the requests), `convert/create.rs` (the create and fork requests; the deprecated flat
//!   option fields are still read there) and `convert/replies.rs` (the replies).
//! - `simulation.rs`: takes and returns the proto-free values of `domain.rs` (requests,
//!   step outcomes, `ServerStatus`); the env operations are there, and its children hold
//!   the rest: `batches.rs`, `states.rs` (saved states and forks), `access.rs`
//!   (`SetJointState` and `GetBodies`), `pictures.rs` (scenes, renders and randomisation
//!   draws), `documents.rs` (conversion, building an env, the model library), `limits.rs`
//!   (every check before anything is built) and `watch.rs` (the dashboard's lookups).
//! - `registry.rs`: the registry of envs and batches (`sim_<n>`, `batch_<n>`), one async
//!   lock each, and each entry's idle time, by which `Simulation::reclaim_idle` (run by
//!   `serve.rs`'s idle sweeper) reclaims it. Every entry has an owner, and
//!   `Registry::get(tenant, id)` treats another tenant's id as unknown; each tenant's quota
//!   is an `EnvCapacity` inside the server's. An entry counts as used when its job ends, so
//!   a long step whose caller gave up is not reclaimed by the idle TTL the moment it ends.
//!   `Close` forgets the id at once and frees the value in a task of its own when the call
//!   running on it ends, so a Close that meets a running step is honoured then, even if its
//!   caller has gone.
//! - `limit.rs` (a leaf): each limit's name, flag, variable and default, written once in
//!   `Limit`; `ServerConfig::limit` gives its value, and the CLI, the checks, the error
//!   messages and the refusal metric read them.
//! - `pool.rs` runs single-env jobs in the fair lane (`Lane::Env`) and batch coordinators
//!   on plain pool threads (`Lane::Batch`), answers through a oneshot, and drops a job
//!   whose caller has gone before starting it. A panic in a pool job is caught: the call
//!   gets INTERNAL and the entry is closed. Its `Jobs` is the pool as jobs see it (with, in
//!   debug builds only, the tests' `JobGate`).
//! - `error.rs`: the only place that maps domain errors to `tonic::Status`;
//!   `error/status.rs` holds the one exhaustive `From`, with each error's code and its
//!   machine-readable `ErrorReason`, sent as the `gymfleet-reason` metadata entry, plus
//!   `gymfleet-limit` for a limit's refusal. Every status message is at most
//!   `MAX_STATUS_MESSAGE_BYTES` (4 KiB), names in it shortened at their source.
//!   `ServerError` holds only what a request can meet; what stops a server from starting or
//!   serving is `StartupError` (`error/startup.rs`: bind, TLS, the model library, the pool,
//!   transport).
//! - `tenant.rs` (a leaf): `Tenant` and the token file (`TokenTable`). `auth.rs`: the
//!   `Authenticator` interceptor in front of the simulator and reflection (never health),
//!   which puts the caller's `Tenant` in the request and counts refusals in the `Metrics`
//!   it holds.
//! - `metrics.rs`: a `prometheus-client` registry per server, served by axum at
//!   `--metrics-listen`; gauges are set at scrape time from a plain snapshot
//!   (`Simulation::gauges`), so the metrics know nothing of the simulation.
//! - `models.rs`: the `--models DIR` library (`.json`, `.xml`, `.mjcf`, `.urdf`; mesh files
//!   read from the folder), every file converted and validated at start
//!   (`ServerConfig::models`); requests name a model instead of sending a document
//!   (`Simulation::resolve_model`), and `ListModels` lists it.
//! - `dashboard/`: the `--dashboard-listen` page and its JSON API (axum). `mod.rs` binds,
//!   refusing an address other than loopback without auth tokens, and serves until the
//!   server's stop signal; `api.rs` the overview, scenes, login and logout; `session.rs`
//!   random session ids mapped to tenants, kept server-side and sent as `HttpOnly;
//!   SameSite=Strict` cookies; `json.rs` the JSON, with `<`, `>` and `&` escaped;
//!   `assets.rs` the page (`server/dashboard/`) and the replay's pinned three.js, embedded,
//!   under a strict Content-Security-Policy; `state.rs` what the handlers share. It reads
//!   the simulation through `simulation/watch.rs` (`watching`, `watch_scene`: registry
//!   lookups that never mark an entry used) and each entry's `registry/activity.rs`
//!   `Activity`: counters the step jobs add to on the pool (atomics), with the entry's
//!   fixed facts (sizes, dt, the document's keyframes and sensors, which the page lists for
//!   the selected entry) and the dashboard's rate window.
//!
//! # Bounded cost
//!
//! Limits are checked before anything is created, counts and bytes: the structural ones
//! (instances, joints, DOFs, end effectors) right after parsing, before a world is built;
//! `--max-step-work` (envs × substeps × DOFs) and a batch's largest step reply against the
//! message limit before its envs are cloned. `--max-contact-work` (contact points ×
//! substeps per env step) is checked inside every step (a step over it fails with
//! RESOURCE_EXHAUSTED before its solver, naming the env where it was) and estimated at
//! creation by one collision detection of the initial state (`simulation/limits.rs`,
//! `check_contact_work`).
//!
//! Saved states (`SaveState`, `LoadState`, `SaveBatchState`, `LoadBatchState`, `Fork`) are
//! decoded on the pool; a fork goes through `CreateBatch`'s limits with the state's
//! document, and a batch's states are refused past the message limit. Documents in other
//! formats are converted on the pool (`simulation/documents.rs`, via `gymfleet-import`)
//! before parsing, so saved states and errors downstream always see assembly JSON;
//! `ConvertDocument` returns the conversion. A request's `assets` (an archive of mesh and
//! include files, with `document_path` saying where the model sits among them, so includes
//! and meshes resolve from its folder) are read there too, and the meshes are inlined into
//! the document.
//!
//! The test hook `panic_on_action` exists only in debug builds (`cfg(debug_assertions)`),
//! never in the release build that ships; it is not a cargo feature, so that no build
//! compiles the crate twice (README, "Build once").

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
