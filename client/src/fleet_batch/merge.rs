//! Merging the shards' replies to one step into the reply a one-server batch would give.

use gymfleet_proto::v1 as pb;

/// The shards' checked replies (of `lens` envs each) as one reply: rows concatenated in
/// shard order, per-env indices shifted by the shard's first position (the listed envs
/// of a subset step's replies too; a shard with none listed gives an empty reply). The
/// first reply's vectors are reused, so a one-shard batch copies nothing.
pub(crate) fn merge_steps(
    replies: Vec<pb::BatchStepResult>,
    lens: &[usize],
) -> pb::BatchStepResult {
    let mut replies = replies.into_iter();
    let mut merged = replies.next().unwrap_or_default();
    let mut position = lens.first().copied().unwrap_or(0);
    for (reply, len) in replies.zip(lens.iter().skip(1)) {
        let shift = u32::try_from(position).unwrap_or(u32::MAX);
        merged
            .env_indices
            .extend(reply.env_indices.iter().map(|i| i + shift));
        merged.observations.extend_from_slice(&reply.observations);
        merged.rewards.extend_from_slice(&reply.rewards);
        merged.terms.extend_from_slice(&reply.terms);
        merged.terminated.extend_from_slice(&reply.terminated);
        merged.truncated.extend_from_slice(&reply.truncated);
        merged
            .final_env_indices
            .extend(reply.final_env_indices.iter().map(|i| i + shift));
        merged
            .final_observations
            .extend_from_slice(&reply.final_observations);
        merged.termination_reasons.extend(
            reply
                .termination_reasons
                .into_iter()
                .map(|(i, reason)| (i + shift, reason)),
        );
        merged.terminations.extend(
            reply
                .terminations
                .into_iter()
                .map(|(i, reason)| (i + shift, reason)),
        );
        position += len;
    }
    merged
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::batch::BatchStep;
    use crate::types::BatchInfo;

    fn reply(n: usize, dim: usize, base: f32, finished: &[u32]) -> pb::BatchStepResult {
        pb::BatchStepResult {
            batch_id: "batch_1".into(),
            step_index: 3,
            observations: (0..n * dim).map(|v| base + v as f32).collect(),
            rewards: vec![base; n],
            terminated: (0..n).map(|i| i == 0).collect(),
            truncated: vec![false; n],
            final_env_indices: finished.to_vec(),
            final_observations: finished
                .iter()
                .flat_map(|&i| vec![-base - i as f32; dim])
                .collect(),
            termination_reasons: finished
                .iter()
                .map(|&i| (i, format!("reason {base} {i}")))
                .collect(),
            terminations: finished.iter().map(|&i| (i, 1)).collect(),
            terms: Vec::new(),
            env_indices: Vec::new(),
        }
    }

    #[test]
    fn merged_replies_keep_env_order_and_shift_per_env_indices() {
        let merged = merge_steps(
            vec![
                reply(2, 3, 0.0, &[1]),
                reply(1, 3, 100.0, &[]),
                reply(3, 3, 200.0, &[0, 2]),
            ],
            &[2, 1, 3],
        );
        let info = BatchInfo {
            n_envs: 6,
            env: crate::EnvInfo {
                observation_dim: 3,
                ..Default::default()
            },
            ..BatchInfo::default()
        };
        let step = BatchStep::new(merged, &info).expect("a well-formed merged reply");
        assert_eq!(step.step_index(), 3);
        assert_eq!(step.obs(0), [0.0, 1.0, 2.0]);
        assert_eq!(step.obs(2), [100.0, 101.0, 102.0]);
        assert_eq!(step.obs(5), [206.0, 207.0, 208.0]);
        assert_eq!(step.rewards(), [0.0, 0.0, 100.0, 200.0, 200.0, 200.0]);
        assert_eq!(step.terminated(), [true, false, true, true, false, false]);
        assert_eq!(step.final_env_indices(), [1, 3, 5]);
        assert_eq!(step.final_observation(1), Some(&[-1.0; 3][..]));
        assert_eq!(step.final_observation(3), Some(&[-200.0; 3][..]));
        assert_eq!(step.final_observation(5), Some(&[-202.0; 3][..]));
        assert_eq!(step.final_observation(4), None);
        assert_eq!(step.termination_reason(5), Some("reason 200 2"));
        assert_eq!(step.termination_reason(1), Some("reason 0 1"));
        assert_eq!(step.termination_reason(2), None);
        assert_eq!(
            step.termination(5),
            Some(crate::TerminationReason::PhysicsDiverged)
        );
        assert_eq!(step.termination(2), None);
    }
}
