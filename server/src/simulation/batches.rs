//! The batch operations: create (and fork's batch), reset, step, observe, close.

use std::sync::Arc;
use std::time::Instant;

use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch};

use crate::domain::{
    Action, BatchObservations, BatchRequest, BatchStep, BatchStepped, Created, JointLinks,
};
use crate::error::{EntityKind, Result, ServerError};
use crate::limit::Limit;
use crate::pool::{self, Lane};
use crate::registry::{clear_done, Activity, Facts, Reservation};
use crate::tenant::Tenant;

use super::documents::build_env;
use super::limits::check_reply_size;
use super::{OpenBatch, Simulation};

pub(super) fn batch_observation(
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

impl Simulation {
    pub(crate) async fn create_batch(
        &self,
        tenant: &Tenant,
        request: BatchRequest,
    ) -> Result<Created> {
        let max = self.config.limit(Limit::BatchSize);
        if Limit::exceeded(max, request.n_envs) {
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
    pub(super) fn open_batch(
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
        keyframe: String,
    ) -> Result<BatchObservations> {
        let pool = self.pool.clone();
        let batch_id = id.to_string();
        self.on_batch(tenant, id, Lane::Batch, "ResetBatch", move |open| {
            let mut observations = Vec::new();
            // On the wire an empty list means every env.
            let only = (!env_indices.is_empty()).then_some(&env_indices[..]);
            let keyframe = (!keyframe.is_empty()).then_some(keyframe.as_str());
            open.batch
                .reset_to(&pool, seed, seed_offset, only, keyframe, &mut observations)?;
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
                    mocap_poses,
                } = step.action;
                let started = Instant::now();
                let envs = step.env_indices;
                if envs.is_empty() {
                    open.batch.step_with_mocap(
                        &pool,
                        action_type,
                        &values,
                        &mocap_poses,
                        &mut open.out,
                    )?;
                } else {
                    open.batch.step_envs(
                        &pool,
                        action_type,
                        &envs,
                        &values,
                        &mocap_poses,
                        &mut open.out,
                    )?;
                }
                open.steps += 1;
                open.activity.record_envs_step(
                    started.elapsed(),
                    (!envs.is_empty()).then_some(&envs[..]),
                    &open.out.terminated,
                    &open.out.truncated,
                    open.batch.autoreset() != Autoreset::Disabled,
                    &mut open.was_done,
                );
                Ok(BatchStepped {
                    batch_id: step.batch_id,
                    step_index: open.steps,
                    // The reply takes the buffers (they are moved into the protobuf
                    // message, not copied); the next step allocates them again at
                    // their exact size (`EnvBatch::step` reserves it).
                    out: std::mem::take(&mut open.out),
                    env_indices: envs,
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

    pub(crate) async fn close_batch(&self, tenant: &Tenant, id: &str) -> Result<()> {
        self.close(&self.batches, tenant, id).await
    }
}
