//! The in-process runner (feature `embedded`): the same workload as the remote runner,
//! stepped directly with `gymfleet-batch` on a local `StepPool` — no server, no
//! network — so that remote / in-process is the cost of the server. Each client is a
//! thread with its own `EnvBatch` (or `RobotEnv`); every step runs inside the pool
//! (`StepPool::install`), as the server runs it, so `--threads N` means N threads of
//! physics on both sides.

use std::time::Instant;

use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::{
    ActionType, EnvConfig, EnvError, RobotEnv, TaskKind, TaskSpec, TermsTask, Units,
    DEFAULT_MAX_STEPS, DEFAULT_SUBSTEPS,
};

use crate::actions::{ActionKind, ActionPlan};
use crate::config::{Api, LoadConfig, UnitsArg};
use crate::error::{LoadError, Result};
use crate::meter::{Meter, Schedule, Tally};
use crate::progress::Progress;
use crate::report::RunResult;
use crate::rss::Memory;

/// Runs `config` on a local pool of `threads` threads (0: one per core).
pub(crate) fn run(config: &LoadConfig, threads: usize) -> Result<RunResult> {
    let label = match config.api {
        Api::Batch => "in-process",
        Api::Env => "in-process env",
        Api::Observe => "in-process env Observe",
        // Refused by the command line: a round trip has no in-process twin.
        Api::Ping => "in-process (nothing)",
    };
    let mut progress = Progress::new(
        config.quiet,
        format!(
            "{label}: creating {} × {} envs",
            config.clients, config.n_envs
        ),
    );
    let template = template(config)?;
    let plan = config.action_plan(&dof_limits(&template), &action_bounds(&template));
    let pool =
        StepPool::new(threads).map_err(|e| LoadError::setup("in-process: start the pool", e))?;
    let target = format!("StepPool ({} threads), no network", pool.threads());

    let mut clients: Vec<Client> = Vec::with_capacity(config.clients);
    for c in 0..config.clients {
        let first_env = config.first_env(c);
        let stage = |what: &str| format!("in-process client {c}: {what}");
        let driven = match config.api {
            Api::Batch => {
                let mut batch =
                    EnvBatch::for_pool(&template, config.n_envs, Autoreset::SameStep, &pool)
                        .map_err(|e| LoadError::setup(stage("create the batch"), e))?;
                let mut scratch = Vec::new();
                batch
                    .reset(&pool, Some(config.seed), first_env, &mut scratch)
                    .map_err(|e| LoadError::setup(stage("reset the batch"), e))?;
                Driven::Batch(Box::new(batch))
            }
            Api::Env | Api::Observe | Api::Ping => {
                let mut env = template.clone();
                env.reset(Some(config.seed.wrapping_add(first_env)));
                Driven::Env(Box::new(env))
            }
        };
        clients.push(Client { driven, first_env });
    }

    let start = Instant::now();
    let schedule = Schedule::new(config, start);
    progress.begin(
        label,
        &schedule,
        start,
        config.clients as u64,
        config.n_envs as u64,
    );
    let action_type = to_env(config.action_type);
    let observe_only = config.api == Api::Observe;
    let tallies: Vec<Tally> = std::thread::scope(|s| {
        let handles: Vec<_> = clients
            .iter_mut()
            .map(|client| {
                let meter = Meter::new(schedule, progress.counter());
                let (pool, plan) = (&pool, &plan);
                s.spawn(move || {
                    client.drive(pool, plan, action_type, config.seed, observe_only, meter)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("in-process client thread panicked"))
            .collect()
    });
    progress.finish();
    let memory_loaded = config.report_rss.then(Memory::current).flatten();
    drop(clients);
    let mut result = RunResult::from_tallies(label.to_string(), target, &tallies);
    result.memory_loaded = memory_loaded;
    Ok(result)
}

/// The env every batch clones, configured as the server would configure it. A task
/// that does not parse, or that does not fit the model, is a setup error naming its file.
fn template(config: &LoadConfig) -> Result<RobotEnv> {
    let task_stage = |file: &std::path::Path| format!("in-process: --task '{}'", file.display());
    let task = match &config.task {
        None => None,
        Some(task) => Some(TaskSpec {
            kind: TaskKind::Terms(
                TermsTask::from_json(&task.json)
                    .map_err(|e| LoadError::setup(task_stage(&task.file), e))?,
            ),
            // As a request's terms task without `action_cost` (`Task::terms`).
            action_cost: 0.0,
        }),
    };
    let env_config = EnvConfig {
        end_effector_ids: config.end_effectors.clone(),
        // 0: the document's `simulation.dt`, else the default, as on a server.
        dt: config.dt.unwrap_or(0.0),
        substeps: config.substeps.unwrap_or(DEFAULT_SUBSTEPS),
        max_steps: config.max_steps.unwrap_or(DEFAULT_MAX_STEPS),
        seed: config.seed,
        task,
        units: match config.units {
            UnitsArg::Document => Units::Document,
            UnitsArg::Si => Units::Si,
        },
        // Gains, reset noise and the rest: the defaults, as the server's CreateBatch
        // without them.
        ..EnvConfig::default()
    };
    RobotEnv::from_json(&config.model.document, env_config).map_err(|e| {
        let stage = match (&e, &config.task) {
            // The task names what the model lacks (a joint, an instance, a site).
            (EnvError::BadTask { .. }, Some(task)) => task_stage(&task.file),
            _ => format!("in-process: load model {}", config.model.name),
        };
        LoadError::setup(stage, e)
    })
}

/// Each actuated DOF's hard limits (one per action value), as the server reports them,
/// then each actuator's control range.
fn dof_limits(env: &RobotEnv) -> Vec<Option<(f64, f64)>> {
    let spec = env.spec();
    spec.dofs
        .iter()
        .filter(|d| d.actuated)
        .map(|d| d.limits.map(|[min, max]| (min, max)))
        .chain(
            spec.actuators
                .iter()
                .map(|a| a.ctrl_range.map(|[min, max]| (min, max))),
        )
        .collect()
}

/// Each action value's torque bound: the actuated DOFs', then each actuator's largest
/// control (1 without a range).
fn action_bounds(env: &RobotEnv) -> Vec<f64> {
    let spec = env.spec();
    spec.dofs
        .iter()
        .filter(|d| d.actuated)
        .map(|d| d.action_bound)
        .chain(spec.actuators.iter().map(|a| {
            a.ctrl_range
                .map_or(1.0, |[min, max]| min.abs().max(max.abs()))
        }))
        .collect()
}

fn to_env(kind: ActionKind) -> ActionType {
    match kind {
        ActionKind::Torque => ActionType::Torque,
        ActionKind::Position => ActionType::Position,
        ActionKind::Velocity => ActionType::Velocity,
    }
}

enum Driven {
    Batch(Box<EnvBatch>),
    Env(Box<RobotEnv>),
}

/// One in-process client: its batch or env and its first global env index.
struct Client {
    driven: Driven,
    first_env: u64,
}

impl Client {
    fn drive(
        &mut self,
        pool: &StepPool,
        plan: &ActionPlan,
        action_type: ActionType,
        seed: u64,
        observe_only: bool,
        mut meter: Meter,
    ) -> Tally {
        let first_env = self.first_env;
        match &mut self.driven {
            Driven::Batch(batch) => {
                let n_envs = batch.n_envs();
                let mut actions = vec![0.0; n_envs * plan.action_dim()];
                let mut out = BatchStepOutput::default();
                while let Some(k) = meter.next_call() {
                    plan.fill(k, first_env, &mut actions);
                    let started = Instant::now();
                    match pool.install(|| batch.step(pool, action_type, &actions, &mut out)) {
                        Ok(()) => {
                            let terminated = out.terminated.iter().filter(|&&t| t).count();
                            meter.success(started, n_envs as u64, terminated as u64);
                        }
                        Err(e) => meter.failure(e.to_string()),
                    }
                }
            }
            Driven::Env(env) if observe_only => {
                let mut obs = vec![0.0; env.spec().observation_dim];
                while meter.next_call().is_some() {
                    let started = Instant::now();
                    pool.install(|| env.observe_into(&mut obs));
                    meter.success(started, 1, 0);
                }
            }
            Driven::Env(env) => {
                let mut action = vec![0.0; plan.action_dim()];
                let mut obs = vec![0.0; env.spec().observation_dim];
                while let Some(k) = meter.next_call() {
                    plan.fill(k, first_env, &mut action);
                    let started = Instant::now();
                    match pool.install(|| env.step_into(action_type, &action, &mut obs)) {
                        Ok(flags) => {
                            meter.success(started, 1, u64::from(flags.terminated));
                            if flags.done() {
                                env.reset_into(Some(seed.wrapping_add(first_env)), &mut obs);
                            }
                        }
                        Err(e) => meter.failure(e.to_string()),
                    }
                }
            }
        }
        meter.tally
    }
}
