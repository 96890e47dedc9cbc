//! [`Clock`]: the time the idle sweeper measures idleness with. The system's monotonic
//! clock in production; a clock a test moves by hand, so that reclaiming can be tested
//! without waiting for real time to pass. The idle sweeper also sweeps whenever a manual
//! clock moves, and [`Clock::swept`] waits for that sweep: a test neither sleeps nor polls.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::sync::watch;

/// A monotonic clock: the time elapsed since it was made.
#[derive(Debug, Clone)]
pub struct Clock(Source);

#[derive(Debug, Clone)]
enum Source {
    System(Instant),
    Manual(Arc<Manual>),
}

/// A manual clock's time, and how far the sweeper has caught up with its moves.
#[derive(Debug)]
struct Manual {
    nanos: AtomicU64,
    /// How many times the clock has moved ([`Clock::advance`]).
    moves: watch::Sender<u64>,
    /// The last move a sweep has started after and finished.
    swept: watch::Sender<u64>,
}

impl Clock {
    /// The system's monotonic clock, from now.
    pub fn system() -> Clock {
        Clock(Source::System(Instant::now()))
    }

    /// A clock that stands still until [`Clock::advance`] moves it (clones share it).
    pub fn manual() -> Clock {
        Clock(Source::Manual(Arc::new(Manual {
            nanos: AtomicU64::new(0),
            moves: watch::Sender::new(0),
            swept: watch::Sender::new(0),
        })))
    }

    /// Moves a manual clock forward by `by` (0 too counts as a move: the sweeper looks
    /// again); a system clock ignores it.
    pub fn advance(&self, by: Duration) {
        if let Source::Manual(m) = &self.0 {
            let by = u64::try_from(by.as_nanos()).unwrap_or(u64::MAX);
            m.nanos.fetch_add(by, Ordering::SeqCst);
            m.moves.send_modify(|n| *n += 1);
        }
    }

    /// Waits until the idle sweeper has swept at the manual clock's present time (after
    /// its last [`Clock::advance`]); returns at once on a system clock. Only for a server
    /// that sweeps (an idle TTL): without a sweeper it waits for ever.
    pub async fn swept(&self) {
        if let Source::Manual(m) = &self.0 {
            let now = *m.moves.borrow();
            let mut swept = m.swept.subscribe();
            // The sender lives in `m`, which this clock holds: the wait cannot fail.
            let _ = swept.wait_for(|&done| done >= now).await;
        }
    }

    /// For the sweeper: a receiver that changes whenever a manual clock moves; `None` for
    /// the system clock.
    pub(crate) fn moves(&self) -> Option<watch::Receiver<u64>> {
        match &self.0 {
            Source::System(_) => None,
            Source::Manual(m) => Some(m.moves.subscribe()),
        }
    }

    /// For the sweeper: runs one sweep, then records that the clock's moves up to the one
    /// before it have been swept.
    pub(crate) fn sweep(&self, sweep: impl FnOnce()) {
        match &self.0 {
            Source::System(_) => sweep(),
            Source::Manual(m) => {
                let now = *m.moves.borrow();
                sweep();
                m.swept.send_modify(|done| *done = (*done).max(now));
            }
        }
    }

    /// The time elapsed since the clock was made (or advanced by hand).
    pub fn elapsed(&self) -> Duration {
        match &self.0 {
            Source::System(start) => start.elapsed(),
            Source::Manual(m) => Duration::from_nanos(m.nanos.load(Ordering::SeqCst)),
        }
    }
}

impl Default for Clock {
    fn default() -> Self {
        Clock::system()
    }
}

impl PartialEq for Clock {
    /// Clocks are equal when they are the same clock (a manual one and its clones).
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (Source::System(a), Source::System(b)) => a == b,
            (Source::Manual(a), Source::Manual(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_manual_clock_moves_only_by_hand_and_its_clones_share_it() {
        let clock = Clock::manual();
        let shared = clock.clone();
        assert_eq!(clock.elapsed(), Duration::ZERO);
        clock.advance(Duration::from_millis(1500));
        assert_eq!(shared.elapsed(), Duration::from_millis(1500));
        assert_eq!(clock, shared);
        assert_ne!(clock, Clock::manual());
    }

    #[test]
    fn swept_waits_for_a_sweep_after_the_last_move() {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_time()
            .build()
            .unwrap();
        // Whether `swept` is ready now (a zero timeout polls it once first).
        let ready = |clock: &Clock| {
            runtime.block_on(async {
                tokio::time::timeout(Duration::ZERO, clock.swept())
                    .await
                    .is_ok()
            })
        };
        let clock = Clock::manual();
        assert!(ready(&clock), "nothing moved yet: nothing to wait for");
        clock.advance(Duration::from_secs(1));
        assert!(!ready(&clock), "no sweep since the move");
        let mut swept = false;
        clock.sweep(|| swept = true);
        assert!(swept);
        assert!(ready(&clock), "the sweep after the move is seen");
        clock.advance(Duration::ZERO);
        assert!(!ready(&clock), "a move of 0 asks for another sweep");
        assert!(ready(&Clock::system()), "a system clock never waits");
    }
}
