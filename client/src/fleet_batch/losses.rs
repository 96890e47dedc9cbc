//! A fleet batch's lost servers: which errors mean a shard is gone, how the shards'
//! outcomes are settled (the lost marked, the first error returned), and dropping the lost
//! shards while keeping the survivors' result of the step that found the loss.

use gymfleet_proto::v1 as pb;

use super::merge::merge_steps;
use super::{FleetBatch, Shard};
use crate::batch::BatchStep;
use crate::error::{ClientError, Result};
use crate::fanout::on_server;

impl FleetBatch {
    /// Forgets the shards of lost servers and returns their original env indices,
    /// ascending (empty if none was lost). The batch then holds the survivors only.
    ///
    /// Nothing is sent to a lost server: if it comes back with the shard still open, its
    /// idle TTL reclaims it.
    pub fn drop_lost(&mut self) -> Vec<usize> {
        let (lost, kept): (Vec<Shard>, Vec<Shard>) = std::mem::take(&mut self.shards)
            .into_iter()
            .partition(|s| s.lost.is_some());
        self.shards = kept;
        self.refresh();
        if !lost.is_empty() {
            // The checkpoint's states and log are by position, which just changed.
            self.checkpoints = None;
        }
        // The survivors' replies to the step that found the loss, if they all stepped.
        let replies: Option<Vec<pb::BatchStepResult>> = self
            .shards
            .iter_mut()
            .map(|s| s.interrupted.take())
            .collect();
        self.interrupted = match replies {
            Some(replies) if !lost.is_empty() && !self.shards.is_empty() => {
                let lens: Vec<usize> = self.shards.iter().map(|s| s.envs.len()).collect();
                BatchStep::new(merge_steps(replies, &lens), &self.info).ok()
            }
            _ => None,
        };
        lost.into_iter().flat_map(|s| s.envs).collect()
    }

    /// After [`FleetBatch::drop_lost`]: the survivors' result of the step that failed
    /// with [`ClientError::ServerLost`], in the survivors' order. They took that step
    /// (their servers did not fail), so a caller going on with them uses this result as
    /// that step's. `None` if the loss was not found by a step, or once taken.
    pub fn take_interrupted_step(&mut self) -> Option<BatchStep> {
        self.interrupted.take()
    }

    /// Fails with the first lost server's error, if one was lost.
    pub(crate) fn check_not_lost(&self) -> Result<()> {
        if self.shards.is_empty() {
            return Err(ClientError::Fleet {
                message: "every server of this fleet batch was lost; create a new one".into(),
            });
        }
        match self
            .shards
            .iter()
            .find_map(|s| s.lost.clone().map(|r| s.lost_error(r)))
        {
            Some(err) => Err(err),
            None => Ok(()),
        }
    }

    /// A server that fails a call without a clear status (a dropped connection can come
    /// back as UNKNOWN) is asked for its info: if that fails too, the server is lost.
    /// A single server's batch (`From<Batch>`) keeps its errors as they are.
    pub(crate) async fn confirm_losses<T>(&self, mut results: Vec<Result<T>>) -> Vec<Result<T>> {
        if self.single {
            return results;
        }
        for (shard, result) in self.shards.iter().zip(results.iter_mut()) {
            let Err(err @ ClientError::Internal { .. }) = result else {
                continue;
            };
            let first = err.to_string();
            if let Err(probe) = shard.batch.client().server_info().await {
                if is_loss(&probe) {
                    *result = Err(ClientError::Unavailable {
                        reason: crate::ErrorReason::Unspecified,
                        message: format!("{first}; then {probe}"),
                        code: tonic::Code::Unavailable,
                    });
                }
            }
        }
        results
    }

    /// Sorts the shards' outcomes: marks the lost servers (unreachable, or no longer
    /// knowing the shard) and returns the first error, a loss first.
    pub(crate) fn settle<T>(&mut self, results: Vec<Result<T>>) -> Result<Vec<T>> {
        self.settle_keeping(results, |_, _| {})
    }

    /// [`FleetBatch::settle`], handing each shard's value to `keep` if a server was lost.
    pub(super) fn settle_keeping<T>(
        &mut self,
        results: Vec<Result<T>>,
        mut keep: impl FnMut(&mut Shard, T),
    ) -> Result<Vec<T>> {
        if self.single {
            // One server's errors are its own: not a loss, not wrapped.
            return results.into_iter().collect();
        }
        let mut values = Vec::with_capacity(results.len());
        let mut lost = None;
        let mut other = None;
        for (shard, result) in self.shards.iter_mut().zip(results) {
            match result {
                Ok(value) => values.push((shard, value)),
                Err(err) if is_loss(&err) => {
                    let reason = err.to_string();
                    shard.lost = Some(reason.clone());
                    lost.get_or_insert_with(|| shard.lost_error(reason));
                }
                Err(err) => {
                    other.get_or_insert_with(|| on_server(shard.batch.client(), err));
                }
            }
        }
        if let Some(err) = lost {
            for (shard, value) in values {
                keep(shard, value);
            }
            return Err(err);
        }
        match other {
            Some(err) => Err(err),
            None => Ok(values.into_iter().map(|(_, value)| value).collect()),
        }
    }
}

/// Errors that mean the shard's envs are gone: the server is unreachable or going away,
/// no longer knows the batch (it restarted, or reclaimed it), or did not answer in time
/// (the shard's state is then unknown).
fn is_loss(err: &ClientError) -> bool {
    use crate::ErrorReason;
    matches!(
        err,
        ClientError::Unavailable { .. }
            | ClientError::DeadlineExceeded { .. }
            // The server no longer knows the shard's batch (a server that sends no
            // reason: any NOT_FOUND of a shard's call is about its batch).
            | ClientError::NotFound {
                reason: ErrorReason::BatchNotFound | ErrorReason::Unspecified,
                ..
            }
            | ClientError::Connect { .. }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_lost_servers_and_unknown_batches_count_as_losses() {
        use crate::ErrorReason;
        let message = String::from("x");
        assert!(is_loss(&ClientError::Unavailable {
            message: message.clone(),
            code: tonic::Code::Unavailable,
            reason: ErrorReason::Unspecified,
        }));
        assert!(is_loss(&ClientError::NotFound {
            message: message.clone(),
            reason: ErrorReason::BatchNotFound,
        }));
        assert!(!is_loss(&ClientError::NotFound {
            message: message.clone(),
            reason: ErrorReason::ModelNotFound,
        }));
        assert!(!is_loss(&ClientError::Internal {
            message: message.clone(),
            code: tonic::Code::Internal,
            reason: ErrorReason::Internal,
        }));
        assert!(!is_loss(&ClientError::InvalidArgument {
            message,
            reason: ErrorReason::InvalidAction,
        }));
    }
}
