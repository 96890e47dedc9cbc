//! The command line: [`Cli`] (clap derive; every flag also reads a `GYMFLEET_*`
//! variable) and its validation into a [`LoadConfig`], with one clear message per bad
//! combination.

use std::path::PathBuf;

use clap::Parser;

use crate::actions::ActionKind;
use crate::config::{
    threads_or_cores, Api, LoadConfig, Mode, StopRule, Target, TaskFile, UnitsArg, Warmup,
};
use crate::error::{LoadError, Result};
use crate::model::Model;

/// Seconds measured when neither `--duration` nor `--steps` is given.
pub const DEFAULT_DURATION_SECS: f64 = 10.0;
/// Seconds of warmup before a timed run, unless `--warmup` says otherwise.
pub const DEFAULT_WARMUP_SECS: f64 = 1.0;
/// Envs per batch with `--api batch`, unless `--n-envs` says otherwise.
pub const DEFAULT_N_ENVS: usize = 256;
/// The most `--compare` rounds one run takes (each builds its envs twice).
pub const MAX_ROUNDS: u32 = 100;

/// gymfleet-load: drives gymfleet batches or single envs and reports throughput and
/// per-call latency.
///
/// With no --server it starts an embedded server on 127.0.0.1:0 (built with the default
/// `embedded` feature; without it, the tool is a pure network client and needs
/// --server). --in-process steps the same workload on a local StepPool with no network,
/// and --compare runs both and prints the ratio.
#[derive(Debug, Clone, Parser)]
#[command(name = "gymfleet-load", version, about, allow_negative_numbers = true)]
pub struct Cli {
    /// Server address (host:port or unix:/path); repeat or comma-separate for several, over which
    /// the clients are spread round-robin. None: an embedded server.
    #[arg(
        long = "server",
        value_name = "ADDR",
        env = "GYMFLEET_SERVER",
        value_delimiter = ','
    )]
    pub servers: Vec<String>,
    /// How to reach --server servers that require a token or TLS.
    #[command(flatten)]
    pub connect: gymfleet_client::ConnectArgs,
    /// pendulum, arm2, arm6, chain20, fourbar (the files of models/), or the path of an assembly
    /// document (JSON, MJCF or URDF).
    #[arg(long, env = "GYMFLEET_MODEL", default_value = "arm2")]
    pub model: String,
    /// Observed instances (repeat or comma-separate); default: the model's tip, or a
    /// file's last instance.
    #[arg(
        long = "end-effector",
        value_name = "ID",
        env = "GYMFLEET_END_EFFECTOR",
        value_delimiter = ','
    )]
    pub end_effectors: Vec<String>,
    /// Envs per batch [default: 256; 1 with the single-env APIs: env, observe, ping].
    #[arg(long, value_name = "N", env = "GYMFLEET_N_ENVS")]
    pub n_envs: Option<usize>,
    /// Concurrent clients, each with its own connection and batch (or env).
    #[arg(long, value_name = "C", env = "GYMFLEET_CLIENTS", default_value_t = 1)]
    pub clients: usize,
    /// Seconds to measure, after the warmup [default: 10].
    #[arg(long, value_name = "SECS", env = "GYMFLEET_DURATION")]
    pub duration: Option<f64>,
    /// Measured calls per client, after the warmup (instead of --duration).
    #[arg(long, value_name = "N", env = "GYMFLEET_STEPS")]
    pub steps: Option<u64>,
    /// Seconds left out of the figures at the start of a timed run [default: 1].
    #[arg(long, value_name = "SECS", env = "GYMFLEET_WARMUP")]
    pub warmup: Option<f64>,
    /// Calls per client left out of the figures at the start of a --steps run [default: 0].
    #[arg(long, value_name = "N", env = "GYMFLEET_WARMUP_STEPS")]
    pub warmup_steps: Option<u64>,
    /// unary: one StepBatch call at a time; stream: StreamBatch with --window in flight.
    #[arg(long, value_enum, env = "GYMFLEET_MODE", default_value_t = Mode::Unary)]
    pub mode: Mode,
    /// Steps in flight per stream with --mode stream.
    #[arg(long, value_name = "W", env = "GYMFLEET_WINDOW", default_value_t = gymfleet_client::DEFAULT_STREAM_WINDOW)]
    pub window: usize,
    /// batch: CreateBatch/StepBatch; env: single-env Step round trips; observe: single-env
    /// Observe (the pool hand-off without physics); ping: GetServerInfo (the transport alone).
    #[arg(long, value_enum, env = "GYMFLEET_API", default_value_t = Api::Batch)]
    pub api: Api,
    /// How action values are read.
    #[arg(long, value_enum, env = "GYMFLEET_ACTION_TYPE", default_value_t = ActionKind::Torque)]
    pub action_type: ActionKind,
    /// Action amplitude: N·m for torque [default: each DOF's own action bound, which the
    /// server derives from the model], deg for position [30], deg/s for velocity [45].
    #[arg(long, value_name = "A", env = "GYMFLEET_AMPLITUDE")]
    pub amplitude: Option<f32>,
    /// Integration substeps per step [default: the server's, 5].
    #[arg(long, value_name = "N", env = "GYMFLEET_SUBSTEPS")]
    pub substeps: Option<u32>,
    /// Seconds per step [default: the server's, 1/240].
    #[arg(long, value_name = "SECS", env = "GYMFLEET_DT")]
    pub dt: Option<f64>,
    /// Episode length in steps [default: the server's, 1000].
    #[arg(long, value_name = "N", env = "GYMFLEET_MAX_STEPS")]
    pub max_steps: Option<u32>,
    /// Seed of the envs and of the actions.
    #[arg(long, env = "GYMFLEET_SEED", default_value_t = 0)]
    pub seed: u64,
    /// A terms task's JSON file (docs/tasks.md: "Terms tasks"), the reward of every env: its terms
    /// are computed in each step, so the run measures them too. Remote: sent as the
    /// request's task; --in-process: parsed here.
    #[arg(long, value_name = "FILE", env = "GYMFLEET_TASK")]
    pub task: Option<PathBuf>,
    /// Units of observations and of the task's values, ranges and noise (actions keep
    /// theirs).
    #[arg(long, value_enum, env = "GYMFLEET_UNITS", default_value_t = UnitsArg::Document)]
    pub units: UnitsArg,
    /// Step-pool threads of the embedded server, --in-process and --compare; 0 = one
    /// per core. A remote server has its own.
    #[arg(long, value_name = "N", env = "GYMFLEET_THREADS")]
    pub threads: Option<usize>,
    /// Step gymfleet-batch directly on a local StepPool: no server, no network.
    #[arg(long, env = "GYMFLEET_IN_PROCESS")]
    pub in_process: bool,
    /// Run in process, then remote, and report the throughput ratio remote / in-process.
    #[arg(long, env = "GYMFLEET_COMPARE")]
    pub compare: bool,
    /// With --compare: run the two this many times, alternating which goes first, and
    /// report each round's ratio and their median [default: 1].
    #[arg(long, value_name = "K", env = "GYMFLEET_ROUNDS")]
    pub rounds: Option<u32>,
    /// Write the configuration and figures as JSON to this file.
    #[arg(long, value_name = "FILE", env = "GYMFLEET_JSON")]
    pub json: Option<PathBuf>,
    /// After the run, record one env of the model on the (first) server for
    /// `--replay-steps` steps of the run's actions and write an HTML replay to FILE.
    #[arg(long, value_name = "FILE", env = "GYMFLEET_REPLAY")]
    pub replay: Option<PathBuf>,
    /// Steps recorded for `--replay`.
    #[arg(
        long,
        value_name = "N",
        env = "GYMFLEET_REPLAY_STEPS",
        default_value_t = 240
    )]
    pub replay_steps: u32,
    /// No progress bar.
    #[arg(long, short, env = "GYMFLEET_QUIET")]
    pub quiet: bool,
    /// Report this process's peak and current resident memory (VmHWM, VmRSS); with an
    /// embedded server that includes the server's envs.
    #[arg(long, env = "GYMFLEET_REPORT_RSS")]
    pub report_rss: bool,
}

