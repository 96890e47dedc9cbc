//! [`run_jobs_here`]: a thread that waits for its own pool jobs runs them itself.
//!
//! A caller that hands a job to a [`crate::StepPool`] and then blocks until it is done
//! (the Python package's calls to its embedded server, with no deadline) pays two thread
//! wake-ups for nothing: the pool thread's to start the job and its own to hear the
//! answer, each several microseconds on a VM. Inside [`run_jobs_here`], the jobs this
//! thread hands to a pool (`spawn`, `spawn_fair`) run at once on this thread instead. A
//! batch step of one chunk runs here too; one of several goes to the pool's threads as
//! before, and its last chunk wakes this thread directly. Such a caller steps again soon,
//! so the pool threads that helped it wait a little for its next step
//! ([`crate::HELPERS_LINGER`]) before they sleep, and that step wakes none. Nothing else
//! changes: results are the same bits, a job's panic is caught as on a pool thread, and a
//! pool thread never runs another caller's job this way.

use std::cell::Cell;

thread_local! {
    static RUNS_JOBS_HERE: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f` with the calling thread marked as one that runs the jobs it hands to any
/// [`crate::StepPool`] itself (see the module documentation); the mark is lifted when
/// `f` returns or unwinds. Meant for a thread that would otherwise block on the jobs'
/// answers, such as one in a `block_on` of a call to an in-process server; never for an
/// async runtime's worker threads, which must not run CPU work. Has no effect on a pool
/// thread.
pub fn run_jobs_here<R>(f: impl FnOnce() -> R) -> R {
    /// Puts the mark back as it was, however `f` ends.
    struct Restore(bool);
    impl Drop for Restore {
        fn drop(&mut self) {
            RUNS_JOBS_HERE.set(self.0);
        }
    }
    let _restore = Restore(RUNS_JOBS_HERE.replace(true));
    f()
}

/// Whether the calling thread is inside [`run_jobs_here`] and not a thread of a rayon
/// pool.
pub(crate) fn runs_jobs_here() -> bool {
    RUNS_JOBS_HERE.get() && rayon::current_thread_index().is_none()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::StepPool;
    use std::sync::{mpsc, Arc, Mutex};
    use std::thread::{self, ThreadId};

    /// The thread each chunk of a `n_chunks` task ran on.
    fn chunk_threads(pool: &StepPool, n_chunks: usize) -> Vec<ThreadId> {
        let ran = Arc::new(Mutex::new(vec![None; n_chunks]));
        let record = Arc::clone(&ran);
        pool.run_chunked(n_chunks, move |i| {
            record.lock().unwrap()[i] = Some(thread::current().id());
        })
        .unwrap();
        let ran = ran.lock().unwrap();
        ran.iter().map(|id| id.expect("every chunk ran")).collect()
    }

    #[test]
    fn jobs_run_on_the_marked_thread_and_a_panic_in_one_is_caught() {
        let pool = StepPool::new(2).unwrap();
        let here = thread::current().id();
        let (tx, rx) = mpsc::channel();
        run_jobs_here(|| {
            let fair = tx.clone();
            pool.spawn(move || tx.send(thread::current().id()).unwrap());
            pool.spawn_fair(move || fair.send(thread::current().id()).unwrap());
            pool.spawn(|| panic!("a job's bug"));
        });
        // Both ran before `spawn` returned, here.
        assert_eq!(rx.try_iter().collect::<Vec<_>>(), [here, here]);
        assert_eq!(pool.job_queue().started, 3);
        // Unmarked, a job goes to a pool thread again.
        let (tx, rx) = mpsc::channel();
        pool.spawn(move || tx.send(thread::current().id()).unwrap());
        assert_ne!(rx.recv().unwrap(), here);
    }

    #[test]
    fn a_marked_caller_runs_one_chunk_itself_and_leaves_several_to_the_pool() {
        let pool = StepPool::new(2).unwrap();
        let here = thread::current().id();
        run_jobs_here(|| {
            assert_eq!(chunk_threads(&pool, 1), [here]);
            let many = chunk_threads(&pool, 16);
            assert!(many.iter().all(|&id| id != here), "{many:?}");
        });
        // Unmarked, the caller helps with a task of several chunks as before: a pool
        // of one thread and a caller kept waiting in its first chunk until the other
        // has started share the chunks between them.
        let pool = StepPool::new(1).unwrap();
        let (started_tx, started_rx) = mpsc::channel::<()>();
        let started_rx = Mutex::new(started_rx);
        let started_tx = Mutex::new(started_tx);
        let ran = Arc::new(Mutex::new(Vec::new()));
        let record = Arc::clone(&ran);
        pool.run_chunked(2, move |i| {
            if i == 0 {
                started_rx.lock().unwrap().recv().unwrap();
            } else {
                started_tx.lock().unwrap().send(()).unwrap();
            }
            record.lock().unwrap().push(thread::current().id());
        })
        .unwrap();
        let ran = ran.lock().unwrap();
        assert_eq!(ran.len(), 2);
        assert!(ran.contains(&here), "{ran:?}");
    }

    #[test]
    fn the_mark_holds_inside_and_is_lifted_after_even_a_panic() {
        assert!(!runs_jobs_here());
        run_jobs_here(|| {
            assert!(runs_jobs_here());
            run_jobs_here(|| assert!(runs_jobs_here()));
            assert!(runs_jobs_here(), "a nested call keeps the outer mark");
        });
        assert!(!runs_jobs_here());
        let unwound = std::panic::catch_unwind(|| run_jobs_here(|| panic!("boom")));
        assert!(unwound.is_err());
        assert!(!runs_jobs_here());
    }
}
