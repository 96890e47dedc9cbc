//! gymfleet-load: the load-test client of gymfleet. This crate owns the load workload
//! and its measurement: the command line ([`Cli`] → [`LoadConfig`]), the deterministic
//! actions ([`ActionPlan`]), the runners — remote, through `gymfleet-client` with unary
//! `StepBatch`, pipelined `StreamBatch` or single-env `Step` calls from many concurrent
//! clients spread over one or several servers; and in process, on a local
//! `gymfleet-batch` `StepPool` — and the report ([`Report`]: env-steps/s, calls/s, per-call
//! latency percentiles from hdrhistogram, errors; a table and JSON).
//!
//! With the default `embedded` feature it also links `gymfleet-server`,
//! `gymfleet-batch` and `gymfleet-env`: with no `--server` it starts a server in process
//! on `127.0.0.1:0` ([`EmbeddedServer`]), and `--in-process` / `--compare` step the
//! batch directly, so the server's overhead is one command. Built without it
//! (`--no-default-features`) it is a pure network client of `gymfleet-client` that
//! needs `--server`, and links no physics. Simulation itself is left to the server.
//!
//! ```no_run
//! use clap::Parser;
//! use gymfleet_load::{render_table, run, Cli};
//!
//! let config = Cli::parse_from(["gymfleet-load", "--model", "arm2", "--steps", "100"])
//!     .resolve()
//!     .expect("valid flags");
//! let report = run(&config).expect("run");
//! print!("{}", render_table(&report));
//! ```
//!
//! # Modes and report
//!
//! The same workload runs remote (unary or streamed, against `--server`s or an embedded
//! server) or `--in-process` through `gymfleet-batch`; `--compare [--rounds K]` runs both,
//! K times alternated, for the remote / in-process ratio, and `--replay FILE` then records
//! one env of the model with the run's actions (`Replay`) and writes an HTML replay. The
//! report has latency histograms (hdrhistogram), a results table and `--json FILE`. Each
//! run's CPU time against its wall time (`cpu.rs`, from `/proc/self/stat`) is in the
//! report, with a warning when a run that simulates in this process was starved, and local
//! runs print the reference for their workload from `reference.json` (`reference.rs`,
//! compiled in).

mod actions;
mod cli;
mod config;
mod cpu;
#[cfg(feature = "embedded")]
mod embedded;
mod error;
#[cfg(feature = "embedded")]
mod in_process;
mod meter;
mod model;
mod progress;
mod reference;
mod remote;
mod report;
mod rss;

use reference::Place::{self, Embedded, InProcess};

pub use actions::{ActionKind, ActionPlan};
pub use cli::{Cli, DEFAULT_DURATION_SECS, DEFAULT_N_ENVS, DEFAULT_WARMUP_SECS, MAX_ROUNDS};
pub use config::{
    threads_or_cores, Api, LoadConfig, Mode, StopRule, Target, TaskFile, UnitsArg, Warmup,
};
pub use cpu::Usage;
#[cfg(feature = "embedded")]
pub use embedded::EmbeddedServer;
pub use error::{LoadError, Result};
pub use meter::MAX_CONSECUTIVE_ERRORS;
pub use model::{
    Model, ARM2, ARM6, BUILTINS, CHAIN20, DEFAULT_TORQUE_AMPLITUDE, FOURBAR, PENDULUM,
};
pub use report::{render_table, to_json, Latency, Report, RunResult};
pub use rss::Memory;

