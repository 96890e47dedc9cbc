//! [`FleetBatch`]: one logical batch sharded across the servers of a [`crate::Fleet`],
//! stepped as one, with lost servers reported per env (`losses.rs`) and dropped on request
//! or rebuilt from a checkpoint (`recovery.rs`); a whole step (`step.rs`) or one of some
//! envs (`subset.rs`) has the shards' replies merged into one (`merge.rs`).

mod losses;
mod merge;
pub(crate) mod recovery;
mod reset;
mod step;
mod subset;

use gymfleet_proto::v1 as pb;
use std::ops::Range;

use crate::batch::{Batch, BatchObservations, BatchStep};
use crate::error::{ClientError, Result};
use crate::fanout::{join_all, on_server};
use crate::types::BatchInfo;

/// Where one shard of a fleet batch lives.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShardPlacement {
    /// The server's address.
    pub server: String,
    /// The shard's batch id on that server.
    pub batch_id: String,
    /// The envs it holds, as original indices of the fleet batch (a contiguous range).
    pub envs: Range<usize>,
    /// Why the server was lost, if it was (until [`FleetBatch::drop_lost`] drops it).
    pub lost: Option<String>,
}

/// One shard: a batch on one server holding a contiguous range of the fleet's envs.
#[derive(Debug)]
pub(crate) struct Shard {
    pub(crate) batch: Batch,
    pub(crate) envs: Range<usize>,
    pub(crate) lost: Option<String>,
    /// This shard's reply to the step in which another shard's server was lost.
    pub(crate) interrupted: Option<pb::BatchStepResult>,
}

impl Shard {
    pub(crate) fn new(batch: Batch, envs: Range<usize>) -> Self {
        Shard {
            batch,
            envs,
            lost: None,
            interrupted: None,
        }
    }

    fn lost_error(&self, reason: String) -> ClientError {
        ClientError::ServerLost {
            server: self.batch.server().to_string(),
            envs: vec![self.envs.clone()],
            reason,
        }
    }
}

/// One batch of `n_envs` identical envs, sharded across the servers of a
/// [`crate::Fleet`] and driven as one: [`FleetBatch::step`] splits the actions by shard,
/// steps every shard concurrently and returns a single [`BatchStep`] with the envs in
/// their original order, exactly as a one-server [`Batch`] would (final observations
/// and termination reasons included). With the same seeds and actions, every env's
/// results are bitwise those of a one-server batch.
///
/// Each shard holds a contiguous range of the envs ([`FleetBatch::placement`]). If a
/// server fails, the call fails with [`ClientError::ServerLost`] naming it and its envs,
/// and so does every later call until [`FleetBatch::drop_lost`]: after it, the batch is
/// the survivors, in their original order, and [`FleetBatch::env_indices`] maps each
/// position to its original index. The survivors did take the step that found the loss;
/// [`FleetBatch::take_interrupted_step`] gives its result, so no step is missed.
///
/// Instead of going on without them, a batch that checkpoints
/// ([`FleetBatch::checkpoint_every`]) can rebuild the lost envs on the survivors or a
/// replacement server ([`FleetBatch::recover`], `fleet_batch/recovery.rs`) and go on with all of
/// them, bitwise as if nothing had been lost.
///
/// A call that fails on some shard for another reason (e.g. INTERNAL) returns
/// [`ClientError::OnServer`]; the other shards have done the call, so the shards may be
/// out of step until the next reset.
///
/// A one-server [`Batch`] becomes a fleet batch of one shard with `FleetBatch::from`
/// (the Python package drives every batch so): its calls go straight to that server, and
/// its errors are the server's own, unwrapped (no shard can step alone, so nothing is
/// checked on this side first, and no error counts as a lost server).
#[derive(Debug)]
pub struct FleetBatch {
    pub(crate) shards: Vec<Shard>,
    pub(crate) info: BatchInfo,
    env_indices: Vec<usize>,
    interrupted: Option<BatchStep>,
    /// With [`FleetBatch::checkpoint_every`]: the last checkpoint and what was done since
    /// (`fleet_batch/recovery.rs`).
    pub(crate) checkpoints: Option<recovery::Checkpoints>,
    /// Made from one server's batch (`From<Batch>`): errors pass through as given.
    pub(crate) single: bool,
}

