//! Stepping some envs of a fleet batch ([`FleetBatch::step_envs`]): each shard steps its
//! listed envs (a shard with none is not called), and the replies merge into one with
//! the listed envs' rows in order. Logged for recovery like a whole step.

use super::recovery::Logged;
use super::{check_positions, FleetBatch};
use crate::batch::BatchStep;
use crate::error::{ClientError, Result};
use crate::fanout::join_all;
use crate::types::ActionType;

impl FleetBatch {
    /// Steps the envs at positions `env_indices` (ascending, distinct, not empty; the
    /// current env order) once, with `actions` holding one row per listed env in that
    /// order (as [`crate::Batch::step_envs`]); the other envs do not change. The result has
    /// one row per listed env ([`BatchStep::env_indices`]). Mistakes are refused before any
    /// server is called (one server's batch leaves that to its server).
    pub async fn step_envs(
        &mut self,
        action_type: ActionType,
        env_indices: &[u32],
        actions: &[f32],
    ) -> Result<BatchStep> {
        self.check_not_lost()?;
        if !self.single {
            self.check_subset(env_indices, actions)?;
        }
        self.log(|| Logged::StepEnvs {
            action_type,
            env_indices: env_indices.to_vec(),
            actions: actions.to_vec(),
        });
        let shares = self.shares(env_indices, actions);
        let stepping = shares
            .into_iter()
            .zip(&self.shards)
            .map(|((local, rows), shard)| {
                let batch = shard.batch.clone();
                async move { batch.step_listed(action_type, local, rows).await }
            });
        let results = join_all(stepping.collect::<Vec<_>>()).await;
        self.finish_step(results).await
    }

    /// Each shard's local indices among `env_indices` and their action rows. One shard
    /// takes the lists as given.
    pub(crate) fn shares(&self, env_indices: &[u32], actions: &[f32]) -> Vec<(Vec<u32>, Vec<f32>)> {
        if self.shards.len() == 1 {
            return vec![(env_indices.to_vec(), actions.to_vec())];
        }
        let dim = self.info.action_dim.max(1);
        let rows: Vec<&[f32]> = actions.chunks(dim).collect();
        self.split_by_shard(env_indices, &rows)
            .into_iter()
            .map(|(local, rows)| (local, rows.concat()))
            .collect()
    }

    /// The list and the actions' length and values, checked as the server checks them,
    /// envs named by their batch index.
    fn check_subset(&self, env_indices: &[u32], actions: &[f32]) -> Result<()> {
        if env_indices.is_empty() {
            return Err(ClientError::InvalidArgument {
                reason: crate::ErrorReason::InvalidField,
                message: "env_indices[0]: expected at least one env to step".into(),
            });
        }
        check_positions(env_indices, self.n_envs())?;
        let dim = self.info.action_dim;
        let expected = env_indices.len() * dim;
        let plural = |n: usize, one: &str, many: &str| if n == 1 { one } else { many }.to_string();
        if actions.len() != expected {
            return Err(ClientError::InvalidArgument {
                reason: crate::ErrorReason::InvalidAction,
                message: format!(
                    "actions: expected {expected} {} ({} {} × {dim} DOF), got {}",
                    plural(expected, "value", "values"),
                    env_indices.len(),
                    plural(env_indices.len(), "env", "envs"),
                    actions.len()
                ),
            });
        }
        match actions.iter().position(|a| !a.is_finite()) {
            Some(k) => Err(ClientError::InvalidArgument {
                reason: crate::ErrorReason::InvalidAction,
                message: format!(
                    "actions[{k}] (env {}, value {}): expected a finite number, got {}",
                    self.env_indices[env_indices[k / dim.max(1)] as usize],
                    k % dim.max(1),
                    actions[k]
                ),
            }),
            None => Ok(()),
        }
    }
}