impl Cli {
    /// Checks the flags together and builds the run they describe.
    pub fn resolve(self) -> Result<LoadConfig> {
        self.check_conflicts()?;
        let n_envs = self.n_envs()?;
        at_least_one("--clients", self.clients as u64)?;
        at_least_one("--window", self.window as u64)?;
        let (stop, warmup) = self.run_length()?;
        self.check_physics()?;
        let target = self.target()?;
        let model = Model::resolve(&self.model)?;
        let end_effectors = if self.end_effectors.is_empty() {
            model.default_end_effectors.clone()
        } else {
            self.end_effectors
        };
        let amplitude = self
            .amplitude
            .or_else(|| self.action_type.default_amplitude());
        Ok(LoadConfig {
            target,
            model,
            end_effectors,
            n_envs,
            clients: self.clients,
            stop,
            warmup,
            api: self.api,
            mode: self.mode,
            window: self.window,
            action_type: self.action_type,
            amplitude,
            substeps: self.substeps,
            dt: self.dt,
            max_steps: self.max_steps,
            seed: self.seed,
            task: self.task.map(TaskFile::read).transpose()?,
            units: self.units,
            json: self.json,
            replay: self.replay.map(|path| (path, self.replay_steps)),
            quiet: self.quiet,
            report_rss: self.report_rss,
            connect: self.connect,
        })
    }