impl From<Batch> for FleetBatch {
    fn from(batch: Batch) -> Self {
        let n_envs = batch.info().n_envs;
        let mut one = FleetBatch::new(vec![Shard::new(batch, 0..n_envs)])
            .unwrap_or_else(|_| unreachable!("one shard agrees with itself"));
        one.single = true;
        one
    }
}

impl FleetBatch {
    /// A fleet batch of shards created with the same options, in env order. Fails (giving
    /// the shards back for closing) if the servers disagree on the env's shape.
    pub(crate) fn new(shards: Vec<Shard>) -> std::result::Result<Self, (ClientError, Vec<Batch>)> {
        let first = shards[0].batch.info();
        let shape = |i: &BatchInfo| (i.action_dim, i.observation_dim, i.num_joints);
        if let Some(odd) = shards
            .iter()
            .find(|s| shape(s.batch.info()) != shape(first))
        {
            let err = ClientError::protocol(format!(
                "fleet batch: server {} reports (action_dim, observation_dim, num_joints) \
                 {:?}, server {} {:?}",
                odd.batch.server(),
                shape(odd.batch.info()),
                shards[0].batch.server(),
                shape(first)
            ));
            return Err((err, shards.into_iter().map(|s| s.batch).collect()));
        }
        let info = first.clone();
        let mut batch = FleetBatch {
            shards,
            info,
            env_indices: Vec::new(),
            interrupted: None,
            checkpoints: None,
            single: false,
        };
        batch.refresh();
        Ok(batch)
    }

    /// Recomputes the combined info and the position → index map from the shards.
    pub(crate) fn refresh(&mut self) {
        self.env_indices = self.shards.iter().flat_map(|s| s.envs.clone()).collect();
        self.info.n_envs = self.env_indices.len();
        let ids: Vec<&str> = self.shards.iter().map(|s| s.batch.id()).collect();
        self.info.batch_id = ids.join("+");
    }

    /// The batch as one: `n_envs` is the current number of envs (survivors only, after
    /// [`FleetBatch::drop_lost`]); `batch_id` is the shards' ids joined with `+`.
    pub fn info(&self) -> &BatchInfo {
        &self.info
    }

    /// The current number of envs.
    pub fn n_envs(&self) -> usize {
        self.info.n_envs
    }

    /// The original index of the env at each position: `0..n` until servers are
    /// dropped, then the survivors' indices, ascending.
    pub fn env_indices(&self) -> &[usize] {
        &self.env_indices
    }

    /// Which server holds which envs, in env order.
    pub fn placement(&self) -> Vec<ShardPlacement> {
        self.shards
            .iter()
            .map(|s| ShardPlacement {
                server: s.batch.server().to_string(),
                batch_id: s.batch.id().to_string(),
                envs: s.envs.clone(),
                lost: s.lost.clone(),
            })
            .collect()
    }

    /// One server's batch as it is (`From<Batch>`, no checkpoints): its calls need no
    /// `&mut self` of the fleet batch's, so several can be in flight on it at once.
    pub fn lone(&self) -> Option<&Batch> {
        (self.single && self.checkpoints.is_none() && self.shards.len() == 1)
            .then(|| &self.shards[0].batch)
    }

    /// The shard batches, one per server, in env order.
    pub fn shards(&self) -> impl Iterator<Item = &Batch> {
        self.shards.iter().map(|s| &s.batch)
    }

    /// Each shard's local indices among global `env_indices` (empty: every env of every
    /// shard), and for each shard its share of `items` (one per index, in index order).
    pub(crate) fn split_by_shard<T: Clone>(
        &self,
        env_indices: &[u32],
        items: &[T],
    ) -> Vec<(Vec<u32>, Vec<T>)> {
        let mut first = 0;
        let mut taken = 0;
        self.shards
            .iter()
            .map(|shard| {
                let len = shard.envs.len();
                let local: Vec<u32> = if env_indices.is_empty() {
                    (0..len as u32).collect()
                } else {
                    shard_local(env_indices, first, len)
                };
                first += len;
                let share = items
                    .get(taken..taken + local.len())
                    .unwrap_or_default()
                    .to_vec();
                taken += local.len();
                (local, share)
            })
            .collect()
    }

