//! The async Rust client of a gymfleet server. This crate owns the client side of the
//! `gymfleet.v1.Simulator` contract: connecting ([`Client`]), typed handles on
//! server-side environments ([`Env`]) and batches ([`Batch`]), zero-copy per-env views of
//! batch replies ([`BatchStep`], [`BatchObservations`]), pipelined stepping over one
//! stream ([`BatchStream`]), and a typed error per status class ([`ClientError`]).
//!
//! It mirrors the domain's names ([`ActionType`], [`Autoreset`], [`Observation`]) with
//! its own small types and never links the physics: simulation is the server's job.
//! Fleet sharding across servers is left for later.
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

mod batch;
mod client;
mod env;
mod error;
mod options;
mod stream;
mod types;

pub use batch::{Batch, BatchObservations, BatchStep, DEFAULT_STREAM_WINDOW};
pub use client::{Client, DEFAULT_MAX_MESSAGE_BYTES};
pub use env::Env;
pub use error::{ClientError, Result};
pub use options::{BatchOptions, EnvOptions, PdGains};
pub use stream::BatchStream;
pub use types::{
    ActionType, Autoreset, BatchInfo, DofLimit, EnvInfo, JointInfo, Observation, ServerInfo,
    ServerLimits, StepResult, POSE_LEN,
};