    /// Flags that cannot go together, and `--rounds` without `--compare`.
    fn check_conflicts(&self) -> Result<()> {
        let conflict = |flag, other| Err(LoadError::Conflict { flag, other });
        if self.duration.is_some() && self.steps.is_some() {
            return conflict("--duration", "--steps");
        }
        if self.warmup.is_some() && self.warmup_steps.is_some() {
            return conflict("--warmup", "--warmup-steps");
        }
        if self.steps.is_some() && self.warmup.is_some() {
            return conflict("--warmup", "--steps (use --warmup-steps)");
        }
        if self.steps.is_none() && self.warmup_steps.is_some() {
            return conflict("--warmup-steps", "--duration (use --warmup)");
        }
        if self.in_process && self.compare {
            return conflict("--in-process", "--compare");
        }
        if self.in_process && !self.servers.is_empty() {
            return conflict("--in-process", "--server");
        }
        if self.api.single_env() && self.mode == Mode::Stream {
            return conflict("--mode stream", self.api.flag());
        }
        if self.api == Api::Ping && (self.in_process || self.compare) {
            let flag = if self.in_process {
                "--in-process"
            } else {
                "--compare"
            };
            return conflict(
                flag,
                "--api ping (a server round trip has no in-process twin)",
            );
        }
        if self.in_process && self.mode == Mode::Stream {
            return conflict("--mode stream", "--in-process");
        }
        if self.rounds.is_some() && !self.compare {
            return Err(LoadError::bad_flag(
                "--rounds",
                "needs --compare (it alternates the in-process and remote runs)",
            ));
        }
        if let Some(rounds) = self.rounds {
            at_least_one("--rounds", u64::from(rounds))?;
            if rounds > MAX_ROUNDS {
                return Err(LoadError::bad_flag(
                    "--rounds",
                    format!("must be at most {MAX_ROUNDS}, got {rounds}"),
                ));
            }
        }

        Ok(())
    }

    /// Envs per client: `--n-envs`, 1 for the single-env APIs.
    fn n_envs(&self) -> Result<usize> {
        Ok(match (self.api, self.n_envs) {
            (_, Some(0)) => {
                return Err(LoadError::bad_flag("--n-envs", "must be at least 1, got 0"))
            }
            (api, Some(n)) if api.single_env() && n != 1 => {
                return Err(LoadError::bad_flag(
                    "--n-envs",
                    format!(
                        "must be 1 with {} (one env per client), got {n}",
                        api.flag()
                    ),
                ))
            }
            (_, Some(n)) => n,
            (Api::Batch, None) => DEFAULT_N_ENVS,
            (_, None) => 1,
        })
    }

    /// When the run stops, and how long it warms up first.
    fn run_length(&self) -> Result<(StopRule, Warmup)> {
        let stop = match (self.duration, self.steps) {
            (_, Some(steps)) => {
                at_least_one("--steps", steps)?;
                StopRule::Steps(steps)
            }
            (duration, None) => {
                let secs = duration.unwrap_or(DEFAULT_DURATION_SECS);
                if !(secs.is_finite() && secs > 0.0) {
                    return Err(LoadError::bad_flag(
                        "--duration",
                        format!("must be a positive number of seconds, got {secs}"),
                    ));
                }
                StopRule::Seconds(secs)
            }
        };
        let warmup = match (self.warmup, self.warmup_steps) {
            (_, Some(steps)) => Warmup::Steps(steps),
            (Some(secs), None) if !(secs.is_finite() && secs >= 0.0) => {
                return Err(LoadError::bad_flag(
                    "--warmup",
                    format!("must be a number of seconds ≥ 0, got {secs}"),
                ))
            }
            (Some(secs), None) => Warmup::Seconds(secs),
            (None, None) if self.steps.is_some() => Warmup::Steps(0),
            (None, None) => Warmup::Seconds(DEFAULT_WARMUP_SECS),
        };
        Ok((stop, warmup))
    }

