//! [`StepPool`]: an explicit rayon pool plus the fair chunk queue that every batch on
//! it shares.
//!
//! A step of a batch is a *task* of a fixed number of *chunks*. The task goes to the
//! back of one queue per pool. Whoever drains the queue (a pool thread, or a caller
//! waiting for its own task) takes the front task, claims its next chunk, and puts the
//! task back at the end of the queue if it has chunks left. So tasks take turns chunk by
//! chunk: a one-chunk task submitted behind a thousand-chunk one waits for about one
//! chunk per draining thread, not for the whole big task.

use std::fmt;
use std::num::NonZeroUsize;
use std::panic::{self, AssertUnwindSafe};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread;
use std::time::Instant;

use crate::caller::runs_jobs_here;
use crate::error::{BatchError, Result};
use crate::queue::{ChunkPanic, Claims, FairQueue, OneOff, QueuedTask, Task};

/// Stack of each pool thread, bytes. Documents are converted and validated on the pool,
/// some of it recursively over the body tree (bounded by
/// `gymfleet_import::MAX_BODY_DEPTH`); Rust's default of 2 MiB holds about 300 nested
/// bodies in a debug build. The stack is reserved, not committed: untouched pages cost
/// no memory.
pub const POOL_STACK_BYTES: usize = 16 << 20;

/// A pool of step threads shared by many batches, scheduled fairly across them.
///
/// Cloning gives another handle to the same pool. The threads stop once the last
/// handle is dropped and their queued work is done.
#[derive(Clone)]
pub struct StepPool {
    inner: Arc<PoolInner>,
}

struct PoolInner {
    pool: rayon::ThreadPool,
    queue: Arc<FairQueue>,
    jobs: Arc<JobStats>,
}

/// Counts of the jobs given to [`StepPool::spawn`] and [`StepPool::spawn_fair`].
#[derive(Default)]
struct JobStats {
    /// Handed over, not yet started.
    waiting: AtomicUsize,
    /// Started so far.
    started: AtomicU64,
    /// Nanoseconds the started ones waited for a thread, in all.
    waited_ns: AtomicU64,
}

impl JobStats {
    /// `f`, counted as waiting from now until it starts.
    fn track<F: FnOnce() + Send + 'static>(
        self: &Arc<Self>,
        f: F,
    ) -> impl FnOnce() + Send + 'static {
        let stats = Arc::clone(self);
        let queued = Instant::now();
        stats.waiting.fetch_add(1, Ordering::Relaxed);
        move || {
            let waited = u64::try_from(queued.elapsed().as_nanos()).unwrap_or(u64::MAX);
            stats.waiting.fetch_sub(1, Ordering::Relaxed);
            stats.started.fetch_add(1, Ordering::Relaxed);
            stats.waited_ns.fetch_add(waited, Ordering::Relaxed);
            f();
        }
    }
}

/// How the pool's jobs have waited for a thread, for metrics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct JobQueueStats {
    /// Jobs handed to the pool and not yet started.
    pub waiting: usize,
    /// Jobs started so far.
    pub started: u64,
    /// Time the started jobs waited for a thread, in all, in nanoseconds.
    pub waited_ns: u64,
}

impl StepPool {
    /// Starts `threads` threads named `gymfleet-step-N`, at the process's own priority;
    /// 0 means one per core this process may use ([`usable_cores`]).
    pub fn new(threads: usize) -> Result<Self> {
        Self::with_niceness(threads, 0)
    }

    /// [`StepPool::new`], with the threads at scheduling niceness `niceness` (Linux; 0
    /// leaves them at the process's own, 1..=19 run them below it). Nicer threads let a
    /// multi-tenant server's network threads answer at once however busy the pool is
    /// ([`FAIR_POOL_NICENESS`]), but they also lose the CPU to every process at the default
    /// priority beside them, a trainer's own threads included: keep 0 wherever the pool
    /// shares its machine with other work. A process already nicer than `niceness` keeps
    /// its own (raising priority needs privileges).
    pub fn with_niceness(threads: usize, niceness: u8) -> Result<Self> {
        let threads = if threads == 0 {
            usable_cores()
        } else {
            threads
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("gymfleet-step-{i}"))
            .stack_size(POOL_STACK_BYTES)
            .start_handler(move |_| {
                if niceness > 0 {
                    lower_priority(niceness);
                }
            })
            // The default hook has already printed the panic; without a handler a
            // panic in a `spawn`ed closure would abort the whole process.
            .panic_handler(|_| {})
            .build()
            .map_err(|e| BatchError::PoolStart {
                threads,
                reason: e.to_string(),
            })?;
        Ok(StepPool {
            inner: Arc::new(PoolInner {
                pool,
                queue: Arc::new(FairQueue::default()),
                jobs: Arc::new(JobStats::default()),
            }),
        })
    }

