//! [`LoadConfig`]: a validated load run — where it runs ([`Target`]), what it loads,
//! how it steps ([`Api`], [`Mode`]), and when it stops ([`StopRule`], [`Warmup`]).
//! Built from the command line by [`crate::Cli::resolve`], or by hand in tests.

use std::num::NonZeroUsize;
use std::path::PathBuf;

use serde::Serialize;

use crate::actions::{ActionKind, ActionPlan};
use crate::error::{LoadError, Result};
use crate::model::Model;

/// Where the workload runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Target {
    /// Remote servers; clients are spread over them round-robin.
    Remote {
        /// `host:port` or `http://host:port`.
        servers: Vec<String>,
    },
    /// A gymfleet server started in this process on `127.0.0.1:0`.
    Embedded {
        /// Its step-pool threads.
        threads: usize,
    },
    /// `gymfleet-batch` stepped directly on a `StepPool`: no server, no network.
    InProcess {
        /// The pool's threads.
        threads: usize,
    },
    /// In process and remote (the given servers, or an embedded server with the same
    /// thread count), `rounds` times, and the throughput ratio remote / in-process: each
    /// round's, and their median. Odd rounds run in process first, even rounds remote
    /// first, so a machine that drifts during the run weighs on both sides alike.
    Compare {
        /// The in-process pool's (and embedded server's) threads.
        threads: usize,
        /// Remote servers; empty means an embedded server.
        servers: Vec<String>,
        /// Rounds of the two runs (at least 1).
        rounds: u32,
    },
}

/// The units of observations and of a terms task's values (`--units`). Actions keep
/// theirs (N·m, deg, deg/s) in both.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum UnitsArg {
    /// The document's: deg and mm (and per second).
    #[default]
    Document,
    /// SI, as MuJoCo and Gymnasium report them: rad and m (and per second).
    Si,
}

impl UnitsArg {
    /// The client's units.
    pub fn client(self) -> gymfleet_client::Units {
        match self {
            UnitsArg::Document => gymfleet_client::Units::Document,
            UnitsArg::Si => gymfleet_client::Units::Si,
        }
    }
}

/// A terms task read from `--task FILE`: its file (for messages and the report) and its
/// JSON, sent as it is (remote) or parsed by the env crate (in process).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TaskFile {
    /// The file as given.
    pub file: PathBuf,
    /// Its text: the terms task's JSON (docs/tasks.md, "Terms tasks").
    pub json: String,
}

impl TaskFile {
    /// Reads `file`; an unreadable file is a `--task` error naming it.
    pub fn read(file: impl Into<PathBuf>) -> Result<Self> {
        let file = file.into();
        match std::fs::read_to_string(&file) {
            Ok(json) => Ok(TaskFile { file, json }),
            Err(e) => Err(LoadError::bad_flag(
                "--task",
                format!("cannot read '{}': {e}", file.display()),
            )),
        }
    }
}

/// Which RPCs carry the steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Api {
    /// `CreateBatch` + `StepBatch` (or `StreamBatch`): `n_envs` env-steps per call.
    Batch,
    /// `CreateEnv` + `Step`: one env-step per call, to measure single-env latency.
    Env,
    /// `CreateEnv` + `Observe`: a single-env call that goes through the pool but runs
    /// no physics, to measure the pool hand-off (Step minus Observe is the physics).
    Observe,
    /// `GetServerInfo`: a call answered without the pool, the transport's floor.
    Ping,
}

impl Api {
    /// Whether each client drives one env (rather than a batch).
    pub fn single_env(self) -> bool {
        !matches!(self, Api::Batch)
    }

    /// The flag that selects it, e.g. `--api env`.
    pub fn flag(self) -> &'static str {
        match self {
            Api::Batch => "--api batch",
            Api::Env => "--api env",
            Api::Observe => "--api observe",
            Api::Ping => "--api ping",
        }
    }
}

/// How batch steps are sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// One `StepBatch` call at a time per client.
    Unary,
    /// A `StreamBatch` stream per client with up to `window` steps in flight.
    Stream,
}

/// When a client stops calling.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopRule {
    /// After this many seconds of measurement (after the warmup), for every client.
    Seconds(f64),
    /// After this many measured calls per client.
    Steps(u64),
}

/// What is excluded from the figures at the start.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Warmup {
    /// The first seconds of a timed run.
    Seconds(f64),
    /// The first calls of each client.
    Steps(u64),
}

