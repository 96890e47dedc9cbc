//! Resetting a fleet batch: every shard's share of the envs, at once, each reseeded as a
//! one-server batch would be (`FleetBatch::reset_envs_to`).

use crate::batch::BatchObservations;
use crate::error::Result;
use crate::fanout::join_all;

use super::{check_positions, recovery, FleetBatch};

impl FleetBatch {
    /// Resets every env; with `seed`, the env of original index `i` is reseeded with
    /// `seed + i` first, as in a one-server batch.
    pub async fn reset(&mut self, seed: Option<u64>) -> Result<BatchObservations> {
        self.reset_with_offset(seed, 0).await
    }

    /// [`FleetBatch::reset`] with the env of original index `i` reseeded with
    /// `seed + seed_offset + i`.
    pub async fn reset_with_offset(
        &mut self,
        seed: Option<u64>,
        seed_offset: u64,
    ) -> Result<BatchObservations> {
        self.reset_envs(seed, seed_offset, None).await
    }

    /// Resets only the envs at the positions `env_indices` (ascending, distinct, each
    /// below [`FleetBatch::n_envs`]; `None`: every env), reseeded as
    /// [`FleetBatch::reset_with_offset`] would. Returns every env's observation: the
    /// others' current ones (shards with none to reset are only observed).
    pub async fn reset_envs(
        &mut self,
        seed: Option<u64>,
        seed_offset: u64,
        env_indices: Option<&[u32]>,
    ) -> Result<BatchObservations> {
        self.reset_envs_to(seed, seed_offset, env_indices, "").await
    }

    /// [`FleetBatch::reset_envs`] from the document's keyframe named `keyframe` (one of
    /// `info().keyframes`), the reset's noise on top; `""`: the document's
    /// `initial_keyframe`, if any.
    pub async fn reset_envs_to(
        &mut self,
        seed: Option<u64>,
        seed_offset: u64,
        env_indices: Option<&[u32]>,
        keyframe: &str,
    ) -> Result<BatchObservations> {
        self.check_not_lost()?;
        if let Some(indices) = env_indices {
            check_positions(indices, self.n_envs())?;
        }
        self.log(|| recovery::Logged::Reset {
            seed,
            seed_offset,
            env_indices: env_indices.map(<[u32]>::to_vec),
            keyframe: keyframe.to_string(),
        });
        let mut first = 0;
        let resetting = self.shards.iter().map(|shard| {
            let batch = shard.batch.clone();
            let offset = seed_offset.wrapping_add(shard.envs.start as u64);
            let len = shard.envs.len();
            let local: Option<Vec<u32>> =
                env_indices.map(|indices| super::shard_local(indices, first, len));
            first += len;
            let keyframe = keyframe.to_string();
            async move {
                match local {
                    None => batch.reset_envs_to(seed, offset, &[], &keyframe).await,
                    Some(local) if local.is_empty() => batch.observe().await,
                    Some(local) => batch.reset_envs_to(seed, offset, &local, &keyframe).await,
                }
            }
        });
        let results = join_all(resetting.collect::<Vec<_>>()).await;
        let results = self.confirm_losses(results).await;
        let parts = self.settle(results);
        let parts = self.unlog_unless_lost(parts)?;
        self.combine_observations(parts)
    }
}
