//! The remote runner: `clients` concurrent clients, each with its own connection and
//! batch (or single env) on one of the servers (round-robin), set up first, then
//! started together and driven through `gymfleet-client` with unary `StepBatch`,
//! pipelined `StreamBatch`, or single-env `Step` calls.

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::Instant;

use gymfleet_client::{
    Autoreset, Batch, BatchOptions, Client, ClientError, Env, EnvOptions, JointInfo, Replay,
};
use tokio::task::JoinSet;

use crate::actions::ActionPlan;
use crate::config::{Api, LoadConfig, Mode};
use crate::error::{LoadError, Result};
use crate::meter::{Meter, Schedule, Tally};
use crate::progress::Progress;
use crate::report::RunResult;
use crate::rss::Memory;

/// What one client drives.
enum Handle {
    Batch(Batch),
    Env(Box<Env>),
}

/// One client, set up and ready to step.
struct Session {
    client: Client,
    server: String,
    handle: Handle,
    plan: ActionPlan,
    first_env: u64,
}

/// Runs `config` against `servers`; `kind` says what they are in the report (e.g.
/// "embedded server" or "server").
pub(crate) async fn run(config: &LoadConfig, servers: &[String], kind: &str) -> Result<RunResult> {
    let config = Arc::new(config.clone());
    let label = match (config.api, config.mode) {
        (Api::Env, _) => "remote env Step".to_string(),
        (Api::Observe, _) => "remote env Observe".to_string(),
        (Api::Ping, _) => "remote GetServerInfo".to_string(),
        (Api::Batch, Mode::Unary) => "remote unary".to_string(),
        (Api::Batch, Mode::Stream) => format!("remote stream w{}", config.window),
    };
    let mut progress = Progress::new(
        config.quiet,
        format!(
            "{label}: creating {} × {} envs",
            config.clients, config.n_envs
        ),
    );

    let mut setups = JoinSet::new();
    for c in 0..config.clients {
        let server = servers[c % servers.len()].clone();
        let config = Arc::clone(&config);
        setups.spawn(async move { (c, setup(&config, c, server).await) });
    }
    let mut sessions: Vec<Option<Session>> = (0..config.clients).map(|_| None).collect();
    let mut first_failure = None;
    while let Some(joined) = setups.join_next().await {
        let (c, session) = joined.map_err(|e| LoadError::setup("client task", e))?;
        match session {
            Ok(s) => sessions[c] = Some(s),
            Err(e) => {
                first_failure.get_or_insert(e);
            }
        }
    }
    let sessions: Vec<Session> = sessions.into_iter().flatten().collect();
    if let Some(failure) = first_failure {
        close_all(&sessions).await;
        progress.finish();
        return Err(failure);
    }
    let target = describe(kind, &sessions).await;

    let start = Instant::now();
    let schedule = Schedule::new(&config, start);
    progress.begin(
        &label,
        &schedule,
        start,
        config.clients as u64,
        config.n_envs as u64,
    );
    let mut drivers = JoinSet::new();
    for (c, session) in sessions.into_iter().enumerate() {
        let meter = Meter::new(schedule, progress.counter());
        let config = Arc::clone(&config);
        drivers.spawn(async move {
            let tally = drive(&config, &session, meter).await;
            (c, session, tally)
        });
    }
    let mut done: Vec<(usize, Session, Tally)> = Vec::with_capacity(config.clients);
    while let Some(joined) = drivers.join_next().await {
        done.push(joined.map_err(|e| LoadError::setup("client task", e))?);
    }
    progress.finish();
    done.sort_by_key(|(c, _, _)| *c);

    let memory_loaded = config.report_rss.then(Memory::current).flatten();
    let (sessions, tallies): (Vec<Session>, Vec<Tally>) =
        done.into_iter().map(|(_, s, t)| (s, t)).unzip();
    close_all(&sessions).await;
    if let Some((path, steps)) = &config.replay {
        record_replay(&config, &servers[0], path, *steps).await?;
    }
    let mut result = RunResult::from_tallies(label, target, &tallies);
    result.memory_loaded = memory_loaded;
    Ok(result)
}

/// Records one env of the model (env 0's actions of the run) for `steps` steps on `server`
/// and writes the HTML replay to `path`.
async fn record_replay(
    config: &LoadConfig,
    server: &str,
    path: &std::path::Path,
    steps: u32,
) -> Result<()> {
    let stage = |what: &str| format!("replay: {what} on {server}");
    let client = config
        .connect
        .builder(server.to_string())
        .connect()
        .await
        .map_err(|e| LoadError::connect(stage("connect"), e))?;
    let env = client
        .create_env(env_options(
            config,
            config.model.document.clone(),
            config.seed,
        ))
        .await
        .map_err(|e| LoadError::setup(stage("CreateEnv"), e))?;
    let recorded = async {
        env.reset(Some(config.seed)).await?;
        let (joints, dim) = (&env.info().joints, env.info().action_dim);
        let plan = config.action_plan(&dof_limits(joints, dim), &action_bounds(joints, dim));
        let mut replay = Replay::new(config.model.name.clone(), env.info().dt);
        replay.capture(&env).await?;
        let mut action = vec![0.0; plan.action_dim()];
        for k in 0..u64::from(steps) {
            plan.fill(k, 0, &mut action);
            let step = env.step(config.action_type.to_client(), &action).await?;
            replay.capture(&env).await?;
            if step.terminated || step.truncated {
                break;
            }
        }
        Ok::<_, ClientError>(replay)
    }
    .await;
    let _ = env.close().await;
    let replay = recorded.map_err(|e| LoadError::setup(stage("record"), e))?;
    replay.write_html(path).map_err(|e| LoadError::Output {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })
}

