//! Running CPU work on the simulation pool and getting the answer back on the async side.
//!
//! Parsing, building, resetting and stepping never run on tokio worker threads: each is
//! a job handed to the [`StepPool`], whose answer comes back through a oneshot channel.
//! Every job runs under `catch_unwind`, so a panic (a bug) becomes an INTERNAL error for
//! its caller instead of aborting the process. The env or batch a panicking job ran on is
//! closed: its state may be half-updated, and serving it again could return garbage.
//!
//! A job whose caller has gone by the time a thread takes it up (the call's deadline
//! passed, or its connection closed, so tonic dropped the call) is not run at all.
//!
//! Jobs on one env take their turn in the pool's fair queue ([`Lane::Env`]), so a
//! single env's step waits for about one chunk per thread, not for whole batch steps
//! queued before it; jobs that run a batch's chunks themselves coordinate from a plain
//! pool thread ([`Lane::Batch`]).

use gymfleet_batch::{panic_message, BatchError, StepPool};
use std::ops::Deref;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;
use tokio::sync::oneshot;

use crate::error::{Result, ServerError};
use crate::registry::{Entry, Registry};

/// How a job is scheduled on the pool.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Lane {
    /// Work on one env, which never waits on other pool work: a one-chunk task of the
    /// fair queue.
    Env,
    /// Work that runs a batch's chunks and waits for them: a pool thread of its own.
    Batch,
}

/// The simulation pool as the server's jobs use it: the [`StepPool`] (which it derefs
/// to) and, in debug builds only, the test gate of `ServerConfig::job_gate`.
#[derive(Clone)]
pub(crate) struct Jobs {
    pool: StepPool,
    #[cfg(debug_assertions)]
    gate: Option<JobGate>,
}

impl Jobs {
    pub(crate) fn new(pool: StepPool, config: &crate::ServerConfig) -> Self {
        #[cfg(not(debug_assertions))]
        let _ = config;
        Jobs {
            pool,
            #[cfg(debug_assertions)]
            gate: config.job_gate.clone(),
        }
    }

    fn spawn_in(&self, lane: Lane, job: impl FnOnce() + Send + 'static) {
        match lane {
            Lane::Env => self.pool.spawn_fair(job),
            Lane::Batch => self.pool.spawn(job),
        }
    }

    /// What a job does before it looks whether its caller is still there.
    fn hold(&self) -> Hold {
        Hold {
            #[cfg(debug_assertions)]
            gate: self.gate.clone(),
        }
    }
}

impl Deref for Jobs {
    type Target = StepPool;

    fn deref(&self) -> &StepPool {
        &self.pool
    }
}

/// Nothing in a release build; in a debug build, waits at the test gate if there is one.
struct Hold {
    #[cfg(debug_assertions)]
    gate: Option<JobGate>,
}

impl Hold {
    fn wait<T>(&self, _caller: &oneshot::Sender<T>) {
        #[cfg(debug_assertions)]
        if let Some(gate) = &self.gate {
            gate.hold(_caller);
        }
    }
}

/// Test-only, in debug builds (`ServerConfig::job_gate`): while the gate is closed, every
/// pool job waits, before it starts, until the gate opens or its caller has gone (the
/// call's deadline passed or it was cancelled). [`JobGate::abandoned`] counts the jobs
/// let go because their caller had gone. Tests of abandoned work wait on these events
/// instead of racing the clock with sleeps and deadlines.
#[cfg(debug_assertions)]
#[doc(hidden)]
#[derive(Clone, Debug, Default)]
pub struct JobGate(std::sync::Arc<GateState>);

/// Two handles are equal when they are the same gate.
#[cfg(debug_assertions)]
impl PartialEq for JobGate {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

#[cfg(debug_assertions)]
#[derive(Debug, Default)]
struct GateState {
    closed: std::sync::atomic::AtomicBool,
    abandoned: std::sync::atomic::AtomicUsize,
}

#[cfg(debug_assertions)]
impl JobGate {
    /// Holds the jobs that start from now on.
    pub fn close(&self) {
        self.0
            .closed
            .store(true, std::sync::atomic::Ordering::SeqCst);
    }

    /// Lets every job go.
    pub fn open(&self) {
        self.0
            .closed
            .store(false, std::sync::atomic::Ordering::SeqCst);
    }

