//! [`Dashboard`]: what the dashboard's handlers share: the simulation whose registries
//! they read, the token table and sessions, the server's clock, and the pool's rate
//! window.

use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use gymfleet_batch::JobQueueStats;

use super::session::Sessions;
use crate::clock::Clock;
use crate::config::ServerConfig;
use crate::simulation::Simulation;
use crate::tenant::TokenTable;

/// Rates are measured over windows at least this long (on the server's clock).
pub(super) const RATE_WINDOW: Duration = Duration::from_secs(1);
/// Most envs, and most batches, one overview lists (it says how many there are).
pub(super) const MAX_LISTED: usize = 200;

/// The pool's job counters at the last reading, and the rates measured then.
type PoolWindow = (Option<(Duration, JobQueueStats)>, Option<PoolRates>);

/// The pool over the last window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct PoolRates {
    pub(super) jobs_per_s: f64,
    /// Mean wait for a thread of the jobs started in the window; `None` if none started.
    pub(super) mean_wait_s: Option<f64>,
}

/// What the handlers share.
pub(super) struct Dashboard {
    pub(super) sim: Arc<Simulation>,
    /// `None`: auth is off.
    pub(super) tokens: Option<Arc<TokenTable>>,
    pub(super) sessions: Sessions,
    pub(super) clock: Clock,
    pool_window: Mutex<PoolWindow>,
}

impl Dashboard {
    pub(super) fn new(sim: Arc<Simulation>, config: &ServerConfig) -> Self {
        Dashboard {
            sim,
            tokens: config.auth_tokens.clone(),
            sessions: Sessions::new(config.clock.clone()),
            clock: config.clock.clone(),
            pool_window: Mutex::new((None, None)),
        }
    }

    /// The pool's rates between the last two readings a window apart (as
    /// `Activity::rates` measures an env's): the first call only takes a reading.
    pub(super) fn pool_rates(&self, stats: JobQueueStats) -> Option<PoolRates> {
        let now = self.clock.elapsed();
        let mut guard = self
            .pool_window
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let (reading, last) = &mut *guard;
        match *reading {
            None => *reading = Some((now, stats)),
            Some((at, before)) => {
                let elapsed = now.saturating_sub(at);
                if elapsed >= RATE_WINDOW && !elapsed.is_zero() {
                    let jobs = stats.started.saturating_sub(before.started);
                    let waited = stats.waited_ns.saturating_sub(before.waited_ns);
                    *last = Some(PoolRates {
                        jobs_per_s: jobs as f64 / elapsed.as_secs_f64(),
                        mean_wait_s: (jobs > 0).then(|| waited as f64 * 1e-9 / jobs as f64),
                    });
                    *reading = Some((now, stats));
                }
            }
        }
        *last
    }
}
