//! [`Meter`]: one client's clock and tally. It decides whether the client starts
//! another call (by count or deadline), sorts each completed call into warmup or
//! measurement, and records measured calls: count, env-steps, latency (hdrhistogram, µs),
//! errors and terminations. Shared by the remote and in-process runners.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use hdrhistogram::Histogram;

use crate::config::{LoadConfig, StopRule, Warmup};

/// A client gives up after this many errors in a row.
pub const MAX_CONSECUTIVE_ERRORS: u32 = 10;

/// Highest latency the histograms hold exactly; longer calls saturate: 10 minutes, in µs.
const MAX_LATENCY_US: u64 = 600_000_000;

/// When every client's measurement starts and stops.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Schedule {
    /// Calls per client before measuring.
    warmup_calls: u64,
    /// Measured calls per client, for `--steps` runs.
    measured_calls: Option<u64>,
    /// Calls completing before this are warmup (timed runs).
    measure_from: Instant,
    /// No call starts after this, and calls completing after it are not counted.
    deadline: Option<Instant>,
}

impl Schedule {
    /// The schedule of a run whose clients all start at `start`.
    pub(crate) fn new(config: &LoadConfig, start: Instant) -> Self {
        let (warmup_calls, warmup_time) = match config.warmup {
            Warmup::Steps(n) => (n, Duration::ZERO),
            Warmup::Seconds(s) => (0, Duration::from_secs_f64(s)),
        };
        let measure_from = start + warmup_time;
        let (measured_calls, deadline) = match config.stop {
            StopRule::Steps(n) => (Some(n), None),
            StopRule::Seconds(s) => (None, Some(measure_from + Duration::from_secs_f64(s))),
        };
        Schedule {
            warmup_calls,
            measured_calls,
            measure_from,
            deadline,
        }
    }

    /// Calls per client in a `--steps` run, warmup included.
    pub(crate) fn total_calls(&self) -> Option<u64> {
        self.measured_calls.map(|n| n + self.warmup_calls)
    }

    /// When measuring stops, in a timed run.
    pub(crate) fn deadline(&self) -> Option<Instant> {
        self.deadline
    }
}

/// The tally of one client.
#[derive(Debug, Clone)]
pub(crate) struct Tally {
    /// Latency of measured successful calls, µs.
    pub(crate) latency: Histogram<u64>,
    /// Measured successful calls.
    pub(crate) calls: u64,
    /// Env-steps of measured successful calls.
    pub(crate) env_steps: u64,
    /// Failed calls (measured or not).
    pub(crate) errors: u64,
    /// The first error's message.
    pub(crate) first_error: Option<String>,
    /// Envs reported `terminated` in measured calls.
    pub(crate) terminations: u64,
    /// When this client's measurement started (its first measured call's start, or the
    /// end of its warmup).
    pub(crate) measure_start: Option<Instant>,
    /// When its last measured call completed.
    pub(crate) measure_end: Option<Instant>,
}

impl Tally {
    pub(crate) fn new() -> Self {
        Tally {
            latency: Histogram::new_with_bounds(1, MAX_LATENCY_US, 3)
                .expect("valid histogram bounds"),
            calls: 0,
            env_steps: 0,
            errors: 0,
            first_error: None,
            terminations: 0,
            measure_start: None,
            measure_end: None,
        }
    }

    pub(crate) fn note_error(&mut self, message: String) {
        self.errors += 1;
        if self.first_error.is_none() {
            self.first_error = Some(message);
        }
    }
}

/// One client's clock and tally.
#[derive(Debug)]
pub(crate) struct Meter {
    schedule: Schedule,
    issued: u64,
    completed: u64,
    consecutive_errors: u32,
    progress: Arc<AtomicU64>,
    pub(crate) tally: Tally,
}

impl Meter {
    /// A meter following `schedule`, adding each completed call to `progress`.
    pub(crate) fn new(schedule: Schedule, progress: Arc<AtomicU64>) -> Self {
        Meter {
            schedule,
            issued: 0,
            completed: 0,
            consecutive_errors: 0,
            progress,
            tally: Tally::new(),
        }
    }

    /// The index of the next call to start, or `None` when the client is done: its
    /// calls are all issued, the deadline has passed, or it has failed too often.
    pub(crate) fn next_call(&mut self) -> Option<u64> {
        if self.consecutive_errors >= MAX_CONSECUTIVE_ERRORS {
            return None;
        }
        if let Some(total) = self.schedule.total_calls() {
            if self.issued >= total {
                return None;
            }
        }
        if let Some(deadline) = self.schedule.deadline {
            if Instant::now() >= deadline {
                return None;
            }
        }
        self.issued += 1;
        Some(self.issued - 1)
    }

    /// Whether the call completing now is measured (and the tally's window updated).
    fn measured(&mut self, started: Instant, finished: Instant) -> bool {
        let index = self.completed;
        self.completed += 1;
        self.progress.fetch_add(1, Ordering::Relaxed);
        if index < self.schedule.warmup_calls || finished < self.schedule.measure_from {
            return false;
        }
        if self.schedule.deadline.is_some_and(|d| finished > d) {
            return false;
        }
        let start = match self.schedule.measured_calls {
            // A --steps run measures from its first measured call.
            Some(_) => started,
            None => self.schedule.measure_from,
        };
        self.tally.measure_start.get_or_insert(start);
        self.tally.measure_end = Some(finished);
        true
    }

    /// Records a successful call that started at `started`, stepped `env_steps`
    /// env-steps and reported `terminations` terminated envs.
    pub(crate) fn success(&mut self, started: Instant, env_steps: u64, terminations: u64) {
        let finished = Instant::now();
        self.consecutive_errors = 0;
        if self.measured(started, finished) {
            let us = (finished - started).as_micros().max(1);
            self.tally
                .latency
                .saturating_record(u64::try_from(us).unwrap_or(u64::MAX));
            self.tally.calls += 1;
            self.tally.env_steps += env_steps;
            self.tally.terminations += terminations;
        }
    }

    /// Records an error outside a timed call (a reset, reopening a stream): it counts
    /// towards the errors and the give-up limit, not towards the calls.
    pub(crate) fn side_error(&mut self, message: String) {
        self.consecutive_errors += 1;
        self.tally.note_error(message);
    }

    /// Records a failed call.
    pub(crate) fn failure(&mut self, message: String) {
        self.completed += 1;
        self.progress.fetch_add(1, Ordering::Relaxed);
        self.consecutive_errors += 1;
        self.tally.note_error(message);
    }
}
