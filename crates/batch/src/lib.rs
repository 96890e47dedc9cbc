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
//!
//! # Modules
//!
//! - `batch.rs`: `EnvBatch`, `n_envs` clones of one `RobotEnv` (no re-parse), actions
//!   validated as a whole, the three autoreset modes (`disabled`, `same_step`,
//!   `next_step`). `save_states`/`load_states` save and load chosen envs' `SavedState`s
//!   (all checked before any loads); `copies_of` builds a batch of exact copies of one env
//!   without resetting them (the server's `Fork`). Past `PREFETCH_ABOVE_ENVS_PER_THREAD`
//!   (64) envs per pool thread, a chunk prefetches each env's state while the env before it
//!   steps (`RobotEnv::prefetch`). Its errors are structured (`BatchError::TooManyEnvs`,
//!   `PoolStart`, `Panicked { first, last, message }`), so the server maps them without
//!   reading text.
//! - `chunk.rs`: a chunk of consecutive envs, the unit of scheduling; `subset.rs`:
//!   `step_envs`, a step of some envs (an asynchronous trainer's): the chunks step only
//!   their marked envs (`Chunk::step_marks`), each as in a whole step, and the output has
//!   the listed envs' rows. `mocap.rs`: `step_with_mocap`, every env's mocap targets with a
//!   batch step, checked with the actions before any env changes. `terrain.rs`:
//!   `set_heightfield` in chosen envs, checked once.
//! - `pool.rs`: `StepPool`, an explicit rayon pool with a fair chunk queue: each step call
//!   enqueues a work item and threads take chunks round-robin across items, so a small
//!   batch is never stuck behind a huge one; the caller helps drain while it waits, so it
//!   cannot deadlock. `spawn_fair` puts a one-off job (the server's single-env work) into
//!   the same queue, so it waits for about one chunk per thread, not for whole batch steps.
//!   With no thread count given the pool has one thread per core the process may use
//!   (`usable_cores`: its CPU affinity and cgroup quota). The threads have 16 MiB stacks
//!   (`POOL_STACK_BYTES`, reserved, not committed: documents are converted there,
//!   recursively over a body tree of bounded depth). They run at the process's own
//!   priority, so that an embedded server does not starve beside its trainer; a server
//!   given a machine of its own can run them nicer (`StepPool::with_niceness`, the server's
//!   `--pool-niceness`; `FAIR_POOL_NICENESS` is 10, the value the Kubernetes manifests
//!   set), so that its network threads answer at once however busy the pool is.
//!   `job_queue()` counts waiting jobs and their wait, for metrics.
//! - `queue.rs`: the fair queue itself (`FairQueue`: `run_one` takes turns chunk by chunk,
//!   `drain` runs chunks until it is empty and lingers if asked; a caller that counted a
//!   lingering drainer pushed its task before it looked, so the drainer's last look after
//!   leaving the count sees it). Within a step each pool thread claims its own block of the
//!   chunks first and then steals from the back of the fullest block (`Claims`), so an env
//!   is stepped on the same core step after step and its state stays in that core's cache.
//!   `panic_message` is the one panic-payload-to-string.
//! - `caller.rs`: inside `run_jobs_here`, a thread that would only block on its own pool
//!   jobs runs them itself (`spawn`, `spawn_fair`, and a one-chunk step). A step of several
//!   chunks goes to the pool's threads, whose last chunk wakes the caller directly, and
//!   which then linger for `HELPERS_LINGER` (100 µs) for the caller's next step before they
//!   sleep. This saves the wake-ups of a hand-off; the Python package's calls to its
//!   embedded server without a deadline run so.

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
