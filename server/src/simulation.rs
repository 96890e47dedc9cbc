//! [`Simulation`]: the server's state — the pool, the open envs and batches, the limits —
//! and the domain operations the RPCs call. Everything CPU-bound here runs on the pool.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::{DrawReport, EnvError, RobotEnv, SavedState};

use crate::auth::Tenant;
use crate::config::ServerConfig;
use crate::domain::{
    Action, BatchObservations, BatchRequest, BatchStep, BatchStepped, Created, DrawsOf, EnvRequest,
    EnvStep, EnvStepOutcome, ForkRequest, JointLinks, ObsSplit, RenderOf, Rendered, ServerStatus,
};
use crate::error::{EntityKind, Result, ServerError};
use crate::metrics::{Metrics, OpenCounts};
use crate::pool::{self, Lane};
use crate::registry::{clear_done, Activity, EnvCapacity, Facts, Held, Registry, Reservation};

pub(crate) mod watch;

/// One open single environment.
pub(crate) struct OpenEnv {
    env: RobotEnv,
    /// Its step counters (see [`Activity::record_step`] for `was_done`).
    activity: Arc<Activity>,
    was_done: Vec<bool>,
}

/// One open batch, with its reusable step output.
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
    pool: StepPool,
    capacity: Arc<EnvCapacity>,
    /// Each tenant's quota, made on its first request (at most one per token-file tenant,
    /// or the anonymous one).
    quotas: Mutex<HashMap<Tenant, Arc<EnvCapacity>>>,
    envs: Registry<OpenEnv>,
    batches: Registry<OpenBatch>,
    metrics: Metrics,
}

/// Refuses a document or env past a structural limit, before anything is built.
fn check_structure(
    config: &ServerConfig,
    assembly: &gymfleet_assembly::Assembly,
    end_effectors: usize,
) -> Result<()> {
    let checks = [
        (
            "assembly.instances",
            assembly.instances.len(),
            config.max_instances,
            "--max-instances",
            "GYMFLEET_MAX_INSTANCES",
        ),
        (
            "assembly.joints",
            assembly.joints.len(),
            config.max_joints,
            "--max-joints",
            "GYMFLEET_MAX_JOINTS",
        ),
        (
            "degrees of freedom",
            assembly.total_dof(),
            config.max_dofs,
            "--max-dofs",
            "GYMFLEET_MAX_DOFS",
        ),
        (
            "end_effector_ids",
            end_effectors,
            config.max_end_effectors,
            "--max-end-effectors",
            "GYMFLEET_MAX_END_EFFECTORS",
        ),
    ];
    for (what, count, max, flag, var) in checks {
        if max != 0 && count > max {
            return Err(ServerError::TooComplex {
                what,
                count,
                max,
                flag,
                var,
            });
        }
    }
    Ok(())
}

/// Refuses envs whose steps would ask for more work than `--max-step-work`: `n_envs`
/// envs × `substeps` integration substeps × `dofs` degrees of freedom per step call.
fn check_step_work(config: &ServerConfig, n_envs: usize, substeps: u32, dofs: usize) -> Result<()> {
    let max = config.max_step_work;
    let substeps = usize::try_from(substeps).unwrap_or(usize::MAX);
    let work = n_envs.saturating_mul(substeps).saturating_mul(dofs.max(1));
    if max != 0 && work > max {
        return Err(ServerError::TooMuchWork {
            work,
            n_envs,
            substeps,
            dofs: dofs.max(1),
            max,
        });
    }
    Ok(())
}

