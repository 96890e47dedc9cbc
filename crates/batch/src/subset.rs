//! Stepping some envs of a batch ([`EnvBatch::step_envs`]): what an asynchronous trainer
//! sends (EnvPool's `send(actions, env_id)`) while the other envs wait for their actions.
//! Each env steps exactly as in a whole-batch step (its own episode, autoreset and random
//! stream), so the same actions per env give the same trajectory, bit for bit, whatever
//! the envs are stepped with.

use gymfleet_env::{ActionType, FREE_POSE_LEN};

use crate::batch::{lock, BatchStepOutput, EnvBatch, PREFETCH_ABOVE_ENVS_PER_THREAD};
use crate::chunk::ChunkOp;
use crate::error::{BatchError, Result};
use crate::pool::StepPool;

impl EnvBatch {
    /// Steps the envs `env_indices` (ascending, distinct, below `n_envs`; not empty) with
    /// `actions` (one row per listed env, in that order) and, if not empty, moves their
    /// mocap bodies to `mocap_poses` (one row of `mocap bodies × 7` per listed env). The
    /// other envs do not change. `out` gets one row per listed env, in that order; its
    /// `final_env_indices` and `termination_reasons` name batch indices. Everything is
    /// checked before any env changes; errors are [`EnvBatch::step`]'s, an env named by
    /// its batch index.
    pub fn step_envs(
        &mut self,
        pool: &StepPool,
        action_type: ActionType,
        env_indices: &[u32],
        actions: &[f32],
        mocap_poses: &[f32],
        out: &mut BatchStepOutput,
    ) -> Result<()> {
        if env_indices.is_empty() {
            return Err(BatchError::EnvIndices {
                position: 0,
                reason: "expected at least one env to step".into(),
            });
        }
        self.check_indices(env_indices)?;
        self.validate_rows(actions, Some(env_indices))?;
        self.check_mocap_rows(env_indices, mocap_poses)?;
        self.set_mocap_rows(env_indices, mocap_poses)?;
        let action_dim = self.spec().action_dim;
        let mut rows = env_indices
            .iter()
            .zip(actions.chunks_exact(action_dim))
            .peekable();
        for chunk in self.chunks.iter() {
            let mut chunk = lock(chunk);
            let first = chunk.first_env;
            chunk.step_marks.fill(false);
            while let Some((&env, action)) =
                rows.next_if(|(&e, _)| (e as usize) < first + chunk.len())
            {
                let i = env as usize - first;
                chunk.step_marks[i] = true;
                chunk.actions[i * action_dim..(i + 1) * action_dim].copy_from_slice(action);
            }
        }
        let prefetch = env_indices.len() > PREFETCH_ABOVE_ENVS_PER_THREAD * pool.threads();
        self.run(
            pool,
            ChunkOp::Step {
                action_type,
                prefetch,
                marked: true,
            },
        )?;
        self.gather_marked(env_indices.len(), out)
    }

    /// The marked envs' rows of the last step, in batch order, into `out`.
    fn gather_marked(&self, n: usize, out: &mut BatchStepOutput) -> Result<()> {
        let spec = self.spec();
        let (obs_dim, terms_dim) = (spec.observation_dim, spec.term_names.len());
        out.clear_for(n, obs_dim, terms_dim);
        let mut error = None;
        for chunk in self.chunks.iter() {
            let mut chunk = lock(chunk);
            for i in (0..chunk.len()).filter(|&i| chunk.step_marks[i]) {
                out.observations
                    .extend_from_slice(&chunk.observations[i * obs_dim..(i + 1) * obs_dim]);
                out.rewards.push(chunk.rewards[i]);
                out.terms
                    .extend_from_slice(&chunk.terms[i * terms_dim..(i + 1) * terms_dim]);
                out.terminated.push(chunk.terminated[i]);
                out.truncated.push(chunk.truncated[i]);
                if let Some(termination) = chunk.terminations[i] {
                    out.termination_reasons
                        .insert((chunk.first_env + i) as u32, termination);
                }
            }
            out.final_env_indices
                .extend_from_slice(&chunk.final_env_indices);
            out.final_observations
                .extend_from_slice(&chunk.final_observations);
            if error.is_none() {
                error = chunk.error.take();
            }
        }
        match error {
            Some((env, source)) => Err(BatchError::Env { env, source }),
            None => Ok(()),
        }
    }

    /// The listed envs' mocap rows checked (length, then each env's poses).
    fn check_mocap_rows(&self, env_indices: &[u32], poses: &[f32]) -> Result<()> {
        if poses.is_empty() {
            return Ok(());
        }
        let bodies = self.spec().mocap_bodies.len();
        let row = FREE_POSE_LEN * bodies;
        let expected = env_indices.len() * row;
        if poses.len() != expected {
            return Err(BatchError::MocapPosesLength {
                expected,
                got: poses.len(),
                n_envs: env_indices.len(),
                bodies,
            });
        }
        for (k, &env) in env_indices.iter().enumerate() {
            let env = env as usize;
            self.with_env(env, |e| e.check_mocap_poses(&poses[k * row..(k + 1) * row]))
                .expect("the index was checked")
                .map_err(|source| BatchError::Env { env, source })?;
        }
        Ok(())
    }

    /// Sets the listed envs' mocap rows (checked by [`Self::check_mocap_rows`]).
    fn set_mocap_rows(&self, env_indices: &[u32], poses: &[f32]) -> Result<()> {
        if poses.is_empty() {
            return Ok(());
        }
        let row = FREE_POSE_LEN * self.spec().mocap_bodies.len();
        for (k, &env) in env_indices.iter().enumerate() {
            let env = env as usize;
            self.with_env_mut(env, |e| e.set_mocap_poses(&poses[k * row..(k + 1) * row]))
                .expect("the index was checked")
                .map_err(|source| BatchError::Env { env, source })?;
        }
        Ok(())
    }
}
