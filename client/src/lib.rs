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
