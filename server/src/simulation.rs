//! [`Simulation`]: the server's state — the pool, the open envs and batches, the limits —
//! and the domain operations the RPCs call. Everything CPU-bound here runs on the pool.
//!
//! This file holds the state and the single-env operations; its children hold the rest,
//! each an `impl Simulation` block: `batches.rs`, `states.rs` (saved states, forks),
//! `pictures.rs` (scenes, renders, randomization draws), `documents.rs` (conversion,
//! building an env, the model library), `limits.rs` (every check before anything is
//! built) and `watch.rs` (what the dashboard reads).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use gymfleet_batch::{BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::{ObservationSegment, RobotEnv};

use crate::config::ServerConfig;
use crate::domain::{Action, Created, EnvRequest, EnvStep, EnvStepOutcome, Observed, ServerStatus};
use crate::error::{EntityKind, Result, ServerError};
use crate::metrics::{Gauges, Metrics, OpenCounts};
use crate::pool::{self, Jobs, Lane};
use crate::registry::{Activity, EnvCapacity, Facts, Held, Registry};
use crate::tenant::Tenant;

mod access;
pub(crate) use access::JointState;
mod batches;
mod documents;
mod limits;
mod pictures;
mod states;
pub(crate) mod watch;

use documents::build_env;

/// One open single environment.
pub(crate) struct OpenEnv {
    env: RobotEnv,
    /// Its step counters (see [`Activity::record_step`] for `was_done`).
    activity: Arc<Activity>,
    was_done: Vec<bool>,
    /// The env's observation layout, shared by every observation it returns.
    layout: Arc<[ObservationSegment]>,
}

impl OpenEnv {
    fn new(env: RobotEnv, activity: Arc<Activity>) -> Self {
        let layout = env.spec().observation_layout.as_slice().into();
        OpenEnv {
            env,
            activity,
            was_done: Vec::new(),
            layout,
        }
    }

    /// A zeroed observation of the env's size and layout.
    fn observation_buffer(&self) -> Observed {
        Observed {
            flat: vec![0.0; self.env.spec().observation_dim],
            layout: Arc::clone(&self.layout),
        }
    }

    /// The env's observation now.
    fn observation(&self) -> Observed {
        let mut obs = self.observation_buffer();
        self.env.observe_into(&mut obs.flat);
        obs
    }
}

/// One open batch, with the buffer its next step writes into.
pub(crate) struct OpenBatch {
    batch: EnvBatch,
    out: BatchStepOutput,
    steps: u64,
    activity: Arc<Activity>,
    was_done: Vec<bool>,
}

/// The server's state.
pub(crate) struct Simulation {
    /// 32 random hex digits, new at every start (`ServerInfo.instance_id`).
    instance_id: String,
    config: ServerConfig,
    pool: Jobs,
    capacity: Arc<EnvCapacity>,
    /// Each tenant's quota, made on its first request (at most one per token-file tenant,
    /// or the anonymous one).
    quotas: Mutex<HashMap<Tenant, Arc<EnvCapacity>>>,
    envs: Registry<OpenEnv>,
    batches: Registry<OpenBatch>,
    metrics: Arc<Metrics>,
}

