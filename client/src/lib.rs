//! The async Rust client of a gymfleet server. This crate owns the client side of the
//! `gymfleet.v1.Simulator` contract: connecting ([`Client`]), typed handles on
//! server-side environments ([`Env`]) and batches ([`Batch`]), zero-copy per-env views of
//! batch replies ([`BatchStep`], [`BatchObservations`]), pipelined stepping over one
//! stream ([`BatchStream`]), and a typed error per status class ([`ClientError`]).
//!
//! It mirrors the domain's names ([`ActionType`], [`Autoreset`], [`Observation`]) with
//! its own small types and never links the physics: simulation is the server's job.
//!
//! It also owns fleet sharding: a [`Fleet`] holds one connection per server (from a list
//! or a Kubernetes StatefulSet's per-pod names, [`FleetEndpoints`]) and splits a
//! [`FleetBatch`] across them in proportion to their simulation threads, stepping the
//! shards concurrently and returning one result in env order. Requests are never
//! load-balanced: an env's state lives on one server, and when that server is lost the
//! client says which envs went with it ([`ClientError::ServerLost`]). Running the fleet
//! (the image, the manifests) is `deploy/`'s job.
//!
//! ```no_run
//! use gymfleet_client::{ActionType, BatchOptions, Client};
//!
//! # async fn demo() -> gymfleet_client::Result<()> {
//! let client = Client::connect("127.0.0.1:50051").await?;
//! let document = std::fs::read_to_string("models/arm2.json").expect("model");
//! let batch = client
//!     .create_batch(BatchOptions::new(document, 256).end_effectors(["forearm"]))
//!     .await?;
//! let info = batch.info().clone();
//! batch.reset(Some(42)).await?;
//! let actions = vec![0.1_f32; info.n_envs * info.action_dim];
//! for _ in 0..10 {
//!     let step = batch.step(ActionType::Torque, &actions).await?;
//!     assert_eq!(step.obs(255).len(), info.observation_dim);
//! }
//! batch.close().await?;
//! # Ok(())
//! # }
//! ```
//!
//! # Modules
//!
//! - `client.rs`: the connection. `ClientBuilder`: connect timeout, per-call deadline (sent
//!   as `grpc-timeout`), HTTP/2 keepalive, TLS, bearer token (an interceptor adds it to
//!   every call), lazy connect. A `Client` calls through a boxed `Transport`: a channel, or
//!   (`ClientBuilder::in_process`) a simulator service running in the same process. Only
//!   `error.rs` and `types.rs` sit below it; every other module sits above it, and the
//!   modules form no cycle.
//! - `environment.rs` is the one reader of the `GYMFLEET_*` connection variables
//!   (`ClientBuilder::from_env`, used by the Python package) and names them (`ENV_TOKEN`,
//!   `ENV_TLS_*`) for `args.rs`'s `ConnectArgs`, the `--token`/`--tls-*` flag group the MCP
//!   adapter and the load client share.
//! - `env.rs` and `batch.rs`: the `Env` and `Batch` handles (each knows its `server()`),
//!   with `Client::create_env` and `create_batch` beside them. `options.rs`'s `EnvOptions`
//!   and `BatchOptions` get their setters from one list, `option_setters!`, and send the
//!   wire's one `EnvOptions`. A `BatchInfo` holds the batch's `EnvInfo`, read through it by
//!   `Deref`; `types/compat.rs` reads what older servers send (the flat `BatchInfo`, enums
//!   named only by their strings). `task.rs`: `Task` (reach, track and upright tasks for
//!   the create options). `BatchStep` views are zero-copy; `stream.rs`: the pipelined
//!   `BatchStream`.
//! - `error.rs`: `ClientError` (`#[non_exhaustive]`): `code()` gives the gRPC code,
//!   `kind()` an exhaustive `ErrorKind` that the Python package maps to its exception
//!   classes with no catch-all, `reason()` the server's `ErrorReason` (the proto's enum,
//!   read from the status metadata; the client's own checks that stand in for the server's
//!   carry the same reason), and `limit()` a refusing limit's flag. The MCP adapter decides
//!   on reasons (an id the server no longer has), never on message text; Python
//!   (`err.reason`, `err.limit`) and TypeScript (`err.reason`, `err.limit`) read the same
//!   entries. A server that cannot be reached is `ClientError::Connect`, whose message is
//!   `cannot_connect`'s (the address, the cause, "Is the server running?", how to point
//!   elsewhere): the Python package, the load client, the MCP adapter and the examples give
//!   it with their own way of pointing elsewhere, and the TypeScript client writes the same
//!   sentence (`cannotConnect`). A setting that cannot work (a malformed address, a bad
//!   token) is `ClientError::Setting`.
//! - `render.rs`: `Camera`, `Image`, `Env::render`/`Batch::render`, and `Scene` from
//!   `Env::scene` (`GetScene`). `replay.rs`: `Replay` records scenes frame by frame and
//!   writes one self-contained HTML page from `assets/replay.html`, embedding the pinned
//!   three.js r170 and its OrbitControls (`assets/three/`, MIT, with a README giving the
//!   version and sha256 sums) as `data:` modules, so the page opens offline.
//! - `document.rs`: `DocumentFormat` for the create options and `Client::convert_document`.
//!   `state.rs`: `EnvState` (opaque bytes), `Env::save_state`/`load_state`,
//!   `Batch::save_states`/`load_states`, `Client::fork`. `access.rs`:
//!   `Env::set_joint_state` and `Env::bodies` (`Bodies`).
//!
//! # Fleet sharding
//!
//! `endpoints.rs`, `placement.rs`, `fleet.rs`, `fanout.rs`, and `fleet_batch.rs` with its
//! children `fleet_batch/{losses,merge,recovery,reset,step,subset}.rs`.
//!
//! - `FleetEndpoints` is a list, or a StatefulSet's per-pod DNS names. `Fleet` holds one
//!   `Client` per server, never request-level balancing: an env's state lives on one
//!   server. `Fleet::connect` needs every server; `Fleet::connect_available` starts with
//!   those that answer, keeps lazy connections to the others, and places new envs and
//!   batches on the servers that answer when they are created.
//! - `FleetBatch` places envs in proportion to each server's `threads` (largest remainder,
//!   capped by its limits); shard `k` gets `seed_offset` = its first env index, so seeding
//!   does not depend on placement. It steps all shards concurrently and merges one
//!   `BatchStep` in env order (`step.rs`: the whole step, its checks and `finish_step`,
//!   which settles and merges the shards' replies; `merge.rs` the merge; `subset.rs`:
//!   `step_envs`, each shard stepping its listed envs, logged for recovery as
//!   `Logged::StepEnvs`; `reset.rs` resets every shard's share at once, `reset_envs_to` a
//!   keyframe by name). Its calls take `&mut self` (no locks inside); `fanout.rs` runs one
//!   call on every server concurrently.
//! - `FleetBatch::from(Batch)` is one server's batch as a fleet batch of one shard: its
//!   calls go straight to the server (one call runs inline, not as a task), its replies are
//!   not copied, and its errors are the server's own (no loss, no `OnServer`); the Python
//!   package drives every batch through `FleetBatch` so.
//! - A lost server yields `ClientError::ServerLost` naming it and the env ranges lost
//!   (`losses.rs`: which errors are losses, settling the shards' outcomes); `drop_lost`
//!   continues with the survivors. `recovery.rs`: with `checkpoint_every(K)` the batch
//!   keeps every env's `EnvState` and a log of the steps and resets since; `recover` forks
//!   each lost shard's first state on a survivor (or a given replacement), loads the
//!   shard's states, replays the log and puts the new batch in the shard's place.