/// Parses, checks against the structural limits (for `n_envs` copies), and builds one
/// env; names the bodies of its non-fixed joints.
fn build_env(
    request: EnvRequest,
    config: &ServerConfig,
    n_envs: usize,
) -> Result<(RobotEnv, JointLinks)> {
    let (document, _warnings) =
        convert_document(&request.document, request.format, &request.assets)?;
    let assembly = gymfleet_assembly::parse(&document).map_err(EnvError::Document)?;
    check_structure(config, &assembly, request.config.end_effector_ids.len())?;
    let substeps = request.config.substeps;
    // Options are checked first (a substep count out of range is a bad argument, not a
    // large request); building one env is cheap, its copies are not made yet.
    let env = RobotEnv::new(&assembly, request.config)?;
    check_step_work(config, n_envs, substeps, assembly.total_dof())?;
    let name = |i: usize| {
        assembly
            .instances
            .get(i)
            .map(|inst| inst.name.clone())
            .unwrap_or_default()
    };
    // One entry per joint with an observed DOF, as `convert::joints` lists them (an
    // unobserved loop-closing joint has none).
    let links = assembly
        .joints
        .iter()
        .filter(|j| j.observed_dof() > 0)
        .map(|j| (name(j.parent), name(j.child)))
        .collect();
    Ok((env, JointLinks(links)))
}

/// A document of `format` (`None`: detect) as assembly JSON text, its mesh files read from
/// `assets` (an archive; empty: none), with the conversion's warnings.
pub(crate) fn convert_document(
    document: &str,
    format: Option<gymfleet_import::Format>,
    assets: &[u8],
) -> Result<(String, Vec<String>)> {
    let format = match format {
        Some(f) => f,
        None => gymfleet_import::Format::detect(document)?,
    };
    let assets = if assets.is_empty() {
        None
    } else {
        Some(gymfleet_import::Assets::from_archive(assets)?)
    };
    Ok(gymfleet_import::to_json(document, format, assets.as_ref())?)
}