    /// How many held jobs were let go because their caller had gone.
    pub fn abandoned(&self) -> usize {
        self.0.abandoned.load(std::sync::atomic::Ordering::SeqCst)
    }

    fn hold<T>(&self, caller: &oneshot::Sender<T>) {
        use std::sync::atomic::Ordering::SeqCst;
        while self.0.closed.load(SeqCst) {
            if caller.is_closed() {
                self.0.abandoned.fetch_add(1, SeqCst);
                return;
            }
            // A test gate: how soon a held job notices does not change what it does.
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }
}

/// Runs `job` on the pool and waits for its answer.
pub(crate) async fn run<R, F>(jobs: &Jobs, lane: Lane, operation: &'static str, job: F) -> Result<R>
where
    R: Send + 'static,
    F: FnOnce() -> Result<R> + Send + 'static,
{
    let (tx, rx) = oneshot::channel();
    let hold = jobs.hold();
    jobs.spawn_in(lane, move || {
        hold.wait(&tx);
        if tx.is_closed() {
            // The caller has gone: nobody would see the answer.
            return;
        }
        let answer = catch_unwind(AssertUnwindSafe(job)).map_err(|p| panic_message(p.as_ref()));
        // The caller may have gone (a cancelled RPC): nobody is left to answer.
        let _ = tx.send(answer);
    });
    match rx.await {
        Ok(Ok(result)) => result,
        Ok(Err(message)) => {
            tracing::error!(operation, %message, "pool job panicked");
            Err(ServerError::Panicked {
                operation,
                id: None,
                message,
            })
        }
        Err(_) => Err(ServerError::JobLost { operation }),
    }
}

/// Locks `entry`, runs `job` on its value on the pool, and waits for the answer. The lock
/// is held until the job ends, even if the caller goes away meanwhile, and the entry counts
/// as used when the job ends: a step longer than the idle TTL, whose caller gave up, is not
/// reclaimed the moment it ends.
pub(crate) async fn run_locked<T, R, F>(
    jobs: &Jobs,
    lane: Lane,
    registry: &Registry<T>,
    entry: &Arc<Entry<T>>,
    operation: &'static str,
    job: F,
) -> Result<R>
where
    T: Send + 'static,
    R: Send + 'static,
    F: FnOnce(&mut T) -> Result<R> + Send + 'static,
{
    let mut slot = entry.lock(registry.kind()).await?;
    let kind = registry.kind();
    let id = entry.id().to_string();
    let (tx, rx) = oneshot::channel();
    let hold = jobs.hold();
    let used = Arc::clone(entry);
    jobs.spawn_in(lane, move || {
        hold.wait(&tx);
        if tx.is_closed() {
            // The caller has gone: leave the env as it is (the lock goes with `slot`).
            return;
        }
        let outcome = catch_unwind(AssertUnwindSafe(|| match slot.as_mut() {
            Some(held) => job(&mut held.value),
            None => Err(ServerError::NotFound { kind, id }),
        }));
        let answer = match outcome {
            Ok(Err(err)) if err.poisons_entry() => Err(poison_message(&err)),
            Ok(result) => Ok(result),
            Err(payload) => Err(panic_message(payload.as_ref())),
        };
        if answer.is_err() {
            let broken = slot.take();
            // Dropping a value whose invariants a panic broke may itself panic.
            let _ = catch_unwind(AssertUnwindSafe(move || drop(broken)));
        }
        used.touch();
        drop(slot);
        let _ = tx.send(answer);
    });
    let answer = rx.await.map_err(|_| ServerError::JobLost { operation })?;
    entry.touch();
    match answer {
        Ok(result) => result,
        Err(message) => {
            registry.remove(entry.id());
            tracing::error!(operation, id = entry.id(), %message, "pool job panicked; closed it");
            Err(ServerError::Panicked {
                operation,
                id: Some(entry.id().to_string()),
                message,
            })
        }
    }
}

/// What went wrong, for an error that poisons its entry. The batch crate's advice to
/// reset is left out: the server closes the batch instead.
fn poison_message(err: &ServerError) -> String {
    match err {
        ServerError::Batch(BatchError::Panicked {
            first,
            last,
            message,
        }) => format!("envs {first}..={last} panicked ({message})"),
        other => other.to_string(),
    }
}