    /// The number of threads in the pool.
    pub fn threads(&self) -> usize {
        self.inner.pool.current_num_threads()
    }

    /// Runs `f` on a pool thread (e.g. a whole batch step, whose result `f` hands back
    /// through a channel). Never blocks the caller (but see below). A panic in `f` is
    /// printed by the panic hook and otherwise ignored: `f`'s captures are dropped, so a
    /// channel sender in them tells the receiver.
    ///
    /// Inside [`crate::run_jobs_here`], `f` runs at once on the calling thread instead.
    pub fn spawn<F: FnOnce() + Send + 'static>(&self, f: F) {
        let job = self.inner.jobs.track(f);
        if runs_jobs_here() {
            run_caught(job);
        } else {
            self.inner.pool.spawn(job);
        }
    }

    /// How many jobs ([`StepPool::spawn`], [`StepPool::spawn_fair`]) wait for a thread,
    /// and how long the started ones waited.
    pub fn job_queue(&self) -> JobQueueStats {
        let jobs = &self.inner.jobs;
        JobQueueStats {
            waiting: jobs.waiting.load(Ordering::Relaxed),
            started: jobs.started.load(Ordering::Relaxed),
            waited_ns: jobs.waited_ns.load(Ordering::Relaxed),
        }
    }

    /// Runs `f` on a pool thread as a one-chunk task of the fair queue: it takes its turn
    /// with the chunks of running batch steps, so it waits for about one chunk per
    /// thread rather than for whole batch steps queued before it (a single env's step
    /// beside a tenant's 16k-env batches). `f` must not wait on other pool work (no
    /// batch steps inside: use [`StepPool::spawn`] for those). A panic in `f` is
    /// caught and dropped, as with `spawn`.
    ///
    /// Inside [`crate::run_jobs_here`], `f` runs at once on the calling thread instead:
    /// the caller's own thread takes no turn from anyone.
    pub fn spawn_fair<F: FnOnce() + Send + 'static>(&self, f: F) {
        if runs_jobs_here() {
            return self.spawn(f);
        }
        let task = Arc::new(OneOff {
            job: Mutex::new(Some(self.inner.jobs.track(f))),
        });
        let queue = &self.inner.queue;
        queue.push(task as Arc<dyn QueuedTask>);
        let queue = Arc::clone(queue);
        self.inner.pool.spawn(move || queue.drain(None));
    }

    /// Runs `f` on a pool thread and returns its result, blocking the caller. A step
    /// called this way is worked on by the pool's threads only; called directly from a
    /// thread outside the pool, the caller runs chunks too, one thread more than
    /// [`StepPool::threads`] (inside [`crate::run_jobs_here`], only a step of one chunk).
    /// From a thread of this pool, `f` runs in place.
    pub fn install<R: Send, F: FnOnce() -> R + Send>(&self, f: F) -> R {
        self.inner.pool.install(f)
    }

    /// How many chunks (of any batch) have been run on this pool so far. A progress
    /// counter for metrics and tests.
    pub fn chunks_run(&self) -> u64 {
        self.inner.queue.chunks_run.load(Ordering::Relaxed)
    }

    /// Runs `work(0..n_chunks)`, each index once, on the pool and on the calling thread,
    /// and returns when all are done. Chunks of concurrent calls are interleaved fairly.
    /// Each pool thread takes its own block of the chunks first ([`Claims`]), so a batch's
    /// envs stay on one core from step to step.
    ///
    /// Deadlock-free from any thread, pool threads included: the caller runs chunks
    /// itself while some of its own are unclaimed, and blocks only once every one of
    /// them is running somewhere, and running chunks never wait on anything. (Inside
    /// [`crate::run_jobs_here`], from outside the pool, a caller of several chunks only
    /// waits: the pool's threads take them all.)
    pub(crate) fn run_chunked<W>(&self, n_chunks: usize, work: W) -> Result<(), ChunkPanic>
    where
        W: Fn(usize) + Send + Sync + 'static,
    {
        if n_chunks == 0 {
            return Ok(());
        }
        let task = Arc::new(Task {
            work,
            claims: Claims::new(n_chunks, self.threads()),
            remaining: AtomicUsize::new(n_chunks),
            panic: Mutex::new(None),
            waiter: thread::current(),
        });
        let queue = &self.inner.queue;
        queue.push(Arc::clone(&task) as Arc<dyn QueuedTask>);
        // A caller inside `run_jobs_here` runs a one-chunk task alone and leaves a task
        // of several chunks to the pool's threads. Running chunks beside them, it would
        // take a core from one (as many threads as cores); beside one fewer of them, it
        // would not save that one from being woken: a rayon thread that finds work wakes
        // a sleeping one, which then spins on the cores the work needs.
        let here = runs_jobs_here();
        let (helpers, helps) = match (here, n_chunks) {
            (true, 1) => (0, true),
            (true, _) => (self.threads().min(n_chunks), false),
            (false, _) => (self.threads().min(n_chunks), true),
        };
        // Such a caller steps again soon, so its helpers linger for the next step, and a
        // helper still lingering from the last one is not woken again. (A caller that
        // counts a lingering helper pushed its task before it looked: see `drain`.)
        let linger = here.then_some(HELPERS_LINGER);
        let awake = queue.lingering.load(Ordering::SeqCst).min(helpers);
        for _ in awake..helpers {
            let queue = Arc::clone(queue);
            self.inner.pool.spawn(move || queue.drain(linger));
        }
        while task.remaining.load(Ordering::Acquire) != 0 {
            // Help while chunks of ours are unclaimed (taking turns with other tasks);
            // once all are claimed, wait for the threads running them.
            if !helps || task.claims.all_claimed() || !queue.run_one() {
                thread::park();
            }
        }
        let panic = task
            .panic
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take();
        panic.map_or(Ok(()), Err)
    }
}

