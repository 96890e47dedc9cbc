//! Batches of gymfleet environments, stepped in parallel and scheduled fairly.
//!
//! This crate owns [`EnvBatch`] — `n_envs` clones of one [`gymfleet_env::RobotEnv`],
//! validated as a whole, stepped together, with the three [`Autoreset`] modes of
//! docs/design.md §3 — and the scheduler that runs them: [`StepPool`], an explicit rayon
//! pool sized to the cores, whose fair chunk queue makes many batches from many
//! clients take turns chunk by chunk, so a small batch is never stuck behind a huge
//! one. Results are bitwise identical whatever the thread count or chunking.
//!
//! It is a plain synchronous library: it knows nothing of tokio, tonic, prost or any
//! wire format. Episode semantics stay in `gymfleet-env`; ids, sessions and the async
//! hand-off to the pool (e.g. [`StepPool::spawn`] plus a oneshot) belong to the server.

mod batch;
mod caller;
mod chunk;
mod error;
mod mocap;
mod pool;
mod queue;
mod subset;
mod terrain;

pub use batch::{default_chunk_size, Autoreset, BatchStepOutput, EnvBatch, MAX_DEFAULT_CHUNK_SIZE};
pub use caller::run_jobs_here;
pub use error::{BatchError, Result};
pub use pool::{
    usable_cores, JobQueueStats, StepPool, FAIR_POOL_NICENESS, HELPERS_LINGER, POOL_STACK_BYTES,
};
pub use queue::panic_message;