/// Connects client `c` to `server`, creates its batch or env and resets it.
async fn setup(config: &LoadConfig, c: usize, server: String) -> Result<Session> {
    let stage = |what: &str| format!("client {c}: {what} on {server}");
    let client = config
        .connect
        .builder(server.clone())
        .connect()
        .await
        .map_err(|e| LoadError::connect(stage("connect"), e))?;
    let first_env = config.first_env(c);
    let document = config.model.document.clone();
    let (handle, joints, action_dim) = match config.api {
        Api::Batch => {
            let options =
                BatchOptions::from_env(env_options(config, document, config.seed), config.n_envs)
                    .seed_offset(first_env)
                    .autoreset(Autoreset::SameStep);
            let batch = client
                .create_batch(options)
                .await
                .map_err(|e| LoadError::setup(stage("CreateBatch"), e))?;
            batch
                .reset_with_offset(Some(config.seed), first_env)
                .await
                .map_err(|e| LoadError::setup(stage("ResetBatch"), e))?;
            let info = batch.info();
            let (joints, dim) = (info.joints.clone(), info.action_dim);
            (Handle::Batch(batch), joints, dim)
        }
        Api::Env | Api::Observe | Api::Ping => {
            let seed = config.seed.wrapping_add(first_env);
            let options = env_options(config, document, seed);
            let env = client
                .create_env(options)
                .await
                .map_err(|e| LoadError::setup(stage("CreateEnv"), e))?;
            env.reset(Some(seed))
                .await
                .map_err(|e| LoadError::setup(stage("Reset"), e))?;
            let (joints, dim) = (env.info().joints.clone(), env.info().action_dim);
            (Handle::Env(Box::new(env)), joints, dim)
        }
    };
    Ok(Session {
        client,
        server,
        handle,
        plan: config.action_plan(
            &dof_limits(&joints, action_dim),
            &action_bounds(&joints, action_dim),
        ),
        first_env,
    })
}

/// The env configuration every client uses: the model's end effectors, `seed`, the
/// step settings given on the command line (the server's defaults otherwise), the
/// `--task` (the server checks it: a bad one fails `CreateBatch`/`CreateEnv` with its
/// `INVALID_ARGUMENT`) and the `--units`.
fn env_options(config: &LoadConfig, document: String, seed: u64) -> EnvOptions {
    let mut options = EnvOptions::new(document)
        .end_effectors(config.end_effectors.clone())
        .seed(seed);
    if let Some(s) = config.substeps {
        options = options.substeps(s);
    }
    if let Some(dt) = config.dt {
        options = options.dt(dt);
    }
    if let Some(m) = config.max_steps {
        options = options.max_steps(m);
    }
    if let Some(task) = &config.task {
        options = options.task(gymfleet_client::Task::terms(task.json.clone()));
    }
    options.units(config.units.client())
}

/// Each actuated DOF's `(min, max)` where both are set, in action order; all `None` if
/// the actuated joints do not add up to `action_dim` DOFs.
pub(crate) fn dof_limits(joints: &[JointInfo], action_dim: usize) -> Vec<Option<(f64, f64)>> {
    let limits: Vec<_> = joints
        .iter()
        .filter(|j| j.actuated)
        .flat_map(|j| j.limits.iter())
        .map(|l| l.min.zip(l.max))
        .collect();
    if limits.len() == action_dim {
        limits
    } else {
        vec![None; action_dim]
    }
}

/// The actuated DOFs' torque action bounds, in action order; empty where the server sent
/// none (older servers), so that the plan falls back to its default amplitude.
pub(crate) fn action_bounds(joints: &[JointInfo], action_dim: usize) -> Vec<f64> {
    let bounds: Vec<f64> = joints
        .iter()
        .filter(|j| j.actuated)
        .flat_map(|j| j.action_bounds.iter().copied())
        .collect();
    if bounds.len() == action_dim {
        bounds
    } else {
        Vec::new()
    }
}

/// "kind ADDR (gymfleet V, N threads)" for each distinct server.
async fn describe(kind: &str, sessions: &[Session]) -> String {
    let mut seen: Vec<String> = Vec::new();
    let mut parts = Vec::new();
    for s in sessions {
        if seen.contains(&s.server) {
            continue;
        }
        seen.push(s.server.clone());
        parts.push(match s.client.server_info().await {
            Ok(info) => format!(
                "{} (gymfleet {}, {} threads)",
                s.server, info.version, info.threads
            ),
            Err(_) => s.server.clone(),
        });
    }
    format!("{kind} {}", parts.join(", "))
}

