//! [`Activity`]: what one env or batch has done, counted by its step jobs on the pool and
//! read by the dashboard without the entry's lock. The step path only adds to atomics;
//! the one lock here is the dashboard's own reading window, which no step takes.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// What an env or batch is, fixed when it is created (the dashboard shows it without
/// taking the entry's lock).
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Facts {
    /// Envs held: 1 for a single env.
    pub(crate) n_envs: usize,
    pub(crate) action_dim: usize,
    pub(crate) observation_dim: usize,
    /// Seconds per step.
    pub(crate) dt: f64,
    pub(crate) max_steps: u32,
    /// The document's keyframes, and its sensors (name, type, floats).
    pub(crate) keyframes: Vec<String>,
    pub(crate) sensors: Vec<(String, &'static str, usize)>,
}

impl Facts {
    /// The facts of `n_envs` envs of `spec`.
    pub(crate) fn of(spec: &gymfleet_env::EnvSpec, n_envs: usize) -> Facts {
        Facts {
            n_envs,
            action_dim: spec.action_dim,
            observation_dim: spec.observation_dim,
            dt: spec.dt,
            max_steps: spec.max_steps,
            keyframes: spec.keyframes.clone(),
            sensors: spec.sensors.clone(),
        }
    }
}

/// Clears the finished flags (`was_done` of [`Activity::record_step`]) of envs `indices`
/// (empty or `None`: all) after they were reset or loaded.
pub(crate) fn clear_done(was_done: &mut [bool], indices: Option<&[u32]>) {
    match indices {
        Some(indices) if !indices.is_empty() => {
            for &i in indices {
                if let Some(done) = usize::try_from(i).ok().and_then(|i| was_done.get_mut(i)) {
                    *done = false;
                }
            }
        }
        _ => was_done.fill(false),
    }
}

/// An entry's counters, as read at one moment.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct ActivityCounts {
    /// Step calls (a batch step counts once).
    pub(crate) steps: u64,
    /// Env steps (a batch step of n envs counts n).
    pub(crate) env_steps: u64,
    /// Episodes that ended (terminated or truncated).
    pub(crate) episodes: u64,
    /// Time the step jobs took on the pool, in all, nanoseconds.
    pub(crate) busy_ns: u64,
}

/// Rates over the last window: see [`Activity::rates`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Rates {
    pub(crate) env_steps_per_s: f64,
    pub(crate) steps_per_s: f64,
    /// Mean time of a step call's pool job, seconds; `None` without step calls.
    pub(crate) mean_step_s: Option<f64>,
}

/// A reading of the counters on the server's clock, and the rates last measured.
type Window = (Option<(Duration, ActivityCounts)>, Option<Rates>);

/// What an env or batch has done: its [`Facts`], counters its step jobs add to (atomics,
/// never a lock on the step path), and the dashboard's last reading of them.
#[derive(Debug, Default)]
pub(crate) struct Activity {
    facts: Facts,
    steps: AtomicU64,
    env_steps: AtomicU64,
    episodes: AtomicU64,
    busy_ns: AtomicU64,
    /// Only [`Activity::rates`] (the dashboard) takes this lock.
    window: Mutex<Window>,
}

impl Activity {
    pub(crate) fn new(facts: Facts) -> Arc<Self> {
        Arc::new(Activity {
            facts,
            ..Activity::default()
        })
    }

    pub(crate) fn facts(&self) -> &Facts {
        &self.facts
    }

    /// Counts one step call that took `busy` on the pool, of envs whose flags are
    /// `terminated` and `truncated` (one each per env). With `autoreset`, every finished
    /// env ended an episode (it starts another); without, an env that stays finished
    /// while it keeps stepping ended one only when it first finished: `was_done` (one
    /// per env; the caller clears it on reset) remembers which were.
    pub(crate) fn record_step(
        &self,
        busy: Duration,
        terminated: &[bool],
        truncated: &[bool],
        autoreset: bool,
        was_done: &mut Vec<bool>,
    ) {
        self.record_envs_step(busy, None, terminated, truncated, autoreset, was_done);
    }

    /// [`Activity::record_step`] of a step of the envs `envs` (batch indices, one flag
    /// each; `None`: every env, in order).
    pub(crate) fn record_envs_step(
        &self,
        busy: Duration,
        envs: Option<&[u32]>,
        terminated: &[bool],
        truncated: &[bool],
        autoreset: bool,
        was_done: &mut Vec<bool>,
    ) {
        let needed = envs.map_or(terminated.len(), |e| {
            e.iter()
                .max()
                .map_or(0, |&m| m as usize + 1)
                .max(was_done.len())
        });
        was_done.resize(needed, false);
        let mut ended = 0u64;
        for (k, (t, u)) in terminated.iter().zip(truncated).enumerate() {
            let was = &mut was_done[envs.map_or(k, |e| e[k] as usize)];
            let done = *t || *u;
            if done && (autoreset || !*was) {
                ended += 1;
            }
            *was = done && !autoreset;
        }
        let n = u64::try_from(terminated.len()).unwrap_or(u64::MAX);
        let busy = u64::try_from(busy.as_nanos()).unwrap_or(u64::MAX);
        self.steps.fetch_add(1, Ordering::Relaxed);
        self.env_steps.fetch_add(n, Ordering::Relaxed);
        self.episodes.fetch_add(ended, Ordering::Relaxed);
        self.busy_ns.fetch_add(busy, Ordering::Relaxed);
    }

