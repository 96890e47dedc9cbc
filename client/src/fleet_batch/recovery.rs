//! Fleet recovery (docs/design.md §6.4): a [`FleetBatch`] that checkpoints every K steps keeps
//! every env's saved state and what it was asked to do since (steps and resets); when a
//! server is lost, [`FleetBatch::recover`] rebuilds the lost shards' envs on a survivor (or
//! a replacement server) from the checkpoint, replays what was done since, and the batch
//! goes on bitwise as if nothing had been lost.
//!
//! Costs (BENCHMARKS.md J2): a checkpoint is one `SaveBatchState` per shard (about 1.3 kB
//! per arm2 env, the document included); the log holds K steps' actions
//! (`K × n_envs × action_dim` floats). Saving re-seats each env on its server (see
//! `gymfleet_env::SavedState`): envs touching something at that moment have their contact
//! solved afresh at the next step, so a run with checkpoints matches a run with the same
//! checkpoints, bit for bit, and one without them only where nothing touches.

use super::merge::merge_steps;
use super::FleetBatch;
use crate::batch::{Batch, BatchStep};
use crate::client::Client;
use crate::error::{ClientError, Result};
use crate::state::EnvState;
use crate::types::ActionType;

/// One call the checkpoint's states have not seen.
#[derive(Debug, Clone)]
pub(crate) enum Logged {
    /// A step, with every env's action and mocap targets (in position order; no targets:
    /// empty).
    Step {
        action_type: ActionType,
        actions: Vec<f32>,
        mocap_poses: Vec<f32>,
    },
    /// A step of some envs (positions, ascending), with their actions in that order.
    StepEnvs {
        action_type: ActionType,
        env_indices: Vec<u32>,
        actions: Vec<f32>,
    },
    /// A reset of some (or every) env.
    Reset {
        seed: Option<u64>,
        seed_offset: u64,
        env_indices: Option<Vec<u32>>,
        keyframe: String,
    },
}

/// The last checkpoint and the log since.
#[derive(Debug)]
pub(crate) struct Checkpoints {
    every: u64,
    /// Every env's state at the checkpoint, in position order.
    states: Vec<EnvState>,
    log: Vec<Logged>,
    /// Steps logged since the checkpoint.
    steps: u64,
}

/// Where a fleet batch's recovery stands ([`FleetBatch::checkpoint_status`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CheckpointStatus {
    /// Steps between checkpoints.
    pub every: u64,
    /// Steps taken since the last checkpoint (what a recovery would replay).
    pub steps_since: u64,
    /// The last checkpoint's size: every env's state, in bytes.
    pub bytes: usize,
}

impl FleetBatch {
    /// Checkpoints the batch every `steps` steps (0: never again, and forgets the last
    /// checkpoint), starting with one now, so that [`FleetBatch::recover`] can rebuild the
    /// envs of a lost server.
    pub async fn checkpoint_every(&mut self, steps: u64) -> Result<()> {
        if steps == 0 {
            self.checkpoints = None;
            return Ok(());
        }
        let states = self.save_states(&[]).await?;
        self.checkpoints = Some(Checkpoints {
            every: steps,
            states,
            log: Vec::new(),
            steps: 0,
        });
        Ok(())
    }

    /// The checkpoints' period, the steps since the last one and its size; `None` when
    /// the batch does not checkpoint.
    pub fn checkpoint_status(&self) -> Option<CheckpointStatus> {
        self.checkpoints.as_ref().map(|c| CheckpointStatus {
            every: c.every,
            steps_since: c.steps,
            bytes: c.states.iter().map(EnvState::len).sum(),
        })
    }

    /// Records a call about to be made, when checkpointing (`entry` is only built then:
    /// a step's actions are not copied otherwise).
    pub(crate) fn log(&mut self, entry: impl FnOnce() -> Logged) {
        if let Some(c) = &mut self.checkpoints {
            c.log.push(entry());
        }
    }

    /// After a logged call: a call that failed without losing a server did not happen on
    /// the servers (or not on all: the batch is then out of step, as documented on
    /// [`FleetBatch`]), so it leaves the log. A loss keeps it: the survivors made the call.
    pub(crate) fn unlog_unless_lost<T>(&mut self, result: Result<T>) -> Result<T> {
        if let (Err(err), Some(c)) = (&result, &mut self.checkpoints) {
            if !matches!(err, ClientError::ServerLost { .. }) {
                c.log.pop();
            }
        }
        result
    }

    /// After a step: counts it, and takes a checkpoint when one is due. A checkpoint that
    /// fails keeps the previous one and its log (a lost server is then reported by the
    /// next call, as usual).
    pub(crate) async fn checkpoint_if_due(&mut self) {
        let due = match &mut self.checkpoints {
            Some(c) => {
                c.steps += 1;
                c.steps >= c.every
            }
            None => false,
        };
        if due {
            let _ = self.take_checkpoint().await;
        }
    }

    /// A checkpoint now, if the batch checkpoints.
    pub(crate) async fn checkpoint_now_if_on(&mut self) -> Result<()> {
        if self.checkpoints.is_some() {
            self.take_checkpoint().await?;
        }
        Ok(())
    }

    async fn take_checkpoint(&mut self) -> Result<()> {
        // Saving is not itself logged: take the log out while the states are saved.
        let Some(mut c) = self.checkpoints.take() else {
            return Ok(());
        };
        let saved = self.save_states(&[]).await;
        if let Ok(states) = &saved {
            c.states.clone_from(states);
            c.log.clear();
            c.steps = 0;
        }
        self.checkpoints = Some(c);
        saved.map(drop)
    }