/// A complete, validated load run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoadConfig {
    /// Where it runs.
    pub target: Target,
    /// The document.
    pub model: Model,
    /// Observed instances.
    pub end_effectors: Vec<String>,
    /// Envs per batch (1 with the single-env APIs).
    pub n_envs: usize,
    /// Concurrent clients, each with its own connection and batch (or env).
    pub clients: usize,
    /// When each client stops.
    pub stop: StopRule,
    /// What is left out of the figures.
    pub warmup: Warmup,
    /// Batch or single-env RPCs.
    pub api: Api,
    /// Unary or streamed batch steps.
    pub mode: Mode,
    /// Steps in flight per stream.
    pub window: usize,
    /// How action values are read.
    pub action_type: ActionKind,
    /// Action amplitude (N·m, deg or deg/s) for every DOF; `None` (torque actions only):
    /// each DOF's own action bound, as the server reports it.
    pub amplitude: Option<f32>,
    /// Integration substeps per step; `None` is the server's default (5).
    pub substeps: Option<u32>,
    /// Seconds per step; `None` is the server's default (1/240).
    pub dt: Option<f64>,
    /// Episode length; `None` is the server's default (1000). Batches reset finished
    /// envs within the step (same-step autoreset); single envs are reset when done.
    pub max_steps: Option<u32>,
    /// Seed of the envs and of the actions.
    pub seed: u64,
    /// A terms task (`--task FILE`), given to every env; `None`: no task.
    pub task: Option<TaskFile>,
    /// The units of observations and of the task's values.
    pub units: UnitsArg,
    /// Where to write the JSON results.
    pub json: Option<PathBuf>,
    /// Where to write an HTML replay of one env, and how many steps it records.
    pub replay: Option<(PathBuf, u32)>,
    /// No progress bar.
    pub quiet: bool,
    /// Report this process's peak and current resident memory.
    pub report_rss: bool,
    /// Token and TLS settings for remote servers (never written to the report).
    #[serde(skip)]
    pub connect: gymfleet_client::ConnectArgs,
}

impl LoadConfig {
    /// A short run of `model` on an embedded server: 1 client, `steps` measured steps,
    /// no warmup, unary batch steps of small torques. A base for tests and examples.
    pub fn new(model: Model, n_envs: usize, steps: u64) -> Self {
        LoadConfig {
            target: Target::Embedded { threads: 0 },
            end_effectors: model.default_end_effectors.clone(),
            amplitude: None,
            model,
            n_envs,
            clients: 1,
            stop: StopRule::Steps(steps),
            warmup: Warmup::Steps(0),
            api: Api::Batch,
            mode: Mode::Unary,
            window: gymfleet_client::DEFAULT_STREAM_WINDOW,
            action_type: ActionKind::Torque,
            substeps: None,
            dt: None,
            max_steps: None,
            seed: 0,
            task: None,
            units: UnitsArg::Document,
            json: None,
            replay: None,
            quiet: true,
            report_rss: false,
            connect: gymfleet_client::ConnectArgs::default(),
        }
    }

    /// The action plan for DOFs with these limits and torque action bounds (same for every
    /// target).
    pub fn action_plan(&self, limits: &[Option<(f64, f64)>], bounds: &[f64]) -> ActionPlan {
        ActionPlan::new(self.action_type, self.amplitude, limits, bounds, self.seed)
    }

    /// The first global env index of client `client`: clients' envs are numbered
    /// consecutively, so each has its own seeds and actions.
    pub fn first_env(&self, client: usize) -> u64 {
        (client * self.n_envs) as u64
    }

    /// One line describing the run, for the report.
    pub fn summary(&self) -> String {
        let api = match (self.api, self.mode) {
            (Api::Env, _) => "single-env Step".to_string(),
            (Api::Observe, _) => "single-env Observe".to_string(),
            (Api::Ping, _) => "GetServerInfo".to_string(),
            (Api::Batch, Mode::Unary) => "unary StepBatch".to_string(),
            (Api::Batch, Mode::Stream) => format!("StreamBatch window {}", self.window),
        };
        let stop = match self.stop {
            StopRule::Seconds(s) => format!("{s} s"),
            StopRule::Steps(n) => format!("{n} steps"),
        };
        let warmup = match self.warmup {
            Warmup::Seconds(s) => format!("{s} s"),
            Warmup::Steps(n) => format!("{n} steps"),
        };
        let envs = if self.n_envs == 1 { "env" } else { "envs" };
        let clients = if self.clients == 1 {
            "client"
        } else {
            "clients"
        };
        if self.api == Api::Ping {
            // No env, model or action: only the transport.
            return format!(
                "{api} · {} {clients} · {stop} after {warmup} warmup",
                self.clients
            );
        }
        format!(
            "model {} · {} {envs} × {} {clients} · {api} · {} ±{} · substeps {} · dt {} · seed {}{}{} · {stop} after {warmup} warmup",
            self.model.name,
            self.n_envs,
            self.clients,
            self.action_type.as_str(),
            self.amplitude.map_or("each DOF's bound".to_string(), |a| a.to_string()),
            self.substeps.map_or("default".into(), |s| s.to_string()),
            self.dt.map_or("default".into(), |s| format!("{s} s")),
            self.seed,
            match &self.task {
                None => String::new(),
                Some(task) => format!(" · task {}", task.file.display()),
            },
            match self.units {
                UnitsArg::Document => "",
                UnitsArg::Si => " · units si",
            },
        )
    }
}

/// Threads for "0 = one per core".
pub fn threads_or_cores(threads: usize) -> usize {
    if threads == 0 {
        std::thread::available_parallelism().map_or(1, NonZeroUsize::get)
    } else {
        threads
    }
}