/// 128 bits from the operating system's generator, as hex; if it fails (it should not), the
/// start time and the process id, which still differ from one start to the next.
fn instance_id() -> String {
    let mut bytes = [0u8; 16];
    if getrandom::fill(&mut bytes).is_err() {
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        bytes[..12].copy_from_slice(&now.to_le_bytes()[..12]);
        bytes[12..].copy_from_slice(&std::process::id().to_le_bytes());
    }
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

impl Simulation {
    pub(crate) fn new(config: ServerConfig, pool: StepPool) -> Self {
        Simulation {
            instance_id: instance_id(),
            capacity: EnvCapacity::new(config.max_envs),
            quotas: Mutex::new(HashMap::new()),
            metrics: Arc::new(Metrics::new()),
            envs: Registry::new(EntityKind::Env, "sim", config.clock.clone()),
            batches: Registry::new(EntityKind::Batch, "batch", config.clock.clone()),
            pool: Jobs::new(pool, &config),
            config,
        }
    }

    /// The server's metrics.
    pub(crate) fn metrics(&self) -> &Metrics {
        &self.metrics
    }

    /// The server's metrics, to keep (the authenticator counts its refusals there).
    pub(crate) fn shared_metrics(&self) -> Arc<Metrics> {
        Arc::clone(&self.metrics)
    }

    /// What the gauges of `/metrics` show now.
    pub(crate) fn gauges(&self) -> Gauges {
        Gauges {
            open: self.open_by_tenant(),
            jobs: self.job_queue(),
        }
    }

    /// How the pool's jobs wait for a thread.
    pub(crate) fn job_queue(&self) -> gymfleet_batch::JobQueueStats {
        self.pool.job_queue()
    }

    /// What each tenant holds now (tenants holding nothing are left out).
    pub(crate) fn open_by_tenant(&self) -> Vec<(Tenant, OpenCounts)> {
        let mut counts: HashMap<Tenant, OpenCounts> = HashMap::new();
        for (tenant, n) in self.envs.count_by_owner() {
            counts.entry(tenant).or_default().envs = n;
        }
        for (tenant, n) in self.batches.count_by_owner() {
            counts.entry(tenant).or_default().batches = n;
        }
        // Every tenant that has had a quota (it created something) keeps its series: a
        // tenant whose last env closed reads 0 rather than vanishing from the gauges.
        let quotas = self.quotas.lock().unwrap_or_else(PoisonError::into_inner);
        for (tenant, quota) in quotas.iter() {
            counts.entry(tenant.clone()).or_default().batch_envs = quota.batch_envs();
        }
        let mut counts: Vec<_> = counts.into_iter().collect();
        counts.sort_by(|a, b| a.0.cmp(&b.0));
        counts
    }

    /// Runs `job` on `tenant`'s env `id` on the pool, in the fair lane (an env's work
    /// never waits on other pool work).
    async fn on_env<R, F>(
        &self,
        tenant: &Tenant,
        id: &str,
        operation: &'static str,
        job: F,
    ) -> Result<R>
    where
        R: Send + 'static,
        F: FnOnce(&mut OpenEnv) -> Result<R> + Send + 'static,
    {
        let entry = self.envs.get(tenant, id)?;
        pool::run_locked(&self.pool, Lane::Env, &self.envs, &entry, operation, job).await
    }

    /// Runs `job` on `tenant`'s batch `id` on the pool: in [`Lane::Batch`] when it steps
    /// or resets the batch's envs (it runs their chunks), [`Lane::Env`] when it only reads.
    async fn on_batch<R, F>(
        &self,
        tenant: &Tenant,
        id: &str,
        lane: Lane,
        operation: &'static str,
        job: F,
    ) -> Result<R>
    where
        R: Send + 'static,
        F: FnOnce(&mut OpenBatch) -> Result<R> + Send + 'static,
    {
        let entry = self.batches.get(tenant, id)?;
        pool::run_locked(&self.pool, lane, &self.batches, &entry, operation, job).await
    }

    /// Test-only fault injection (`ServerConfig::panic_on_action`, debug builds only):
    /// whether this action must panic in its pool job.
    #[cfg(debug_assertions)]
    fn injected_panic(&self, action: &Action) -> bool {
        self.config
            .panic_on_action
            .is_some_and(|v| action.values.first() == Some(&v))
    }

    #[cfg(not(debug_assertions))]
    fn injected_panic(&self, _action: &Action) -> bool {
        false
    }

    pub(crate) async fn create_env(&self, tenant: &Tenant, request: EnvRequest) -> Result<Created> {
        let request = self.resolve_model(request)?;
        self.check_document(&request.document)?;
        let reservation = self.reserve(tenant, 1, EntityKind::Env)?;
        let config = self.config.clone();
        let (env, links) = pool::run(&self.pool, Lane::Env, "CreateEnv", move || {
            build_env(request, &config, 1)
        })
        .await?;
        let spec = env.spec().clone();
        let activity = Activity::new(Facts::of(&spec, 1));
        let open = OpenEnv::new(env, Arc::clone(&activity));
        let id = self.envs.insert_with(tenant, open, reservation, activity);
        tracing::info!(env_id = %id, action_dim = spec.action_dim, "created env");
        Ok(Created {
            id,
            spec,
            links,
            batch: None,
        })
    }

    pub(crate) async fn reset_env(
        &self,
        tenant: &Tenant,
        id: &str,
        seed: Option<u64>,
        keyframe: String,
    ) -> Result<Observed> {
        self.on_env(tenant, id, "Reset", move |open| {
            let mut obs = open.observation_buffer();
            // On the wire an empty name means the document's initial keyframe.
            let keyframe = (!keyframe.is_empty()).then_some(keyframe.as_str());
            open.env.reset_to_into(seed, keyframe, &mut obs.flat)?;
            open.was_done.fill(false);
            Ok(obs)
        })
        .await
    }

    pub(crate) async fn step_env(&self, tenant: &Tenant, step: EnvStep) -> Result<EnvStepOutcome> {
        let inject = self.injected_panic(&step.action);
        let outcome = self
            .on_env(tenant, &step.env_id, "Step", move |open| {
                if inject {
                    panic!("injected panic (ServerConfig::panic_on_action)");
                }
                let started = Instant::now();
                let mut observation = open.observation_buffer();
                let flags = open.env.step_with_mocap_into(
                    step.action.action_type,
                    &step.action.values,
                    &step.action.mocap_poses,
                    &mut observation.flat,
                )?;
                open.activity.record_step(
                    started.elapsed(),
                    &[flags.terminated],
                    &[flags.truncated],
                    false,
                    &mut open.was_done,
                );
                Ok(EnvStepOutcome {
                    observation,
                    flags,
                    episode_step: open.env.elapsed_steps(),
                    terms: open.env.term_values().to_vec(),
                })
            })
            .await;
        if outcome.is_ok() {
            self.metrics.env_steps(tenant, 1);
        }
        outcome
    }

    /// Sets one mocap body's target (`SetMocapPose`).
    pub(crate) async fn set_mocap_pose(
        &self,
        tenant: &Tenant,
        id: &str,
        body: String,
        pose: [f32; 7],
    ) -> Result<()> {
        self.on_env(tenant, id, "SetMocapPose", move |open| {
            Ok(open.env.set_mocap_pose(&body, pose)?)
        })
        .await
    }

    /// Heightfield `name`'s new heights in env `env_id`, or (with a `batch_id`) in envs
    /// `env_indices` of a batch (empty: all).
    pub(crate) async fn set_heightfield(
        &self,
        tenant: &Tenant,
        (env_id, batch_id, env_indices): (String, String, Vec<u32>),
        name: String,
        heights: Vec<f32>,
    ) -> Result<()> {
        if batch_id.is_empty() {
            return self
                .on_env(tenant, &env_id, "SetHeightfield", move |open| {
                    Ok(open.env.set_heightfield(&name, &heights)?)
                })
                .await;
        }
        self.on_batch(
            tenant,
            &batch_id,
            Lane::Batch,
            "SetHeightfield",
            move |open| Ok(open.batch.set_heightfield(&env_indices, &name, &heights)?),
        )
        .await
    }

    pub(crate) async fn observe_env(&self, tenant: &Tenant, id: &str) -> Result<Observed> {
        self.on_env(tenant, id, "Observe", move |open| Ok(open.observation()))
            .await
    }

    /// Takes a value out of its registry for good. The id is forgotten at once, so no new
    /// call finds it; a call already running or queued on it (a long step) ends first, and
    /// the value is freed then, even if the caller of `Close` has gone by then (its
    /// deadline passed while it waited).
    async fn close<T: Send + 'static>(
        &self,
        registry: &Registry<T>,
        tenant: &Tenant,
        id: &str,
    ) -> Result<()> {
        let entry = registry.get(tenant, id)?;
        registry.remove(id);
        let kind = registry.kind();
        let pool = self.pool.clone();
        let id = id.to_string();
        // A task of its own: dropping this call's future (a cancelled or timed-out Close)
        // does not stop it.
        let closing = tokio::spawn(async move {
            let mut slot = entry.lock(kind).await?;
            let value = slot.take().map(Held::release);
            drop(slot);
            // The capacity is free as of now; freeing thousands of worlds is CPU work too.
            pool.spawn(move || drop(value));
            tracing::info!(id, "closed");
            Ok(())
        });
        closing
            .await
            .map_err(|_| ServerError::JobLost { operation: "Close" })?
    }

    pub(crate) async fn close_env(&self, tenant: &Tenant, id: &str) -> Result<()> {
        self.close(&self.envs, tenant, id).await
    }

    /// The server as `tenant` sees it: its own envs and batches only, unless auth is off
    /// (then everyone is the anonymous tenant and sees all).
    pub(crate) fn status(&self, tenant: &Tenant) -> ServerStatus<'_> {
        ServerStatus {
            instance_id: &self.instance_id,
            threads: self.pool.threads(),
            tenant: tenant.clone(),
            envs: self.envs.len_of(tenant),
            batches: self.batches.len_of(tenant),
            batch_envs: self.quota(tenant).batch_envs(),
            config: &self.config,
        }
    }

    /// Closes every env and batch idle for at least `ttl`, and logs each.
    pub(crate) fn reclaim_idle(&self, ttl: Duration) {
        let envs = self.envs.take_idle(ttl);
        let batches = self.batches.take_idle(ttl);
        for (id, idle, _) in &envs {
            tracing::info!(env_id = %id, idle_secs = idle.as_secs_f64(), "reclaimed idle env");
        }
        for (id, idle, held) in &batches {
            tracing::info!(
                batch_id = %id,
                n_envs = held.value.batch.n_envs(),
                idle_secs = idle.as_secs_f64(),
                "reclaimed idle batch"
            );
        }
        if !envs.is_empty() || !batches.is_empty() {
            // Capacity is free at once; the worlds are freed on the pool.
            let envs: Vec<_> = envs.into_iter().map(|(_, _, h)| h.release()).collect();
            let batches: Vec<_> = batches.into_iter().map(|(_, _, h)| h.release()).collect();
            self.pool.spawn(move || drop((envs, batches)));
        }
    }
}