    /// The counters now.
    pub(crate) fn counts(&self) -> ActivityCounts {
        ActivityCounts {
            steps: self.steps.load(Ordering::Relaxed),
            env_steps: self.env_steps.load(Ordering::Relaxed),
            episodes: self.episodes.load(Ordering::Relaxed),
            busy_ns: self.busy_ns.load(Ordering::Relaxed),
        }
    }

    /// The rates between the last two readings at least `window` apart, `now` being the
    /// time on the server's clock: the first call only takes a reading (`None`), and a
    /// call less than `window` after the last reading returns the last rates.
    pub(crate) fn rates(&self, now: Duration, window: Duration) -> Option<Rates> {
        let counts = self.counts();
        let mut guard = self.window.lock().unwrap_or_else(PoisonError::into_inner);
        let (reading, last) = &mut *guard;
        match *reading {
            None => *reading = Some((now, counts)),
            Some((at, before)) => {
                let elapsed = now.saturating_sub(at);
                if elapsed >= window && !elapsed.is_zero() {
                    let secs = elapsed.as_secs_f64();
                    let steps = counts.steps.saturating_sub(before.steps);
                    let env_steps = counts.env_steps.saturating_sub(before.env_steps);
                    let busy = counts.busy_ns.saturating_sub(before.busy_ns);
                    *last = Some(Rates {
                        env_steps_per_s: env_steps as f64 / secs,
                        steps_per_s: steps as f64 / secs,
                        mean_step_s: (steps > 0).then(|| busy as f64 * 1e-9 / steps as f64),
                    });
                    *reading = Some((now, counts));
                }
            }
        }
        *last
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn episodes_end_once_without_autoreset_and_at_every_finish_with_it() {
        let activity = Activity::new(Facts::default());
        let mut was_done = Vec::new();
        let flags = |t: [bool; 2], u: [bool; 2]| (t, u);
        // Env 0 truncates and keeps stepping (still truncated), env 1 terminates once.
        for (t, u) in [
            flags([false, false], [false, false]),
            flags([false, true], [true, false]),
            flags([false, false], [true, false]),
            flags([false, false], [true, false]),
        ] {
            activity.record_step(2 * MS, &t, &u, false, &mut was_done);
        }
        let counts = activity.counts();
        assert_eq!((counts.steps, counts.env_steps, counts.episodes), (4, 8, 2));
        assert_eq!(counts.busy_ns, 8_000_000);
        // After a reset (the caller clears `was_done`) the next finish counts again.
        was_done.fill(false);
        activity.record_step(MS, &[false, false], &[true, false], false, &mut was_done);
        assert_eq!(activity.counts().episodes, 3);
        activity.record_step(MS, &[false, false], &[true, true], false, &mut was_done);
        assert_eq!(activity.counts().episodes, 4, "only env 1 newly finished");
        clear_done(&mut was_done, Some(&[0, 7]));
        assert_eq!(was_done, [false, true], "indices past the end are ignored");
        clear_done(&mut was_done, Some(&[]));
        assert_eq!(was_done, [false, false], "an empty list means every env");
        // With autoreset each finish is an episode of its own.
        let auto = Activity::new(Facts::default());
        let mut was_done = Vec::new();
        for _ in 0..3 {
            auto.record_step(MS, &[false], &[true], true, &mut was_done);
        }
        assert_eq!(auto.counts().episodes, 3);
    }

    #[test]
    fn rates_come_from_two_readings_a_window_apart() {
        let activity = Activity::new(Facts::default());
        let mut was_done = Vec::new();
        let second = Duration::from_secs(1);
        assert_eq!(activity.rates(Duration::ZERO, second), None);
        for _ in 0..10 {
            activity.record_step(4 * MS, &[false; 3], &[false; 3], true, &mut was_done);
        }
        // Too soon: no new reading yet.
        assert_eq!(activity.rates(500 * MS, second), None);
        let rates = activity.rates(2 * second, second).expect("a window passed");
        assert_eq!(rates.env_steps_per_s, 15.0);
        assert_eq!(rates.steps_per_s, 5.0);
        assert!((rates.mean_step_s.unwrap() - 0.004).abs() < 1e-12);
        // Nothing new: the rates fall to zero once another window passes.
        assert_eq!(activity.rates(2 * second + 10 * MS, second), Some(rates));
        let idle = activity.rates(3 * second, second).unwrap();
        assert_eq!((idle.env_steps_per_s, idle.mean_step_s), (0.0, None));
    }
}
