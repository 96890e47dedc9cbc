//! The fair chunk queue a [`crate::StepPool`] shares among its tasks: tasks take turns
//! chunk by chunk ([`FairQueue::run_one`]), and the pool's drainers run chunks until the
//! queue is empty ([`FairQueue::drain`]), lingering a little for more when their caller
//! comes back soon. Within a task, each pool thread claims its own block of chunks first
//! ([`Claims`]).

use std::cmp::Reverse;
use std::collections::VecDeque;
use std::panic::{self, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::{self, Thread};
use std::time::{Duration, Instant};

/// A chunk that panicked.
#[derive(Debug)]
pub(crate) struct ChunkPanic {
    /// Its index.
    pub(crate) chunk: usize,
    /// The panic message, when it was a string.
    pub(crate) message: String,
}

/// The round-robin queue of tasks with unclaimed chunks.
#[derive(Default)]
pub(crate) struct FairQueue {
    tasks: Mutex<VecDeque<Arc<dyn QueuedTask>>>,
    pub(crate) chunks_run: AtomicU64,
    /// Whether `tasks` has a task, as of the last change under its lock.
    nonempty: AtomicBool,
    /// Drainers waiting a little for more work before they go back to rayon.
    pub(crate) lingering: AtomicUsize,
}

impl FairQueue {
    fn lock(&self) -> MutexGuard<'_, VecDeque<Arc<dyn QueuedTask>>> {
        // Nothing panics while holding the lock; recover rather than cascade if it did.
        self.tasks.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Puts `task` at the back.
    pub(crate) fn push(&self, task: Arc<dyn QueuedTask>) {
        let mut tasks = self.lock();
        tasks.push_back(task);
        self.nonempty.store(true, Ordering::SeqCst);
    }

    /// Claims and runs one chunk of the front task; false if the queue was empty.
    pub(crate) fn run_one(&self) -> bool {
        let (task, index) = {
            let mut tasks = self.lock();
            let Some(task) = tasks.pop_front() else {
                return false;
            };
            let (index, more) = task.claim();
            if more {
                tasks.push_back(Arc::clone(&task));
            }
            self.nonempty.store(!tasks.is_empty(), Ordering::SeqCst);
            (task, index)
        };
        task.run(index, &self.chunks_run);
        true
    }

    /// Runs chunks until the queue is empty; then, with a `linger`, waits up to that long
    /// for more (a caller that steps again soon finds this thread awake) and goes on if
    /// some came. A caller that counted this thread among the lingering ones pushed its
    /// task before it looked, so the look after leaving the count sees it.
    pub(crate) fn drain(&self, linger: Option<Duration>) {
        loop {
            while self.run_one() {}
            let Some(linger) = linger else { return };
            self.lingering.fetch_add(1, Ordering::SeqCst);
            let until = Instant::now() + linger;
            while !self.nonempty.load(Ordering::Relaxed) && Instant::now() < until {
                thread::yield_now();
            }
            self.lingering.fetch_sub(1, Ordering::SeqCst);
            if !self.nonempty.load(Ordering::SeqCst) {
                return;
            }
        }
    }
}

/// A task as the queue sees it.
pub(crate) trait QueuedTask: Send + Sync {
    /// Claims the next chunk: its index, and whether unclaimed chunks remain.
    /// Only called under the queue lock, on a task with an unclaimed chunk.
    fn claim(&self) -> (usize, bool);
    /// Runs a claimed chunk and records its completion: first in `chunks_run`, then
    /// towards the task's, so a finished task's chunks are all counted.
    fn run(&self, index: usize, chunks_run: &AtomicU64);
}

pub(crate) struct Task<W> {
    pub(crate) work: W,
    /// Which chunks are still unclaimed.
    pub(crate) claims: Claims,
    /// Chunks not yet finished.
    pub(crate) remaining: AtomicUsize,
    /// The first chunk that panicked.
    pub(crate) panic: Mutex<Option<ChunkPanic>>,
    /// The thread blocked in `run_chunked`.
    pub(crate) waiter: Thread,
}

impl<W: Fn(usize) + Send + Sync> QueuedTask for Task<W> {
    fn claim(&self) -> (usize, bool) {
        self.claims.claim(rayon::current_thread_index())
    }

    fn run(&self, index: usize, chunks_run: &AtomicU64) {
        if let Err(payload) = panic::catch_unwind(AssertUnwindSafe(|| (self.work)(index))) {
            let message = panic_message(payload.as_ref());
            let mut first = self.panic.lock().unwrap_or_else(PoisonError::into_inner);
            if first.as_ref().is_none_or(|p| index < p.chunk) {
                *first = Some(ChunkPanic {
                    chunk: index,
                    message,
                });
            }
        }
        chunks_run.fetch_add(1, Ordering::Relaxed);
        if self.remaining.fetch_sub(1, Ordering::AcqRel) == 1 {
            self.waiter.unpark();
        }
    }
}

/// The unclaimed chunks of a task of several, as one block of consecutive chunks per pool
/// thread: a thread claims its own block's chunks first, front to back, and then takes from
/// the back of the block with the most left (as does a caller outside the pool that helps).
/// A batch's chunks are the same envs at every step, so each env is stepped by the same
/// thread step after step while the threads keep pace, and its state stays in that core's
/// cache instead of moving between cores. Only read and changed under the queue's lock,
/// except [`Claims::all_claimed`].
pub(crate) struct Claims {
    /// Per block, its unclaimed chunks `front..back`.
    blocks: Box<[(AtomicUsize, AtomicUsize)]>,
    unclaimed: AtomicUsize,
}

impl Claims {
    /// `n_chunks` chunks in `blocks` blocks (at least one).
    pub(crate) fn new(n_chunks: usize, blocks: usize) -> Self {
        let blocks = blocks.clamp(1, n_chunks.max(1));
        let edge = |b: usize| b * n_chunks / blocks;
        Claims {
            blocks: (0..blocks)
                .map(|b| (AtomicUsize::new(edge(b)), AtomicUsize::new(edge(b + 1))))
                .collect(),
            unclaimed: AtomicUsize::new(n_chunks),
        }
    }

    /// Claims a chunk for pool thread `home` (`None` for a thread outside the pool): the
    /// front of its own block, or else the back of the (first) fullest block, where that
    /// block's owner would come last. Returns its index, and whether unclaimed chunks
    /// remain. Only called under the queue lock, with a chunk unclaimed.
    fn claim(&self, home: Option<usize>) -> (usize, bool) {
        let left = |(front, back): &(AtomicUsize, AtomicUsize)| {
            back.load(Ordering::Relaxed) - front.load(Ordering::Relaxed)
        };
        let own = home
            .and_then(|h| self.blocks.get(h))
            .filter(|b| left(b) > 0);
        let index = match own {
            Some((front, _)) => front.fetch_add(1, Ordering::Relaxed),
            None => {
                let fullest = self.blocks.iter().min_by_key(|b| Reverse(left(b)));
                fullest.expect("a block").1.fetch_sub(1, Ordering::Relaxed) - 1
            }
        };
        let unclaimed = self.unclaimed.fetch_sub(1, Ordering::AcqRel) - 1;
        (index, unclaimed > 0)
    }

    /// Whether every chunk has been claimed.
    pub(crate) fn all_claimed(&self) -> bool {
        self.unclaimed.load(Ordering::Acquire) == 0
    }
}

/// A job of [`StepPool::spawn_fair`]: one chunk, run once.
pub(crate) struct OneOff<F> {
    pub(crate) job: Mutex<Option<F>>,
}

impl<F: FnOnce() + Send> QueuedTask for OneOff<F> {
    fn claim(&self) -> (usize, bool) {
        (0, false)
    }

    fn run(&self, _index: usize, _chunks_run: &AtomicU64) {
        let job = self
            .job
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take();
        if let Some(job) = job {
            // The panic hook has printed it; the job's captures tell its caller.
            let _ = panic::catch_unwind(AssertUnwindSafe(job));
        }
    }
}

/// The text of a panic's payload (what `panic!` was given), or a placeholder when it is
/// not a string.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(non-string panic payload)".to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A task whose chunks record `(name, index)` when they run.
    fn recording(
        name: &'static str,
        n_chunks: usize,
        log: &Arc<Mutex<Vec<(&'static str, usize)>>>,
    ) -> Arc<dyn QueuedTask> {
        let log = Arc::clone(log);
        Arc::new(Task {
            work: move |i| log.lock().unwrap().push((name, i)),
            claims: Claims::new(n_chunks, 1),
            remaining: AtomicUsize::new(n_chunks),
            panic: Mutex::new(None),
            waiter: thread::current(),
        })
    }

    /// Tasks take turns chunk by chunk: a one-chunk task queued behind a big one runs
    /// after one chunk of it, not after all of it, and so does each newcomer.
    #[test]
    fn tasks_take_turns_chunk_by_chunk() {
        let queue = FairQueue::default();
        let log = Arc::new(Mutex::new(Vec::new()));
        queue.push(recording("big", 5, &log));
        assert!(queue.run_one());
        queue.push(recording("small", 1, &log));
        queue.push(recording("pair", 2, &log));
        while queue.run_one() {}
        assert_eq!(
            *log.lock().unwrap(),
            // A thread outside the pool takes each task's chunks from the back.
            [
                ("big", 4),
                ("big", 3),
                ("small", 0),
                ("pair", 1),
                ("big", 2),
                ("pair", 0),
                ("big", 1),
                ("big", 0),
            ]
        );
        assert_eq!(queue.chunks_run.load(Ordering::Relaxed), 8);
    }

    /// Threads that keep pace each claim their own block, front to back, every time: the
    /// same chunks (the same envs) land on the same thread step after step.
    #[test]
    fn threads_that_keep_pace_claim_their_own_blocks() {
        for _step in 0..3 {
            let claims = Claims::new(8, 2);
            let mut got: [Vec<usize>; 2] = Default::default();
            for turn in 0..8 {
                let (index, more) = claims.claim(Some(turn % 2));
                got[turn % 2].push(index);
                assert_eq!(more, turn < 7);
            }
            assert_eq!(got, [vec![0, 1, 2, 3], vec![4, 5, 6, 7]]);
            assert!(claims.all_claimed());
        }
    }

    /// A thread whose block is done, or one outside the pool, takes from the back of the
    /// fullest block, where its owner would come last. Every chunk is claimed exactly
    /// once, whoever claims it.
    #[test]
    fn a_thread_done_with_its_block_takes_from_the_back_of_the_fullest() {
        // Blocks of 10 chunks over 3 threads: 0..3, 3..6, 6..10.
        let claims = Claims::new(10, 3);
        let mut order = Vec::new();
        for _ in 0..3 {
            order.push(claims.claim(Some(1)).0);
        }
        assert_eq!(order, [3, 4, 5]);
        assert_eq!(claims.claim(Some(1)).0, 9, "the back of 6..10, the fullest");
        assert_eq!(
            claims.claim(None).0,
            2,
            "the back of 0..3: as full as 6..9, first"
        );
        assert_eq!(claims.claim(Some(0)).0, 0);
        order.extend([9, 2, 0]);
        while !claims.all_claimed() {
            order.push(claims.claim(Some(7)).0); // an index with no block: it steals
        }
        order.sort_unstable();
        assert_eq!(order, (0..10).collect::<Vec<_>>());
        // More blocks than chunks: one block per chunk, none empty.
        let claims = Claims::new(2, 8);
        assert_eq!(claims.claim(Some(1)), (1, true));
        assert_eq!(claims.claim(Some(1)), (0, false));
    }

    /// The hand-over between a caller and a lingering drainer, as `StepPool::run_chunked`
    /// does it: the caller pushes its task, then starts a drainer only if none lingers. A
    /// drainer that a caller counted always takes the task, however close to the end of
    /// its wait the push came: no task is ever left in the queue with nobody to run it.
    /// The linger is short so that rounds land on every side of its end.
    #[test]
    fn a_task_pushed_while_a_drainer_lingers_is_never_left_behind() {
        let queue = Arc::new(FairQueue::default());
        let ran = Arc::new(AtomicUsize::new(0));
        let mut drainers = Vec::new();
        for round in 0..2000 {
            // 0–40 µs after the last task ran: before, around and after the drainer's end.
            let pause = Instant::now();
            while pause.elapsed() < Duration::from_micros(round as u64 % 41) {
                std::hint::spin_loop();
            }
            let counter = Arc::clone(&ran);
            queue.push(Arc::new(OneOff {
                job: Mutex::new(Some(move || {
                    counter.fetch_add(1, Ordering::SeqCst);
                })),
            }));
            if queue.lingering.load(Ordering::SeqCst) == 0 {
                let queue = Arc::clone(&queue);
                drainers.push(thread::spawn(move || {
                    queue.drain(Some(Duration::from_micros(20)))
                }));
            }
            // A hang guard only: a lost task never runs.
            let start = Instant::now();
            while ran.load(Ordering::SeqCst) != round + 1 {
                assert!(
                    start.elapsed() < Duration::from_secs(10),
                    "task {round} was left behind"
                );
                thread::yield_now();
            }
        }
        for drainer in drainers {
            drainer.join().unwrap();
        }
        assert_eq!(queue.lingering.load(Ordering::SeqCst), 0);
        assert!(!queue.nonempty.load(Ordering::SeqCst));
    }
}