/// Refuses a batch whose step reply could exceed the message limit: observations and
/// same-step final observations (`n_envs × observation_dim` floats each, at most), plus
/// the per-env rewards and flags.
fn check_reply_size(config: &ServerConfig, n_envs: usize, observation_dim: usize) -> Result<()> {
    let max = config.max_message_bytes;
    let bytes = n_envs
        .saturating_mul(observation_dim)
        .saturating_mul(2 * 4)
        .saturating_add(n_envs.saturating_mul(4 + 4 + 2));
    if max != 0 && bytes > max {
        return Err(ServerError::ReplyTooLarge {
            bytes,
            max,
            n_envs,
            observation_dim,
        });
    }
    Ok(())
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
            metrics: Metrics::new(),
            envs: Registry::new(EntityKind::Env, "sim", config.clock.clone()),
            batches: Registry::new(EntityKind::Batch, "batch", config.clock.clone()),
            config,
            pool,
        }
    }

    /// The server's metrics.
    pub(crate) fn metrics(&self) -> &Metrics {
        &self.metrics
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

    /// `tenant`'s quota.
    fn quota(&self, tenant: &Tenant) -> Arc<EnvCapacity> {
        let mut quotas = self.quotas.lock().unwrap_or_else(PoisonError::into_inner);
        let quota = quotas.entry(tenant.clone()).or_insert_with(|| {
            EnvCapacity::for_tenant(self.config.tenant_max_envs, tenant.clone())
        });
        Arc::clone(quota)
    }

    /// Reserves `n` environments for `tenant`: in its quota and in the server's capacity.
    fn reserve(&self, tenant: &Tenant, n: usize, kind: EntityKind) -> Result<Reservation> {
        self.quota(tenant).reserve_within(&self.capacity, n, kind)
    }

    fn check_document(&self, document: &str) -> Result<()> {
        self.check_document_in("document_json", document)
    }

    /// [`Simulation::check_document`] for a document found in `field`.
    fn check_document_in(&self, field: &'static str, document: &str) -> Result<()> {
        let max = self.config.max_document_bytes;
        if max != 0 && document.len() > max {
            return Err(ServerError::DocumentTooLarge {
                field,
                bytes: document.len(),
                max,
            });
        }
        Ok(())
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

    /// A request naming a library model, with that model's document in its place.
    fn resolve_model(&self, mut request: EnvRequest) -> Result<EnvRequest> {
        let Some(name) = request.model.take() else {
            return Ok(request);
        };
        let library = self.config.models.as_deref();
        match library.and_then(|l| l.get(&name)) {
            Some(model) => {
                request.document = model.document.clone();
                request.format = Some(gymfleet_import::Format::Json);
                Ok(request)
            }
            None => {
                let known = match library {
                    Some(l) if !l.is_empty() => {
                        let names: Vec<String> =
                            l.iter().take(16).map(|(n, _)| format!("{n:?}")).collect();
                        let more = l.len().saturating_sub(16);
                        if more > 0 {
                            format!("{} and {more} more", names.join(", "))
                        } else {
                            names.join(", ")
                        }
                    }
                    _ => "none: start the server with --models DIR".to_string(),
                };
                Err(ServerError::UnknownModel { name, known })
            }
        }
    }

    /// The library's models: name, format, DOFs, action length.
    pub(crate) fn models(&self) -> Vec<(String, gymfleet_import::Format, usize, usize)> {
        self.config.models.as_deref().map_or_else(Vec::new, |l| {
            l.iter()
                .map(|(n, m)| (n.to_string(), m.format, m.dofs, m.action_dim))
                .collect()
        })
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
        let open = OpenEnv {
            env,
            activity: Arc::clone(&activity),
            was_done: Vec::new(),
        };
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
    ) -> Result<(Vec<f32>, ObsSplit)> {
        self.on_env(tenant, id, "Reset", move |open| {
            let spec = open.env.spec();
            let (dim, split) = (spec.observation_dim, ObsSplit::of(spec));
            let mut obs = vec![0.0; dim];
            open.env.reset_into(seed, &mut obs);
            open.was_done.fill(false);
            Ok((obs, split))
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
                let spec = open.env.spec();
                let (dim, split) = (spec.observation_dim, ObsSplit::of(spec));
                let mut observation = vec![0.0; dim];
                let flags = open.env.step_into(
                    step.action.action_type,
                    &step.action.values,
                    &mut observation,
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
                    split,
                    terms: open.env.term_values().to_vec(),
                })
            })
            .await;
        if outcome.is_ok() {
            self.metrics.env_steps(tenant, 1);
        }
        outcome
    }

    pub(crate) async fn observe_env(
        &self,
        tenant: &Tenant,
        id: &str,
    ) -> Result<(Vec<f32>, ObsSplit)> {
        self.on_env(tenant, id, "Observe", move |open| {
            let spec = open.env.spec();
            let (dim, split) = (spec.observation_dim, ObsSplit::of(spec));
            let mut obs = vec![0.0; dim];
            open.env.observe_into(&mut obs);
            Ok((obs, split))
        })
        .await
    }

    /// Takes a value out of its registry for good, waiting for calls in flight on it.
    async fn close<T: Send + 'static>(
        &self,
        registry: &Registry<T>,
        tenant: &Tenant,
        id: &str,
    ) -> Result<()> {
        let entry = registry.get(tenant, id)?;
        let mut slot = entry.lock(registry.kind()).await?;
        let value = slot.take().map(Held::release);
        registry.remove(id);
        drop(slot);
        // The capacity is free as of now; freeing thousands of worlds is CPU work too.
        self.pool.spawn(move || drop(value));
        tracing::info!(id, "closed");
        Ok(())
    }

    pub(crate) async fn close_env(&self, tenant: &Tenant, id: &str) -> Result<()> {
        self.close(&self.envs, tenant, id).await
    }

    pub(crate) async fn create_batch(
        &self,
        tenant: &Tenant,
        request: BatchRequest,
    ) -> Result<Created> {
        let max = self.config.max_batch_size;
        if max != 0 && request.n_envs > max {
            return Err(ServerError::BatchTooLarge {
                n_envs: request.n_envs,
                max,
            });
        }
        let mut request = request;
        request.env = self.resolve_model(request.env)?;
        self.check_document(&request.env.document)?;
        let reservation = self.reserve(tenant, request.n_envs, EntityKind::Batch)?;
        let pool = self.pool.clone();
        let config = self.config.clone();
        let (batch, links) = pool::run(&self.pool, Lane::Batch, "CreateBatch", move || {
            let BatchRequest {
                env,
                seed,
                n_envs,
                autoreset,
                seed_offset,
            } = request;
            let (template, links) = build_env(env, &config, n_envs)?;
            check_reply_size(&config, n_envs, template.spec().observation_dim)?;
            let mut batch = EnvBatch::for_pool(&template, n_envs, autoreset, &pool)?;
            // Env i is seeded with seed + seed_offset + i; the clones start with the
            // template's seed, so reseed them (a reset is exact and cheap).
            let mut scratch = Vec::new();
            batch.reset(&pool, Some(seed.unwrap_or(0)), seed_offset, &mut scratch)?;
            Ok((batch, links))
        })
        .await?;
        Ok(self.open_batch(tenant, batch, links, reservation, "created batch"))
    }

    /// Registers a built batch under a new id for `tenant` (its envs already reserved).
    fn open_batch(
        &self,
        tenant: &Tenant,
        batch: EnvBatch,
        links: JointLinks,
        reservation: Reservation,
        what: &'static str,
    ) -> Created {
        let spec = batch.spec().clone();
        let n_envs = batch.n_envs();
        let autoreset = batch.autoreset();
        let activity = Activity::new(Facts::of(&spec, n_envs));
        let open = OpenBatch {
            batch,
            out: BatchStepOutput::default(),
            steps: 0,
            activity: Arc::clone(&activity),
            was_done: Vec::new(),
        };
        let id = self
            .batches
            .insert_with(tenant, open, reservation, activity);
        tracing::info!(batch_id = %id, n_envs, "{what}");
        Created {
            id,
            spec,
            links,
            batch: Some((n_envs, autoreset)),
        }
    }

    pub(crate) async fn reset_batch(
        &self,
        tenant: &Tenant,
        id: &str,
        seed: Option<u64>,
        seed_offset: u64,
        env_indices: Vec<u32>,
    ) -> Result<BatchObservations> {
        let pool = self.pool.clone();
        let batch_id = id.to_string();
        self.on_batch(tenant, id, Lane::Batch, "ResetBatch", move |open| {
            let mut observations = Vec::new();
            // On the wire an empty list means every env.
            let only = (!env_indices.is_empty()).then_some(&env_indices[..]);
            open.batch
                .reset_envs(&pool, seed, seed_offset, only, &mut observations)?;
            clear_done(&mut open.was_done, only);
            Ok(batch_observation(batch_id, &open.batch, observations))
        })
        .await
    }

    pub(crate) async fn step_batch(
        &self,
        tenant: &Tenant,
        step: BatchStep,
    ) -> Result<BatchStepped> {
        let inject = self.injected_panic(&step.action);
        let pool = self.pool.clone();
        let batch_id = step.batch_id.clone();
        let stepped = self
            .on_batch(tenant, &batch_id, Lane::Batch, "StepBatch", move |open| {
                if inject {
                    panic!("injected panic (ServerConfig::panic_on_action)");
                }
                let Action {
                    action_type,
                    values,
                } = step.action;
                let started = Instant::now();
                open.batch
                    .step(&pool, action_type, &values, &mut open.out)?;
                open.steps += 1;
                open.activity.record_step(
                    started.elapsed(),
                    &open.out.terminated,
                    &open.out.truncated,
                    open.batch.autoreset() != Autoreset::Disabled,
                    &mut open.was_done,
                );
                Ok(BatchStepped {
                    batch_id: step.batch_id,
                    step_index: open.steps,
                    out: open.out.clone(),
                })
            })
            .await;
        if let Ok(stepped) = &stepped {
            self.metrics.env_steps(tenant, stepped.out.rewards.len());
        }
        stepped
    }

    pub(crate) async fn observe_batch(
        &self,
        tenant: &Tenant,
        id: &str,
    ) -> Result<BatchObservations> {
        let batch_id = id.to_string();
        self.on_batch(tenant, id, Lane::Batch, "ObserveBatch", move |open| {
            let mut observations = Vec::new();
            open.batch.observe(&mut observations);
            Ok(batch_observation(batch_id, &open.batch, observations))
        })
        .await
    }

    /// The randomisation factors of an env, or of env `index` of a batch.
    pub(crate) async fn randomization(
        &self,
        tenant: &Tenant,
        target: DrawsOf,
    ) -> Result<DrawReport> {
        match target {
            DrawsOf::Env(id) => {
                let env_id = id.clone();
                self.on_env(tenant, &env_id, "GetRandomization", move |open| {
                    open.env.draws().ok_or(ServerError::NotRandomized { id })
                })
                .await
            }
            DrawsOf::BatchEnv(id, index) => {
                let batch_id = id.clone();
                self.on_batch(
                    tenant,
                    &batch_id,
                    Lane::Env,
                    "GetRandomization",
                    move |open| {
                        let n_envs = open.batch.n_envs();
                        if index >= n_envs {
                            return Err(ServerError::EnvIndex { index, n_envs });
                        }
                        open.batch.draws(index).ok_or(ServerError::NotRandomized {
                            id: format!("{id}[{index}]"),
                        })
                    },
                )
                .await
            }
        }
    }

    /// An env's scene (shapes and poses), read on the pool.
    pub(crate) async fn scene(&self, tenant: &Tenant, id: &str) -> Result<gymfleet_env::Scene> {
        self.on_env(tenant, id, "GetScene", |open| Ok(open.env.scene()))
            .await
    }

    /// A picture of an env, or of env `index` of a batch, taken on the pool.
    pub(crate) async fn render(&self, tenant: &Tenant, request: RenderOf) -> Result<Rendered> {
        let RenderOf {
            of,
            camera,
            width,
            height,
        } = request;
        let draw = move |scene: gymfleet_env::Scene| -> Result<Rendered> {
            let frame = gymfleet_render::render(&scene, &camera, width, height)?;
            Ok(Rendered {
                png: frame.to_png(),
                width: frame.width,
                height: frame.height,
                description: gymfleet_render::describe(&scene, &frame, &camera),
                grid_mm: frame.grid_mm,
            })
        };
        match of {
            DrawsOf::Env(id) => {
                self.on_env(tenant, &id, "Render", move |open| draw(open.env.scene()))
                    .await
            }
            DrawsOf::BatchEnv(id, index) => {
                let batch_id = id.clone();
                self.on_batch(tenant, &batch_id, Lane::Env, "Render", move |open| {
                    let n_envs = open.batch.n_envs();
                    let scene = open
                        .batch
                        .scene(index)
                        .ok_or(ServerError::EnvIndex { index, n_envs })?;
                    draw(scene)
                })
                .await
            }
        }
    }

    /// Saves an env's state (re-seating it; see `gymfleet_env::SavedState`).
    pub(crate) async fn save_state(&self, tenant: &Tenant, id: &str) -> Result<Vec<u8>> {
        self.on_env(tenant, id, "SaveState", |open| {
            Ok(open.env.save()?.encode())
        })
        .await
    }

    /// Loads a state into an env of the same document and options; its observation.
    pub(crate) async fn load_state(
        &self,
        tenant: &Tenant,
        id: &str,
        state: Vec<u8>,
    ) -> Result<(Vec<f32>, ObsSplit)> {
        self.on_env(tenant, id, "LoadState", move |open| {
            let state = SavedState::decode(&state)?;
            open.env.load(&state)?;
            open.was_done.fill(false);
            let spec = open.env.spec();
            let (dim, split) = (spec.observation_dim, ObsSplit::of(spec));
            let mut obs = vec![0.0; dim];
            open.env.observe_into(&mut obs);
            Ok((obs, split))
        })
        .await
    }

    /// Saves the states of envs `env_indices` of a batch (empty: every env), refusing a
    /// reply over the message limit.
    pub(crate) async fn save_batch_state(
        &self,
        tenant: &Tenant,
        id: &str,
        env_indices: Vec<u32>,
    ) -> Result<Vec<Vec<u8>>> {
        let max = self.config.max_message_bytes;
        self.on_batch(tenant, id, Lane::Batch, "SaveBatchState", move |open| {
            let states: Vec<Vec<u8>> = open
                .batch
                .save_states(&env_indices)?
                .iter()
                .map(SavedState::encode)
                .collect();
            // Each state also costs a few bytes of framing on the wire.
            let bytes = states.iter().map(|s| s.len() + 8).sum::<usize>();
            if max != 0 && bytes > max {
                return Err(ServerError::StatesTooLarge {
                    bytes,
                    max,
                    count: states.len(),
                });
            }
            Ok(states)
        })
        .await
    }

    /// Loads states into envs `env_indices` of a batch (empty: every env); every env's
    /// observation.
    pub(crate) async fn load_batch_state(
        &self,
        tenant: &Tenant,
        id: &str,
        env_indices: Vec<u32>,
        states: Vec<Vec<u8>>,
    ) -> Result<BatchObservations> {
        let batch_id = id.to_string();
        self.on_batch(tenant, id, Lane::Batch, "LoadBatchState", move |open| {
            let decoded = states
                .iter()
                .enumerate()
                .map(|(k, bytes)| {
                    SavedState::decode(bytes).map_err(|err| ServerError::InvalidArgument {
                        field: "states",
                        reason: format!("states[{k}]: {err}"),
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            open.batch.load_states(&env_indices, &decoded)?;
            clear_done(&mut open.was_done, Some(&env_indices));
            let mut observations = Vec::new();
            open.batch.observe(&mut observations);
            Ok(batch_observation(batch_id, &open.batch, observations))
        })
        .await
    }

    /// A new batch of `n_envs` copies of a saved state, built through the same checks as
    /// `CreateBatch` (the state's document and options against every server limit).
    pub(crate) async fn fork(&self, tenant: &Tenant, request: ForkRequest) -> Result<Created> {
        let ForkRequest {
            state,
            n_envs,
            autoreset,
        } = request;
        let max = self.config.max_batch_size;
        if max != 0 && n_envs > max {
            return Err(ServerError::BatchTooLarge { n_envs, max });
        }
        // Decoding checksums the whole state: CPU work, so on the pool.
        let state = pool::run(&self.pool, Lane::Env, "Fork", move || {
            Ok(SavedState::decode(&state)?)
        })
        .await?;
        self.check_document_in("state.document", state.document())?;
        let reservation = self.reserve(tenant, n_envs, EntityKind::Batch)?;
        let pool = self.pool.clone();
        let config = self.config.clone();
        let (batch, links) = pool::run(&self.pool, Lane::Batch, "Fork", move || {
            let request = EnvRequest {
                document: state.document().to_string(),
                format: Some(gymfleet_import::Format::Json),
                model: None,
                assets: Vec::new(),
                config: state.config().clone(),
            };
            let (mut template, links) = build_env(request, &config, n_envs)?;
            check_reply_size(&config, n_envs, template.spec().observation_dim)?;
            template.load(&state)?;
            let batch = EnvBatch::copies_of(&template, n_envs, autoreset, &pool)?;
            Ok((batch, links))
        })
        .await?;
        Ok(self.open_batch(tenant, batch, links, reservation, "forked batch"))
    }

    /// A description as assembly JSON (checked by parsing it), its warnings and format.
    pub(crate) async fn convert(
        &self,
        document: String,
        format: Option<gymfleet_import::Format>,
        assets: Vec<u8>,
    ) -> Result<(String, Vec<String>, gymfleet_import::Format)> {
        self.check_document(&document)?;
        pool::run(&self.pool, Lane::Env, "ConvertDocument", move || {
            let format = match format {
                Some(f) => f,
                None => gymfleet_import::Format::detect(&document)?,
            };
            let (json, warnings) = convert_document(&document, Some(format), &assets)?;
            gymfleet_assembly::parse(&json).map_err(EnvError::Document)?;
            Ok((json, warnings, format))
        })
        .await
    }

    pub(crate) async fn close_batch(&self, tenant: &Tenant, id: &str) -> Result<()> {
        self.close(&self.batches, tenant, id).await
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

fn batch_observation(
    batch_id: String,
    batch: &EnvBatch,
    observations: Vec<f32>,
) -> BatchObservations {
    BatchObservations {
        batch_id,
        n_envs: batch.n_envs(),
        observation_dim: batch.spec().observation_dim,
        observations,
    }
}