    /// Rebuilds the envs of every lost server from the last checkpoint, on `replacement`
    /// or (when `None`) on the surviving servers in turn, and replays the steps and resets
    /// made since; the batch then goes on with every env, in the same positions, bitwise as
    /// if no server had been lost (given the same checkpoints).
    ///
    /// If the loss was found by a step, the survivors had taken that step: the result of
    /// that step for the whole batch is returned (the rebuilt envs' part from the replay),
    /// so no step is missed. `None` otherwise, or when nothing was lost.
    ///
    /// Fails with [`ClientError::Fleet`] if the batch does not checkpoint
    /// ([`FleetBatch::checkpoint_every`]) or no server is left to rebuild on; a failure
    /// while rebuilding leaves that shard lost (call again, e.g. with a replacement).
    pub async fn recover(&mut self, replacement: Option<&Client>) -> Result<Option<BatchStep>> {
        let Some(checkpoints) = self.checkpoints.take() else {
            return Err(ClientError::Fleet {
                message: "this fleet batch keeps no checkpoint to recover from: call \
                          checkpoint_every first"
                    .into(),
            });
        };
        let result = self.rebuild_lost(&checkpoints, replacement).await;
        self.checkpoints = Some(checkpoints);
        self.refresh();
        result
    }

    async fn rebuild_lost(
        &mut self,
        checkpoints: &Checkpoints,
        replacement: Option<&Client>,
    ) -> Result<Option<BatchStep>> {
        if self.shards.iter().all(|s| s.lost.is_none()) {
            return Ok(None);
        }
        let hosts: Vec<Client> = match replacement {
            Some(client) => vec![client.clone()],
            None => self
                .shards
                .iter()
                .filter(|s| s.lost.is_none())
                .map(|s| s.batch.client().clone())
                .collect(),
        };
        if hosts.is_empty() {
            return Err(ClientError::Fleet {
                message: "every server of this fleet batch was lost: recover onto a \
                          replacement server"
                    .into(),
            });
        }
        let ends_with_step = matches!(
            checkpoints.log.last(),
            Some(Logged::Step { .. } | Logged::StepEnvs { .. })
        );
        let mut replies = Vec::with_capacity(self.shards.len());
        let (mut position, mut rebuilt) = (0, 0);
        for k in 0..self.shards.len() {
            let shard = &self.shards[k];
            let len = shard.envs.len();
            let positions = position..position + len;
            position += len;
            if shard.lost.is_none() {
                replies.push(self.shards[k].interrupted.take());
                continue;
            }
            let host = &hosts[rebuilt % hosts.len()];
            rebuilt += 1;
            let first_index = shard.envs.start as u64;
            let states = &checkpoints.states[positions.clone()];
            let batch = host.fork(&states[0], len, self.info.autoreset).await?;
            let reply = match self
                .replay(&batch, states, &checkpoints.log, positions, first_index)
                .await
            {
                Ok(reply) => reply,
                Err(err) => {
                    let _ = batch.close().await;
                    return Err(err);
                }
            };
            let shard = &mut self.shards[k];
            shard.batch = batch;
            shard.lost = None;
            replies.push(reply);
        }
        let replies: Option<Vec<_>> = replies.into_iter().collect();
        Ok(match replies {
            Some(replies) if ends_with_step => {
                let lens: Vec<usize> = self.shards.iter().map(|s| s.envs.len()).collect();
                let mut info = self.info.clone();
                info.n_envs = lens.iter().sum();
                Some(BatchStep::new(merge_steps(replies, &lens), &info)?)
            }
            _ => None,
        })
    }

    /// Loads a shard's checkpointed states into `batch` and replays the log on them;
    /// the last step's reply, if the log ends with a step.
    async fn replay(
        &self,
        batch: &Batch,
        states: &[EnvState],
        log: &[Logged],
        positions: std::ops::Range<usize>,
        first_index: u64,
    ) -> Result<Option<gymfleet_proto::v1::BatchStepResult>> {
        batch.load_states(&[], states).await?;
        let dim = self.info.action_dim;
        let mut last = None;
        for entry in log {
            last = None;
            match entry {
                Logged::Step {
                    action_type,
                    actions,
                    mocap_poses,
                } => {
                    let rows = actions[positions.start * dim..positions.end * dim].to_vec();
                    let targets = self.mocap_rows(mocap_poses, positions.clone());
                    last = Some(batch.step_raw(*action_type, rows, targets).await?);
                }
                Logged::StepEnvs {
                    action_type,
                    env_indices,
                    actions,
                } => {
                    let (local, rows): (Vec<u32>, Vec<f32>) = env_indices
                        .iter()
                        .zip(actions.chunks(dim.max(1)))
                        .filter(|(&i, _)| positions.contains(&(i as usize)))
                        .map(|(&i, row)| (i - positions.start as u32, row.to_vec()))
                        .fold((Vec::new(), Vec::new()), |(mut l, mut r), (i, row)| {
                            l.push(i);
                            r.extend(row);
                            (l, r)
                        });
                    last = Some(batch.step_listed(*action_type, local, rows).await?);
                }
                Logged::Reset {
                    seed,
                    seed_offset,
                    env_indices,
                    keyframe,
                } => {
                    let offset = seed_offset.wrapping_add(first_index);
                    match env_indices {
                        None => {
                            batch.reset_envs_to(*seed, offset, &[], keyframe).await?;
                        }
                        Some(indices) => {
                            let local: Vec<u32> = indices
                                .iter()
                                .map(|&i| i as usize)
                                .filter(|i| positions.contains(i))
                                .map(|i| (i - positions.start) as u32)
                                .collect();
                            if !local.is_empty() {
                                batch.reset_envs_to(*seed, offset, &local, keyframe).await?;
                            }
                        }
                    }
                }
            }
        }
        Ok(last)
    }
}