    /// Saves the states of the envs at positions `env_indices` (ascending, distinct; empty:
    /// every env), in that order, each from the shard that holds it
    /// ([`Batch::save_states`]).
    pub async fn save_states(&mut self, env_indices: &[u32]) -> Result<Vec<crate::EnvState>> {
        self.check_not_lost()?;
        check_positions(env_indices, self.n_envs())?;
        let saving = self
            .split_by_shard::<()>(env_indices, &[])
            .into_iter()
            .zip(&self.shards)
            .map(|((local, _), shard)| {
                let batch = shard.batch.clone();
                async move {
                    if local.is_empty() {
                        Ok(Vec::new())
                    } else {
                        batch.save_states(&local).await
                    }
                }
            });
        let results = join_all(saving.collect::<Vec<_>>()).await;
        let results = self.confirm_losses(results).await;
        Ok(self.settle(results)?.into_iter().flatten().collect())
    }

    /// Replaces heightfield `name`'s heights in the envs at positions `env_indices`
    /// (ascending, distinct; empty: every env), each on the shard that holds it
    /// ([`Batch::set_heightfield`]).
    pub async fn set_heightfield(
        &mut self,
        env_indices: &[u32],
        name: &str,
        heights: &[f32],
    ) -> Result<()> {
        self.check_not_lost()?;
        check_positions(env_indices, self.n_envs())?;
        let all: Vec<u32> = (0..self.n_envs() as u32).collect();
        let chosen = if env_indices.is_empty() {
            &all[..]
        } else {
            env_indices
        };
        let setting = self
            .split_by_shard::<()>(chosen, &[])
            .into_iter()
            .zip(&self.shards)
            .map(|((local, _), shard)| {
                let batch = shard.batch.clone();
                let (name, heights) = (name.to_string(), heights.to_vec());
                async move {
                    if local.is_empty() {
                        Ok(())
                    } else {
                        batch.set_heightfield(&local, &name, &heights).await
                    }
                }
            });
        let results = join_all(setting.collect::<Vec<_>>()).await;
        let results = self.confirm_losses(results).await;
        self.settle(results)?;
        Ok(())
    }

    /// Loads `states[k]` into the env at position `env_indices[k]` (empty: every env, one
    /// state each), each on the shard that holds it ([`Batch::load_states`]); returns every
    /// env's observation. Each shard checks all of its states before loading any.
    pub async fn load_states(
        &mut self,
        env_indices: &[u32],
        states: &[crate::EnvState],
    ) -> Result<BatchObservations> {
        self.check_not_lost()?;
        check_positions(env_indices, self.n_envs())?;
        let expected = if env_indices.is_empty() {
            self.n_envs()
        } else {
            env_indices.len()
        };
        if states.len() != expected {
            return Err(ClientError::InvalidArgument {
                reason: crate::ErrorReason::InvalidState,
                message: format!(
                    "states: expected one state per env index ({expected}), got {}",
                    states.len()
                ),
            });
        }
        let loading = self
            .split_by_shard(env_indices, states)
            .into_iter()
            .zip(&self.shards)
            .map(|((local, share), shard)| {
                let batch = shard.batch.clone();
                async move {
                    if local.is_empty() {
                        batch.observe().await
                    } else {
                        batch.load_states(&local, &share).await
                    }
                }
            });
        let results = join_all(loading.collect::<Vec<_>>()).await;
        let results = self.confirm_losses(results).await;
        let parts = self.settle(results)?;
        let observations = self.combine_observations(parts)?;
        // What was loaded is not in the log: start a new checkpoint from here.
        self.checkpoint_now_if_on().await?;
        Ok(observations)
    }