/// Runs `config` to the end and returns its report; writes the JSON file if
/// `config.json` is set. Builds its own tokio runtime, so call it from outside one.
pub fn run(config: &LoadConfig) -> Result<Report> {
    let memory_baseline = config.report_rss.then(Memory::current).flatten();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| LoadError::setup("tokio runtime", e))?;
    let mut runs = Vec::new();
    let mut ratio = None;
    let mut round_ratios = Vec::new();
    match &config.target {
        Target::Remote { servers } => {
            runs.push(timed(config, None, || {
                runtime.block_on(remote::run(config, servers, "server"))
            })?);
        }
        Target::Embedded { threads } => {
            runs.push(timed(config, Some((Embedded, *threads)), || {
                runtime.block_on(run_embedded(config, *threads))
            })?)
        }
        Target::InProcess { threads } => {
            runs.push(timed(config, Some((InProcess, *threads)), || {
                run_in_process(config, *threads)
            })?)
        }
        Target::Compare {
            threads,
            servers,
            rounds,
        } => {
            let run_remote = || {
                if servers.is_empty() {
                    timed(config, Some((Embedded, *threads)), || {
                        runtime.block_on(run_embedded(config, *threads))
                    })
                } else {
                    timed(config, None, || {
                        runtime.block_on(remote::run(config, servers, "server"))
                    })
                }
            };
            let run_in_process = |config, threads: usize| {
                timed(config, Some((InProcess, threads)), || {
                    run_in_process(config, threads)
                })
            };
            for round in 1..=*rounds {
                // Odd rounds in process first, even rounds remote first.
                let (mut local, mut remote) = if round % 2 == 1 {
                    let local = run_in_process(config, *threads)?;
                    (local, run_remote()?)
                } else {
                    let remote = run_remote()?;
                    (run_in_process(config, *threads)?, remote)
                };
                if local.env_steps_per_s > 0.0 {
                    round_ratios.push(remote.env_steps_per_s / local.env_steps_per_s);
                }
                if *rounds > 1 {
                    local.label = format!("{} #{round}", local.label);
                    remote.label = format!("{} #{round}", remote.label);
                }
                runs.push(local);
                runs.push(remote);
            }
            ratio = median(&round_ratios);
        }
    }
    let report = Report {
        config: config.clone(),
        summary: config.summary(),
        runs,
        ratio_remote_to_in_process: ratio,
        round_ratios,
        memory_baseline,
        memory_end: config.report_rss.then(Memory::current).flatten(),
    };
    if let Some(path) = &config.json {
        std::fs::write(path, to_json(&report) + "\n").map_err(|e| LoadError::Output {
            path: path.clone(),
            reason: e.to_string(),
        })?;
    }
    Ok(report)
}

/// `run`'s result with the CPU time this process got during it and its wall time, and the
/// reference for its workload; `local`: where in this process it simulates, on how many
/// threads (`None`: on a server).
fn timed(
    config: &LoadConfig,
    local: Option<(Place, usize)>,
    run: impl FnOnce() -> Result<RunResult>,
) -> Result<RunResult> {
    let (result, usage) = cpu::measure(run);
    // Envs stepped at once: a batch's (every client's), or one per client.
    let envs = match config.api {
        config::Api::Batch => Some(config.n_envs * config.clients),
        config::Api::Env => Some(config.clients),
        config::Api::Observe | config::Api::Ping => None,
    };
    let threads = local.map(|(_, threads)| threads);
    result.map(|mut r| {
        r.usage = usage;
        r.reference = local.map(|(place, threads)| {
            reference::lookup(config, place, config::threads_or_cores(threads))
        });
        r.local_parallel = threads
            .zip(envs)
            .map(|(t, envs)| config::threads_or_cores(t).min(envs));
        r
    })
}

/// The median of `values` (the mean of the middle two for an even count); `None` if empty.
fn median(values: &[f64]) -> Option<f64> {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(sorted[n / 2]),
        _ => Some((sorted[n / 2 - 1] + sorted[n / 2]) / 2.0),
    }
}

#[cfg(feature = "embedded")]
async fn run_embedded(config: &LoadConfig, threads: usize) -> Result<RunResult> {
    let server = EmbeddedServer::start(threads).await?;
    let result = remote::run(config, &[server.addr()], "embedded server").await;
    let stopped = server.stop().await;
    let result = result?;
    stopped?;
    Ok(result)
}

#[cfg(not(feature = "embedded"))]
async fn run_embedded(_config: &LoadConfig, _threads: usize) -> Result<RunResult> {
    Err(LoadError::NotEmbedded {
        what: "running without --server (an embedded server)",
    })
}

#[cfg(feature = "embedded")]
fn run_in_process(config: &LoadConfig, threads: usize) -> Result<RunResult> {
    in_process::run(config, threads)
}

#[cfg(not(feature = "embedded"))]
fn run_in_process(_config: &LoadConfig, _threads: usize) -> Result<RunResult> {
    Err(LoadError::NotEmbedded {
        what: "--in-process",
    })
}