async fn close_all(sessions: &[Session]) {
    for s in sessions {
        // Closing is best effort: the figures are taken, and the server's idle TTL
        // reclaims anything left.
        let _ = match &s.handle {
            Handle::Batch(b) => b.close().await,
            Handle::Env(e) => e.close().await,
        };
    }
}

async fn drive(config: &LoadConfig, session: &Session, mut meter: Meter) -> Tally {
    match (&session.handle, config.mode) {
        (Handle::Batch(batch), Mode::Unary) => {
            drive_unary(config, session, batch, &mut meter).await
        }
        (Handle::Batch(batch), Mode::Stream) => {
            drive_stream(config, session, batch, &mut meter).await
        }
        (Handle::Env(env), _) => drive_env(config, session, env, &mut meter).await,
    }
    meter.tally
}

async fn drive_unary(config: &LoadConfig, session: &Session, batch: &Batch, meter: &mut Meter) {
    let action_type = config.action_type.to_client();
    let n_envs = batch.info().n_envs as u64;
    let mut actions = vec![0.0; batch.info().n_envs * session.plan.action_dim()];
    while let Some(k) = meter.next_call() {
        session.plan.fill(k, session.first_env, &mut actions);
        let started = Instant::now();
        match batch.step(action_type, &actions).await {
            Ok(step) => meter.success(started, n_envs, count_true(step.terminated())),
            Err(e) => meter.failure(e.to_string()),
        }
    }
}

async fn drive_stream(config: &LoadConfig, session: &Session, batch: &Batch, meter: &mut Meter) {
    let action_type = config.action_type.to_client();
    let n_envs = batch.info().n_envs as u64;
    let window = config.window;
    let mut actions = vec![0.0; batch.info().n_envs * session.plan.action_dim()];
    let mut stream = match batch.stream_with_window(window).await {
        Ok(s) => s,
        Err(e) => return meter.side_error(e.to_string()),
    };
    let mut sent: VecDeque<Instant> = VecDeque::with_capacity(window);
    loop {
        let mut broken: Option<ClientError> = None;
        // Keep fewer than `window` pending before a send, so `send` never has to
        // receive a result itself and every result is timed when it arrives.
        while stream.pending() < window {
            let Some(k) = meter.next_call() else { break };
            session.plan.fill(k, session.first_env, &mut actions);
            sent.push_back(Instant::now());
            if let Err(e) = stream.send(action_type, &actions).await {
                broken = Some(e);
                break;
            }
        }
        if broken.is_none() {
            match stream.next().await {
                None => break,
                Some(Ok(step)) => {
                    let started = sent.pop_front().unwrap_or_else(Instant::now);
                    meter.success(started, n_envs, count_true(step.terminated()));
                    continue;
                }
                Some(Err(e)) => broken = Some(e),
            }
        }
        // The stream is over: every step in flight is lost. Open a new one.
        if let Some(e) = broken {
            let lost = sent.len().max(1);
            meter.failure(e.to_string());
            for _ in 1..lost {
                meter.failure("lost with its stream".to_string());
            }
            sent.clear();
            stream = match batch.stream_with_window(window).await {
                Ok(s) => s,
                Err(e) => return meter.side_error(e.to_string()),
            };
        }
    }
    if let Err(e) = stream.finish().await {
        meter.side_error(e.to_string());
    }
}

async fn drive_env(config: &LoadConfig, session: &Session, env: &Env, meter: &mut Meter) {
    match config.api {
        Api::Observe => {
            while meter.next_call().is_some() {
                let started = Instant::now();
                match env.observe().await {
                    Ok(_) => meter.success(started, 1, 0),
                    Err(e) => meter.failure(e.to_string()),
                }
            }
            return;
        }
        Api::Ping => {
            while meter.next_call().is_some() {
                let started = Instant::now();
                match session.client.server_info().await {
                    Ok(_) => meter.success(started, 1, 0),
                    Err(e) => meter.failure(e.to_string()),
                }
            }
            return;
        }
        Api::Env | Api::Batch => {}
    }
    let action_type = config.action_type.to_client();
    let mut action = vec![0.0; session.plan.action_dim()];
    let seed = config.seed.wrapping_add(session.first_env);
    while let Some(k) = meter.next_call() {
        session.plan.fill(k, session.first_env, &mut action);
        let started = Instant::now();
        match env.step(action_type, &action).await {
            Ok(step) => {
                meter.success(started, 1, u64::from(step.terminated));
                if step.done {
                    // Untimed: a new episode, as a trainer would start one.
                    if let Err(e) = env.reset(Some(seed)).await {
                        meter.side_error(e.to_string());
                    }
                }
            }
            Err(e) => meter.failure(e.to_string()),
        }
    }
}

fn count_true(flags: &[bool]) -> u64 {
    flags.iter().filter(|&&f| f).count() as u64
}
