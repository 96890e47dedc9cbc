//! The batch tools of the user guide: `batch_create_envs`, `batch_step` (actions as one
//! array per env, results grouped by env), `batch_reset`, and `batch_close`.

use rmcp::handler::server::wrapper::Parameters;
use rmcp::{tool, tool_router};

use crate::actions;
use crate::errors::Result;
use crate::output::{
    BatchClosed, BatchCreated, BatchObservationsOut, BatchStepOut, EnvStepOut, ObservationOut,
};
use crate::params::{BatchRefParams, BatchResetParams, BatchStepParams, CreateBatchParams};
use crate::reply::Json;
use crate::server::GymTools;

#[tool_router(router = batch_router, vis = "pub(crate)")]
impl GymTools {
    /// Creates a batch of identical environments.
    #[tool(
        description = "Create n_envs identical physics environments from one assembly \
        document, stepped together in parallel. Returns batch_id (use it in batch_step, \
        batch_reset, batch_close), n_envs, action_dim, observation_dim, num_joints, and the \
        shared configuration."
    )]
    async fn batch_create_envs(
        &self,
        Parameters(p): Parameters<CreateBatchParams>,
    ) -> Result<Json<BatchCreated>> {
        let n_envs = p.n_envs;
        let options = p.into_options()?;
        let placed = self.fleet.create_batch(options).await?;
        let server = self.fleet.addr(placed.server);
        tracing::info!(batch_id = %placed.id, n_envs, server, "created batch");
        Ok(Json(BatchCreated::new(
            placed.id.clone(),
            placed.handle.info(),
        )))
    }

    /// Steps every env of a batch.
    #[tool(
        description = "Step every environment of a batch once. actions holds one array per \
        env (n_envs arrays, env 0 first), each with exactly action_dim numbers: torque in N·m \
        or N, position targets in degrees or mm, velocity targets in degrees/s or mm/s. \
        Returns results grouped by env: {env_index, observation, reward, done, terminated, \
        truncated} for each."
    )]
    async fn batch_step(
        &self,
        Parameters(p): Parameters<BatchStepParams>,
    ) -> Result<Json<BatchStepOut>> {
        let placed = self.fleet.batch(&p.batch_id)?;
        let info = placed.handle.info();
        let flat = actions::batch_actions(&placed.id, info.n_envs, info.action_dim, &p.actions)?;
        let step = placed
            .handle
            .step(p.action_type.into(), &flat)
            .await
            .map_err(|err| self.fleet.batch_failed(&placed, &err))?;
        let layout = &info.observation_layout;
        let k = info.term_names.len();
        let results = (0..step.n_envs())
            .map(|env| {
                let terminated = step.terminated()[env];
                let truncated = step.truncated()[env];
                EnvStepOut {
                    env_index: env,
                    observation: ObservationOut::from_row(step.obs(env), layout),
                    reward: crate::output::clean(step.rewards()[env]),
                    done: terminated || truncated,
                    terminated,
                    truncated,
                    termination_reason: step.termination_reason(env).map(str::to_string),
                    final_observation: step
                        .final_observation(env)
                        .map(|row| ObservationOut::from_row(row, layout)),
                    terms: crate::output::terms(
                        &info.term_names,
                        step.terms().get(env * k..(env + 1) * k).unwrap_or_default(),
                    ),
                }
            })
            .collect();
        Ok(Json(BatchStepOut {
            batch_id: placed.id,
            results,
        }))
    }

    /// Resets every env of a batch.
    #[tool(
        description = "Reset every environment of a batch to its initial state and return \
        one observation per env: {batch_id, observations: [{joint_positions, \
        joint_velocities, end_effector_poses}, ...]}."
    )]
    async fn batch_reset(
        &self,
        Parameters(p): Parameters<BatchResetParams>,
    ) -> Result<Json<BatchObservationsOut>> {
        let placed = self.fleet.batch(&p.batch_id)?;
        let observations = placed
            .handle
            .reset_envs_to(p.seed, 0, &[], p.keyframe.as_deref().unwrap_or(""))
            .await
            .map_err(|err| self.fleet.batch_failed(&placed, &err))?;
        let info = placed.handle.info();
        let layout = &info.observation_layout;
        let observations = (0..observations.n_envs())
            .map(|env| ObservationOut::from_row(observations.obs(env), layout))
            .collect();
        Ok(Json(BatchObservationsOut {
            batch_id: placed.id,
            observations,
        }))
    }

    /// Closes a batch.
    #[tool(
        description = "Close a batch and free all its environments. Its batch_id is invalid \
        afterwards."
    )]
    async fn batch_close(
        &self,
        Parameters(p): Parameters<BatchRefParams>,
    ) -> Result<Json<BatchClosed>> {
        let placed = self.fleet.batch(&p.batch_id)?;
        placed
            .handle
            .close()
            .await
            .map_err(|err| self.fleet.batch_failed(&placed, &err))?;
        self.fleet.forget_batch(&placed.id);
        tracing::info!(batch_id = %placed.id, "closed batch");
        Ok(Json(BatchClosed {
            batch_id: placed.id,
            closed: true,
        }))
    }
}