mod access;
mod args;
mod batch;
mod client;
mod document;
mod endpoints;
mod env;
mod environment;
mod error;
mod fanout;
mod fleet;
mod fleet_batch;
mod options;
mod placement;
mod render;
mod replay;
mod state;
mod stream;
mod task;
mod types;

pub use access::Bodies;
pub use args::ConnectArgs;
pub use batch::{Batch, BatchObservations, BatchStep};
pub use client::{
    with_deadline, CallService, Client, ClientBuilder, Transport, TransportError,
    DEFAULT_CONNECT_TIMEOUT, DEFAULT_KEEPALIVE_INTERVAL, DEFAULT_KEEPALIVE_TIMEOUT,
    DEFAULT_MAX_MESSAGE_BYTES,
};
pub use document::{ConvertedDocument, DocumentFormat, ModelInfo};
pub use endpoints::FleetEndpoints;
pub use env::Env;
pub use environment::{
    ENV_TLS_CA, ENV_TLS_CLIENT_CERT, ENV_TLS_CLIENT_KEY, ENV_TLS_DOMAIN, ENV_TOKEN,
};
pub use error::{cannot_connect, ClientError, ErrorKind, ErrorReason, Result, POINT_THE_LIBRARY};
pub use fleet::Fleet;
pub use fleet_batch::recovery::CheckpointStatus;
pub use fleet_batch::{FleetBatch, ShardPlacement};
/// The status metadata entries that carry an error's reason and a refusing limit's flag.
pub use gymfleet_proto::{LIMIT_KEY, REASON_KEY};
pub use options::{BatchOptions, EnvOptions, PdGains};
pub use render::{Camera, CameraPreset, Image, Scene, SceneBody, SceneJoint, SceneShape};
pub use replay::{Replay, ReplayMismatch};
pub use state::EnvState;
pub use stream::{BatchStream, DEFAULT_STREAM_WINDOW};
pub use task::{
    Randomization, RandomizationDraws, ReachTask, Task, TaskKind, TrackTask, UprightTask,
};
/// gRPC status codes, as [`ClientError::code`] returns them.
pub use tonic::Code;
pub use types::{
    ActionType, ActuatorInfo, Autoreset, BatchInfo, DofLimit, DofUnit, EnvInfo, JointInfo,
    JointType, Observation, ServerInfo, ServerLimits, StepResult, TerminationReason, Units,
    POSE_LEN,
};