impl fmt::Debug for StepPool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("StepPool")
            .field("threads", &self.threads())
            .field("chunks_run", &self.chunks_run())
            .finish()
    }
}

/// How long a helper of a [`crate::run_jobs_here`] caller's step waits, spinning politely
/// (`yield_now`), for the caller's next step once the queue is empty, before it goes back
/// to rayon (which puts it to sleep). The Python package's own work between two
/// `make_vec` steps fits in it, so the next step starts without a thread wake-up:
/// HalfCheetah's 64-env step 567.5 → 540.5 and 575.5 → 528 µs, medians of two sets of
/// eight alternated runs (bench/journal/2026-12-07-benchmarks-notebook.md, "The calling thread runs its own pool work"). A
/// caller that comes back later pays for the wait: up to about 1 % there. Lingering only
/// for a caller that came back within the linger last time was tried beside a policy's
/// forward pass and busy neighbours, and lost (BENCHMARKS.md N1).
pub const HELPERS_LINGER: std::time::Duration = std::time::Duration::from_micros(100);

/// Runs `job` as a pool thread would: a panic is printed by the panic hook and dropped.
fn run_caught(job: impl FnOnce()) {
    let _ = panic::catch_unwind(AssertUnwindSafe(job));
}

/// The niceness a multi-tenant server's pool runs at when it asks for fairness between
/// tenants (`gymfleet-server --pool-niceness 10`, as the Kubernetes manifests set it):
/// below the default 0 of the threads that answer the network. A pool as busy as its
/// cores then still lets the server's I/O threads run the moment a request arrives,
/// instead of after a time slice: on 2 cores with both pool threads stepping 16k-env
/// batches, another tenant's single-env `Step` p99 went from 13× to 2.3× its idle value
/// (BENCHMARKS.md I1). The price: beside any other process at the default priority the
/// pool gets about a tenth of a core per thread (BENCHMARKS.md N1), so it is never the
/// default.
pub const FAIR_POOL_NICENESS: u8 = 10;

/// The cores this process may run on: its CPU affinity and its cgroup's CPU quota (a
/// container's `--cpus`, a Kubernetes CPU limit), as [`thread::available_parallelism`]
/// reads them on Linux, rather than the machine's count; at least 1.
pub fn usable_cores() -> usize {
    thread::available_parallelism().map_or(1, NonZeroUsize::get)
}

/// Lowers the calling thread's priority to niceness `niceness`. A process already running
/// nicer than that keeps its own (raising priority needs privileges), so failure is
/// not an error.
fn lower_priority(niceness: u8) {
    use thread_priority::{ThreadPriority, ThreadPriorityValue};
    // thread-priority maps its 0..=99 onto niceness `(39 × (1 − p/99)) as i8 − 20` for
    // normal threads (19 down to -20); this inverts that (10 → 22).
    let p = 99.0 * (1.0 - f64::from(i32::from(niceness.min(19)) + 20) / 39.0);
    if let Ok(value) = ThreadPriorityValue::try_from(p as u8) {
        let _ = thread_priority::set_current_thread_priority(ThreadPriority::Crossplatform(value));
    }
}

#[cfg(test)]
mod tests {
    use std::sync::{Arc, Mutex};
    use std::thread;

    use super::*;

