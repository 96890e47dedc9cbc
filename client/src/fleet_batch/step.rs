//! Stepping every env of a fleet batch ([`FleetBatch::step`]): the actions checked once
//! here (several shards) or by the one server, each shard's rows sent to it, and the
//! replies settled and merged into one ([`FleetBatch::finish_step`], which the subset step
//! shares). Logged for recovery.

use std::borrow::Cow;

use gymfleet_proto::v1 as pb;

use super::merge::merge_steps;
use super::recovery;
use super::FleetBatch;
use crate::batch::BatchStep;
use crate::error::{ClientError, Result};
use crate::fanout::join_all;
use crate::types::ActionType;

impl FleetBatch {
    /// Steps every env once. `actions` holds `n_envs × action_dim` values, row-major, in
    /// the current env order. Wrong lengths and non-finite values are refused before any
    /// server is called, so no shard steps alone (one server's batch, `From<Batch>`,
    /// leaves that to its server, whose refusal it returns as it is).
    pub async fn step(&mut self, action_type: ActionType, actions: &[f32]) -> Result<BatchStep> {
        self.step_with_mocap(action_type, actions, &[]).await
    }

    /// [`FleetBatch::step`], moving every env's mocap bodies to `mocap_poses` by the end of
    /// the step (as [`Batch::step_with_mocap`]: `n_envs × mocap bodies × 7` values in the
    /// current env order; empty: the targets stay). Each shard gets its envs' rows.
    pub async fn step_with_mocap(
        &mut self,
        action_type: ActionType,
        actions: &[f32],
        mocap_poses: &[f32],
    ) -> Result<BatchStep> {
        self.step_values(
            action_type,
            Cow::Borrowed(actions),
            Cow::Borrowed(mocap_poses),
        )
        .await
    }

    /// [`FleetBatch::step_with_mocap`] with owned values: a batch on one server moves them
    /// into its request, without a copy (the Python binding's path).
    pub async fn step_owned(
        &mut self,
        action_type: ActionType,
        actions: Vec<f32>,
        mocap_poses: Vec<f32>,
    ) -> Result<BatchStep> {
        self.step_values(action_type, Cow::Owned(actions), Cow::Owned(mocap_poses))
            .await
    }

    async fn step_values(
        &mut self,
        action_type: ActionType,
        actions: Cow<'_, [f32]>,
        mocap_poses: Cow<'_, [f32]>,
    ) -> Result<BatchStep> {
        self.check_not_lost()?;
        if !self.single {
            self.check_actions(&actions)?;
            self.check_mocap_poses(&mocap_poses)?;
        }
        self.log(|| recovery::Logged::Step {
            action_type,
            actions: actions.to_vec(),
            mocap_poses: mocap_poses.to_vec(),
        });
        // One shard takes every value as given (the server checks them when this side did
        // not), moved when they are owned; several take their checked slices.
        let parts: Vec<(Vec<f32>, Vec<f32>)> = if self.shards.len() == 1 {
            vec![(actions.into_owned(), mocap_poses.into_owned())]
        } else {
            let dim = self.info.action_dim;
            let mut position = 0;
            self.shards
                .iter()
                .map(|shard| {
                    let n = shard.envs.len();
                    let part = (
                        actions[position * dim..(position + n) * dim].to_vec(),
                        self.mocap_rows(&mocap_poses, position..position + n),
                    );
                    position += n;
                    part
                })
                .collect()
        };
        let stepping = self
            .shards
            .iter()
            .zip(parts)
            .map(|(shard, (part, targets))| {
                let batch = shard.batch.clone();
                async move { batch.step_raw(action_type, part, targets).await }
            });
        let results = join_all(stepping.collect::<Vec<_>>()).await;
        self.finish_step(results).await
    }

    /// The shards' replies to one step (whole or of some envs) as one: losses confirmed,
    /// a lost shard's reply kept for recovery, the log kept only for a loss, merged in env
    /// order; then a checkpoint if one is due.
    pub(crate) async fn finish_step(
        &mut self,
        results: Vec<Result<pb::BatchStepResult>>,
    ) -> Result<BatchStep> {
        let results = self.confirm_losses(results).await;
        let replies = self.settle_keeping(results, |shard, reply| {
            shard.interrupted = Some(reply);
        });
        let replies = self.unlog_unless_lost(replies)?;
        let lens: Vec<usize> = self.shards.iter().map(|s| s.envs.len()).collect();
        let step = BatchStep::new(merge_steps(replies, &lens), &self.info)?;
        self.checkpoint_if_due().await;
        Ok(step)
    }

    /// The mocap targets of the envs at `positions` (empty when none are given).
    pub(crate) fn mocap_rows(
        &self,
        mocap_poses: &[f32],
        positions: std::ops::Range<usize>,
    ) -> Vec<f32> {
        if mocap_poses.is_empty() {
            return Vec::new();
        }
        let row = 7 * self.info.mocap_bodies.len();
        mocap_poses[positions.start * row..positions.end * row].to_vec()
    }

    /// Refuses mocap targets of the wrong length before any server is called (each server
    /// checks their values, all before stepping any env).
    fn check_mocap_poses(&self, mocap_poses: &[f32]) -> Result<()> {
        let expected = self.info.n_envs * 7 * self.info.mocap_bodies.len();
        if mocap_poses.is_empty() || mocap_poses.len() == expected {
            return Ok(());
        }
        Err(ClientError::InvalidArgument {
            reason: crate::ErrorReason::InvalidAction,
            message: format!(
                "mocap_poses: expected {expected} values ({} envs × {} mocap bodies × 7: x, y, z, qw, qx, qy, qz), or none to keep the targets, got {}",
                self.info.n_envs,
                self.info.mocap_bodies.len(),
                mocap_poses.len()
            ),
        })
    }

    /// Refuses wrong lengths and non-finite values before any server is called, so that
    /// no shard steps alone. The messages are the server's, with original env indices.
    fn check_actions(&self, actions: &[f32]) -> Result<()> {
        let dim = self.info.action_dim;
        let n_envs = self.info.n_envs;
        let expected = n_envs * dim;
        if actions.len() != expected {
            let plural =
                |n: usize, one: &str, many: &str| if n == 1 { one } else { many }.to_string();
            return Err(ClientError::InvalidArgument {
                reason: crate::ErrorReason::InvalidAction,
                message: format!(
                    "actions: expected {expected} {} ({n_envs} {} × {dim} DOF), got {}",
                    plural(expected, "value", "values"),
                    plural(n_envs, "env", "envs"),
                    actions.len()
                ),
            });
        }
        match actions.iter().position(|a| !a.is_finite()) {
            Some(k) => Err(ClientError::InvalidArgument {
                reason: crate::ErrorReason::InvalidAction,
                message: format!(
                    "actions[{k}] (env {}, value {}): expected a finite number, got {}",
                    self.env_indices[k / dim.max(1)],
                    k % dim.max(1),
                    actions[k]
                ),
            }),
            None => Ok(()),
        }
    }
}
