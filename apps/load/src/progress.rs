//! [`Progress`]: the indicatif progress bar on stderr while a run measures, fed by a
//! shared counter of completed calls. Hidden with `--quiet` or when stderr is not a
//! terminal, so piped output and tests see nothing.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

use crate::meter::Schedule;

/// How often the bar is redrawn.
const TICK: Duration = Duration::from_millis(200);

/// A progress bar and the thread that updates it.
#[derive(Debug)]
pub(crate) struct Progress {
    bar: ProgressBar,
    calls: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
    ticker: Option<JoinHandle<()>>,
}

impl Progress {
    /// A spinner saying `setup` (e.g. "creating envs"), or nothing when `quiet` or
    /// stderr is not a terminal.
    pub(crate) fn new(quiet: bool, setup: String) -> Self {
        let bar = if quiet || !std::io::stderr().is_terminal() {
            ProgressBar::hidden()
        } else {
            let bar = ProgressBar::new_spinner();
            bar.set_message(setup);
            bar.enable_steady_tick(Duration::from_millis(100));
            bar
        };
        Progress {
            bar,
            calls: Arc::new(AtomicU64::new(0)),
            stop: Arc::new(AtomicBool::new(false)),
            ticker: None,
        }
    }

    /// The counter that clients add their completed calls to.
    pub(crate) fn counter(&self) -> Arc<AtomicU64> {
        Arc::clone(&self.calls)
    }

    /// Turns the spinner into a bar for a run that started at `start`: by calls for
    /// `--steps` runs, by time for timed ones, with the current env-steps/s.
    pub(crate) fn begin(
        &mut self,
        label: &str,
        schedule: &Schedule,
        start: Instant,
        clients: u64,
        n_envs: u64,
    ) {
        if self.bar.is_hidden() {
            return;
        }
        self.bar.disable_steady_tick();
        let (length, by_time) = match (schedule.total_calls(), schedule.deadline()) {
            (Some(calls), _) => (calls * clients, false),
            (None, Some(deadline)) => (
                deadline.saturating_duration_since(start).as_millis() as u64,
                true,
            ),
            (None, None) => (0, false),
        };
        self.bar.set_length(length);
        self.bar.set_position(0);
        let template = if by_time {
            "{prefix} [{bar:30}] {msg}"
        } else {
            "{prefix} [{bar:30}] {pos}/{len} calls {msg}"
        };
        if let Ok(style) = ProgressStyle::with_template(template) {
            self.bar.set_style(style.progress_chars("=> "));
        }
        self.bar.set_prefix(label.to_string());
        let (bar, calls, stop) = (self.bar.clone(), self.counter(), Arc::clone(&self.stop));
        self.ticker = Some(std::thread::spawn(move || {
            let (mut last_calls, mut last_time) = (0, Instant::now());
            while !stop.load(Ordering::Relaxed) {
                std::thread::sleep(TICK);
                let now = Instant::now();
                let done = calls.load(Ordering::Relaxed);
                let rate = (done - last_calls) as f64 * n_envs as f64
                    / (now - last_time).as_secs_f64().max(1e-9);
                (last_calls, last_time) = (done, now);
                if by_time {
                    let elapsed = ((now - start).as_millis() as u64).min(length);
                    bar.set_position(elapsed);
                    bar.set_message(format!(
                        "{:.1}/{:.1} s · {rate:.0} env-steps/s",
                        elapsed as f64 / 1e3,
                        length as f64 / 1e3
                    ));
                } else {
                    bar.set_message(format!("{rate:.0} env-steps/s"));
                    bar.set_position(done.min(length));
                }
            }
        }));
    }

    /// Stops updating and clears the bar.
    pub(crate) fn finish(mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(ticker) = self.ticker.take() {
            let _ = ticker.join();
        }
        self.bar.finish_and_clear();
    }
}