    #[test]
    fn a_panicking_chunk_is_reported_and_the_others_still_run() {
        let pool = StepPool::new(2).unwrap();
        let ran = Arc::new(AtomicUsize::new(0));
        let counter = Arc::clone(&ran);
        let result = pool.run_chunked(6, move |i| {
            counter.fetch_add(1, Ordering::SeqCst);
            if i == 4 || i == 2 {
                panic!("chunk {i} exploded");
            }
        });
        let panic = result.unwrap_err();
        assert_eq!(panic.chunk, 2);
        assert_eq!(panic.message, "chunk 2 exploded");
        assert_eq!(ran.load(Ordering::SeqCst), 6);
        // The pool still works.
        assert!(pool.run_chunked(3, |_| {}).is_ok());
        assert_eq!(pool.chunks_run(), 9);
    }

    /// The calling thread's scheduling niceness, read from the kernel.
    #[cfg(target_os = "linux")]
    fn niceness() -> i32 {
        let stat = std::fs::read_to_string("/proc/thread-self/stat").unwrap();
        // Fields after the command name (in parentheses); nice is field 19.
        let after = stat.rsplit_once(')').unwrap().1;
        after.split_whitespace().nth(16).unwrap().parse().unwrap()
    }

    /// A plain pool's threads run at the process's own priority, so that they do not
    /// starve beside a trainer's threads (issue P2).
    #[cfg(target_os = "linux")]
    #[test]
    fn pool_threads_run_at_the_process_priority() {
        let ours = niceness();
        for pool in [
            StepPool::new(2).unwrap(),
            StepPool::with_niceness(2, 0).unwrap(),
        ] {
            let theirs = pool.install(niceness);
            assert_eq!(theirs, ours, "caller at {ours}");
        }
    }

    /// A pool asked for fairness runs nicer than the network threads.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_fair_pool_runs_nicer_than_the_rest() {
        let ours = niceness();
        let pool = StepPool::with_niceness(1, FAIR_POOL_NICENESS).unwrap();
        let theirs = pool.install(niceness);
        assert_eq!(
            theirs,
            i32::from(FAIR_POOL_NICENESS).max(ours),
            "caller at {ours}"
        );
        let pool = StepPool::with_niceness(1, 19).unwrap();
        assert_eq!(pool.install(niceness), 19);
    }

    /// A one-off job waits for about one chunk per thread behind a running many-chunk
    /// step, not for the whole step. No sleeps and no reliance on timing: every chunk waits
    /// at a gate that opens only once the job is queued, and every chunk past the two held
    /// there (one per drainer) then waits until the job has started. The queue hands the
    /// job out right after the held chunks and at most one more, so a drainer is always
    /// left to run it; had it been queued behind more chunks, both drainers would wait
    /// on chunks of the step and the waits would time out.
    #[test]
    fn a_fair_job_overtakes_a_long_step() {
        use std::sync::{Condvar, RwLock};
        use std::time::Duration;
        let pool = StepPool::new(1).unwrap();
        let gate = Arc::new(RwLock::new(()));
        let closed = gate.write().unwrap();
        let fair_started = Arc::new((Mutex::new(false), Condvar::new()));
        let (started_tx, started_rx) = std::sync::mpsc::channel();
        // Chunks past the held ones that ran without seeing the job started.
        let overtaken = Arc::new(Mutex::new(Vec::new()));
        let step_pool = pool.clone();
        let step_gate = Arc::clone(&gate);
        let step_fair = Arc::clone(&fair_started);
        let step_overtaken = Arc::clone(&overtaken);
        let step = thread::spawn(move || {
            step_pool
                .run_chunked(200, move |i| {
                    if i == 0 {
                        started_tx.send(()).unwrap();
                    }
                    drop(step_gate.read().unwrap());
                    // Once one has waited in vain, the rest need not (a failure takes 10 s).
                    if i >= 2 && step_overtaken.lock().unwrap().is_empty() {
                        let (started, changed) = &*step_fair;
                        let guard = started.lock().unwrap();
                        let (guard, _) = changed
                            .wait_timeout_while(guard, Duration::from_secs(10), |s| !*s)
                            .unwrap();
                        if !*guard {
                            step_overtaken.lock().unwrap().push(i);
                        }
                    }
                })
                .unwrap();
        });
        // The step is queued and running (its chunk 0 is held at the gate).
        started_rx.recv().unwrap();
        let (done_tx, done_rx) = std::sync::mpsc::channel();
        let job_fair = Arc::clone(&fair_started);
        pool.spawn_fair(move || {
            let (started, changed) = &*job_fair;
            *started.lock().unwrap() = true;
            changed.notify_all();
            done_tx.send(()).unwrap();
        });
        drop(closed);
        done_rx.recv().unwrap();
        step.join().unwrap();
        let jobs = pool.job_queue();
        assert_eq!((jobs.waiting, jobs.started), (0, 1));
        assert!(jobs.waited_ns > 0);
        let overtaken = overtaken.lock().unwrap();
        assert!(
            overtaken.is_empty(),
            "chunks {overtaken:?} ran before the fair job started"
        );
    }
}