    /// The flags that shape each env's physics and actions.
    fn check_physics(&self) -> Result<()> {
        if let Some(substeps) = self.substeps {
            at_least_one("--substeps", u64::from(substeps))?;
        }
        if let Some(max_steps) = self.max_steps {
            at_least_one("--max-steps", u64::from(max_steps))?;
        }
        if let Some(dt) = self.dt {
            if !(dt.is_finite() && dt > 0.0) {
                return Err(LoadError::bad_flag(
                    "--dt",
                    format!("must be a positive number of seconds, got {dt}"),
                ));
            }
        }
        if let Some(a) = self.amplitude {
            if !(a.is_finite() && a >= 0.0) {
                return Err(LoadError::bad_flag(
                    "--amplitude",
                    format!("must be a finite number ≥ 0, got {a}"),
                ));
            }
        }
        Ok(())
    }

    /// Where the run goes: in process, an embedded server, servers, or a comparison.
    fn target(&self) -> Result<Target> {
        if let Some(empty) = self.servers.iter().position(|s| s.trim().is_empty()) {
            return Err(LoadError::bad_flag(
                "--server",
                format!("address {} is empty", empty + 1),
            ));
        }

        let threads = threads_or_cores(self.threads.unwrap_or(0));
        let servers: Vec<String> = self.servers.iter().map(|s| s.trim().to_string()).collect();
        let target = if self.in_process {
            Target::InProcess { threads }
        } else if self.compare {
            Target::Compare {
                threads,
                servers,
                rounds: self.rounds.unwrap_or(1),
            }
        } else if servers.is_empty() {
            Target::Embedded { threads }
        } else {
            Target::Remote { servers }
        };
        check_embedded(&target)?;
        if self.replay.is_some() && self.in_process {
            return Err(LoadError::bad_flag(
                "--replay",
                "records over the network: it needs a server (not --in-process)",
            ));
        }
        if self.replay.is_some() {
            at_least_one("--replay-steps", u64::from(self.replay_steps))?;
        }

        Ok(target)
    }
}

fn at_least_one(flag: &'static str, value: u64) -> Result<()> {
    if value == 0 {
        Err(LoadError::bad_flag(flag, "must be at least 1, got 0"))
    } else {
        Ok(())
    }
}

/// Without the `embedded` feature only remote targets can run.
fn check_embedded(target: &Target) -> Result<()> {
    if cfg!(feature = "embedded") {
        return Ok(());
    }
    match target {
        Target::Remote { .. } => Ok(()),
        Target::Embedded { .. } => Err(LoadError::NotEmbedded {
            what: "running without --server (an embedded server)",
        }),
        Target::InProcess { .. } => Err(LoadError::NotEmbedded {
            what: "--in-process",
        }),
        Target::Compare { .. } => Err(LoadError::NotEmbedded { what: "--compare" }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn command_is_well_formed() {
        Cli::command().debug_assert();
    }

    #[cfg(not(feature = "embedded"))]
    #[test]
    fn pure_network_clients_need_a_server() {
        // The caller's GYMFLEET_* variables must not change what is checked here.
        std::env::vars_os()
            .map(|(key, _)| key)
            .filter(|key| key.to_string_lossy().starts_with("GYMFLEET_"))
            .for_each(|key| std::env::remove_var(key));
        let resolve = |args: &[&str]| {
            let argv = [&["gymfleet-load"][..], args].concat();
            Cli::try_parse_from(argv).unwrap().resolve()
        };
        let message = |args: &[&str]| resolve(args).unwrap_err().to_string();
        assert_eq!(
            message(&[]),
            "running without --server (an embedded server) needs the `embedded` feature; \
             this build is a pure network client: pass --server ADDR"
        );
        assert!(message(&["--in-process"]).starts_with("--in-process needs the `embedded` feature"));
        assert!(message(&["--compare"]).starts_with("--compare needs the `embedded` feature"));
        assert!(resolve(&["--server", "127.0.0.1:1"]).is_ok());
    }
}