    /// The current observation of every env, without stepping.
    pub async fn observe(&mut self) -> Result<BatchObservations> {
        self.check_not_lost()?;
        let observing = self.shards.iter().map(|shard| {
            let batch = shard.batch.clone();
            async move { batch.observe().await }
        });
        let results = join_all(observing.collect::<Vec<_>>()).await;
        let results = self.confirm_losses(results).await;
        let parts = self.settle(results)?;
        self.combine_observations(parts)
    }

    pub(crate) fn combine_observations(
        &self,
        mut parts: Vec<BatchObservations>,
    ) -> Result<BatchObservations> {
        // One shard's observations are the batch's: no copy.
        if parts.len() == 1 {
            return Ok(parts.remove(0));
        }
        let mut observations = Vec::with_capacity(self.info.n_envs * self.info.observation_dim);
        for part in parts {
            observations.extend_from_slice(part.observations());
        }
        let reply = pb::BatchObservation {
            batch_id: self.info.batch_id.clone(),
            n_envs: u32::try_from(self.info.n_envs).unwrap_or(u32::MAX),
            observation_dim: u32::try_from(self.info.observation_dim).unwrap_or(u32::MAX),
            observations,
        };
        BatchObservations::new(reply, &self.info)
    }

    /// The domain-randomisation factors of the env at position `env` (see
    /// [`Batch::randomization`]), asked of the shard that holds it.
    pub async fn randomization(&self, env: usize) -> Result<crate::RandomizationDraws> {
        let (batch, local) = self.shard_of(env)?;
        batch.randomization(local).await
    }

    /// The shard batch holding global env `env`, and the env's index in it.
    fn shard_of(&self, env: usize) -> Result<(&Batch, usize)> {
        let mut first = 0;
        for shard in &self.shards {
            let len = shard.envs.len();
            if env < first + len {
                return Ok((&shard.batch, env - first));
            }
            first += len;
        }
        Err(ClientError::InvalidArgument {
            reason: crate::ErrorReason::InvalidField,
            message: format!("env_index: {env} is out of range: the batch has {first} envs"),
        })
    }

    /// A picture of env `env` (global index), from the shard that holds it
    /// ([`crate::Batch::render`]).
    pub async fn render(
        &self,
        env: usize,
        camera: &crate::Camera,
        width: u32,
        height: u32,
    ) -> Result<crate::Image> {
        let (batch, local) = self.shard_of(env)?;
        batch.render(local, camera, width, height).await
    }

    /// Closes every shard that is not lost, concurrently. Fails with the first failure,
    /// naming its server, after trying them all.
    pub async fn close(&self) -> Result<()> {
        let closing = self
            .shards
            .iter()
            .filter(|s| s.lost.is_none())
            .map(|shard| {
                let batch = shard.batch.clone();
                let single = self.single;
                async move {
                    let closed = batch.close().await;
                    if single {
                        return closed;
                    }
                    closed.map_err(|e| on_server(batch.client(), e))
                }
            });
        join_all(closing.collect::<Vec<_>>())
            .await
            .into_iter()
            .collect::<Result<Vec<()>>>()
            .map(drop)
    }
}

/// Checks a partial reset's positions as a server would, so no shard resets anything
/// when the list is bad.
pub(crate) fn check_positions(indices: &[u32], n_envs: usize) -> Result<()> {
    let mut previous: Option<u32> = None;
    for (position, &i) in indices.iter().enumerate() {
        let reason = match previous {
            _ if i as usize >= n_envs => {
                format!("env {i} is out of range: the batch has {n_envs} envs")
            }
            Some(p) if i <= p => format!("expected ascending, distinct indices, got {i} after {p}"),
            _ => {
                previous = Some(i);
                continue;
            }
        };
        return Err(ClientError::InvalidArgument {
            reason: crate::ErrorReason::InvalidField,
            message: format!("env_indices[{position}]: {reason}"),
        });
    }
    Ok(())
}

/// The fleet-wide env indices among `indices` that fall in the shard of `len` envs from
/// `first`, as the shard's own indices.
fn shard_local(indices: &[u32], first: usize, len: usize) -> Vec<u32> {
    indices
        .iter()
        .map(|&i| i as usize)
        .filter(|i| (first..first + len).contains(i))
        .map(|i| (i - first) as u32)
        .collect()
}
