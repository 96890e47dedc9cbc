//! The three autoreset modes, and a diverged env in each.

mod common;

use common::*;
use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::{ActionType, RobotEnv, Termination};

const N: usize = 3;
/// Torque (N·m) that blows the pendulum up in one step.
const HUGE: f32 = 1e6;

/// A batch of `N` pendulums with `max_steps` 3, chunked so that envs span chunks.
fn batch(autoreset: Autoreset) -> (StepPool, EnvBatch, RobotEnv) {
    let template = pendulum(3, 4);
    let batch = EnvBatch::with_chunk_size(&template, N, autoreset, 2).unwrap();
    (StepPool::new(2).unwrap(), batch, template)
}

/// The first observation and the observations of steps 1..=k of a lone pendulum
/// pushed with `torque` each step.
fn lone_episode(template: &RobotEnv, torque: f32, k: usize) -> Vec<Vec<f32>> {
    let mut env = template.clone();
    let mut row = vec![0.0; 9];
    env.reset_into(None, &mut row);
    let mut rows = vec![row.clone()];
    for _ in 0..k {
        env.step_into(ActionType::Torque, &[torque], &mut row)
            .unwrap();
        rows.push(row.clone());
    }
    rows
}

fn step(batch: &mut EnvBatch, pool: &StepPool, torques: [f32; N], out: &mut BatchStepOutput) {
    batch.step(pool, ActionType::Torque, &torques, out).unwrap();
}

fn row(out: &BatchStepOutput, i: usize) -> Vec<u32> {
    bits(&out.observations[i * 9..(i + 1) * 9])
}

const PUSH: f32 = 1e-3;

#[test]
fn disabled_keeps_stepping_past_truncation() {
    let (pool, mut batch, template) = batch(Autoreset::Disabled);
    let lone = lone_episode(&template, PUSH, 5);
    let mut out = BatchStepOutput::default();
    for (t, expected) in lone.iter().enumerate().skip(1) {
        step(&mut batch, &pool, [PUSH; N], &mut out);
        assert_eq!(out.truncated, [t >= 3; N], "step {t}");
        assert_eq!(out.terminated, [false; N]);
        assert_eq!(out.rewards, [0.0; N]);
        assert!(out.final_env_indices.is_empty() && out.final_observations.is_empty());
        for i in 0..N {
            assert_eq!(row(&out, i), bits(expected), "step {t}, env {i}");
        }
    }
}

#[test]
fn same_step_resets_within_the_step_and_returns_the_final_observation() {
    let (pool, mut batch, template) = batch(Autoreset::SameStep);
    let lone = lone_episode(&template, PUSH, 3);
    let mut out = BatchStepOutput::default();
    for t in 1..=7 {
        step(&mut batch, &pool, [PUSH; N], &mut out);
        let k = (t - 1) % 3 + 1; // step within the episode
        let finished = k == 3;
        assert_eq!(out.truncated, [finished; N], "step {t}");
        assert_eq!(out.terminated, [false; N]);
        if finished {
            assert_eq!(out.final_env_indices, [0, 1, 2]);
            assert_eq!(bits(&out.final_observations), bits(&lone[3].repeat(N)));
            for i in 0..N {
                assert_eq!(row(&out, i), bits(&lone[0]), "step {t}: reset obs");
            }
        } else {
            assert!(out.final_env_indices.is_empty() && out.final_observations.is_empty());
            for i in 0..N {
                assert_eq!(row(&out, i), bits(&lone[k]), "step {t}, env {i}");
            }
        }
    }
}

#[test]
fn next_step_resets_on_the_following_step_ignoring_its_action() {
    let (pool, mut batch, template) = batch(Autoreset::NextStep);
    let lone = lone_episode(&template, PUSH, 3);
    let mut out = BatchStepOutput::default();
    // Steps 1-3: the episode; step 4: the reset, whose (huge) action is ignored;
    // steps 5-7: the next episode; step 8: the reset again.
    for t in 1..=8 {
        let torques = if t % 4 == 0 { [HUGE; N] } else { [PUSH; N] };
        step(&mut batch, &pool, torques, &mut out);
        let k = t % 4;
        assert_eq!(out.truncated, [k == 3; N], "step {t}");
        assert_eq!(out.terminated, [false; N], "step {t}");
        assert_eq!(out.rewards, [0.0; N]);
        assert!(out.final_env_indices.is_empty() && out.final_observations.is_empty());
        assert!(out.termination_reasons.is_empty(), "step {t}");
        for i in 0..N {
            assert_eq!(row(&out, i), bits(&lone[k]), "step {t}, env {i}");
        }
    }
}

#[test]
fn disabled_reports_a_diverged_env_without_failing_the_batch() {
    let (pool, mut batch, template) = batch(Autoreset::Disabled);
    let lone = lone_episode(&template, PUSH, 4);
    let mut out = BatchStepOutput::default();
    step(&mut batch, &pool, [PUSH, HUGE, PUSH], &mut out);
    assert_eq!(out.terminated, [false, true, false]);
    assert_eq!(out.termination_reasons.len(), 1);
    assert_eq!(out.termination_reasons[&1], Termination::PhysicsDiverged);
    // The last finite observation: the initial one.
    assert_eq!(row(&out, 1), bits(&lone[0]));
    for t in 2..=4 {
        step(&mut batch, &pool, [PUSH; N], &mut out);
        assert_eq!(out.terminated, [false, true, false], "step {t}");
        assert_eq!(out.termination_reasons[&1], Termination::PhysicsDiverged);
        assert_eq!(row(&out, 1), bits(&lone[0]), "step {t}");
        assert_eq!(row(&out, 0), bits(&lone[t]), "step {t}");
        assert_eq!(row(&out, 2), bits(&lone[t]), "step {t}");
    }
    // A batch reset brings it back.
    let mut obs = Vec::new();
    batch.reset(&pool, None, 0, &mut obs).unwrap();
    step(&mut batch, &pool, [PUSH; N], &mut out);
    assert_eq!(out.terminated, [false; N]);
    assert!(out.termination_reasons.is_empty());
    assert_eq!(row(&out, 1), bits(&lone[1]));
}

#[test]
fn same_step_resets_a_diverged_env_at_once() {
    let (pool, mut batch, template) = batch(Autoreset::SameStep);
    let lone = lone_episode(&template, PUSH, 1);
    let mut out = BatchStepOutput::default();
    step(&mut batch, &pool, [PUSH, PUSH, HUGE], &mut out);
    assert_eq!(out.terminated, [false, false, true]);
    assert_eq!(out.final_env_indices, [2]);
    assert_eq!(bits(&out.final_observations), bits(&lone[0]));
    assert_eq!(out.termination_reasons[&2], Termination::PhysicsDiverged);
    step(&mut batch, &pool, [PUSH; N], &mut out);
    assert_eq!(out.terminated, [false; N]);
    assert_eq!(row(&out, 2), bits(&lone[1]));
}

#[test]
fn next_step_resets_a_diverged_env_on_the_following_step() {
    let (pool, mut batch, template) = batch(Autoreset::NextStep);
    let lone = lone_episode(&template, PUSH, 1);
    let mut out = BatchStepOutput::default();
    step(&mut batch, &pool, [HUGE, PUSH, PUSH], &mut out);
    assert_eq!(out.terminated, [true, false, false]);
    assert_eq!(out.termination_reasons[&0], Termination::PhysicsDiverged);
    step(&mut batch, &pool, [HUGE, PUSH, PUSH], &mut out);
    assert_eq!(out.terminated, [false; N]);
    assert!(out.termination_reasons.is_empty());
    assert_eq!(row(&out, 0), bits(&lone[0]));
    step(&mut batch, &pool, [PUSH; N], &mut out);
    assert_eq!(row(&out, 0), bits(&lone[1]));
}

#[test]
fn a_batch_reset_cancels_a_pending_next_step_reset() {
    let (pool, mut batch, template) = batch(Autoreset::NextStep);
    let lone = lone_episode(&template, PUSH, 1);
    let mut out = BatchStepOutput::default();
    for _ in 0..3 {
        step(&mut batch, &pool, [PUSH; N], &mut out);
    }
    assert_eq!(out.truncated, [true; N]);
    let mut obs = Vec::new();
    batch.reset(&pool, None, 0, &mut obs).unwrap();
    assert_eq!(bits(&obs), bits(&lone[0].repeat(N)));
    // This step is a real step, not a second reset.
    step(&mut batch, &pool, [PUSH; N], &mut out);
    assert_eq!(bits(&out.observations), bits(&lone[1].repeat(N)));
}

#[test]
fn a_partial_reset_resets_the_listed_envs_and_leaves_the_others_as_they_are() {
    let (pool, mut batch, template) = batch(Autoreset::NextStep);
    let lone = lone_episode(&template, PUSH, 2);
    let mut out = BatchStepOutput::default();
    for _ in 0..3 {
        step(&mut batch, &pool, [PUSH; N], &mut out);
    }
    assert_eq!(out.truncated, [true; N]);
    let ended = out.observations[9..18].to_vec();
    // Envs 0 and 2 span both chunks (chunk size 2).
    let mut obs = Vec::new();
    batch
        .reset_envs(&pool, None, 0, Some(&[0, 2]), &mut obs)
        .unwrap();
    assert_eq!(bits(&obs[..9]), bits(&lone[0]));
    assert_eq!(
        bits(&obs[9..18]),
        bits(&ended),
        "env 1 keeps its observation"
    );
    assert_eq!(bits(&obs[18..]), bits(&lone[0]));
    // Envs 0 and 2 take a real step; env 1 still has its pending reset.
    step(&mut batch, &pool, [PUSH; N], &mut out);
    assert_eq!(row(&out, 0), bits(&lone[1]));
    assert_eq!(row(&out, 1), bits(&lone[0]));
    assert_eq!(row(&out, 2), bits(&lone[1]));
}

#[test]
fn a_partial_reset_refuses_a_bad_index_list_and_resets_nothing() {
    let (pool, mut batch, _) = batch(Autoreset::Disabled);
    let mut out = BatchStepOutput::default();
    step(&mut batch, &pool, [PUSH; N], &mut out);
    let before = out.observations.clone();
    let mut obs = Vec::new();
    for (indices, message) in [
        (
            &[0, 3][..],
            "env_indices[1]: env 3 is out of range: the batch has 3 envs",
        ),
        (
            &[1, 1][..],
            "env_indices[1]: expected ascending, distinct indices, got 1 after 1",
        ),
        (
            &[2, 0][..],
            "env_indices[1]: expected ascending, distinct indices, got 0 after 2",
        ),
    ] {
        let err = batch
            .reset_envs(&pool, None, 0, Some(indices), &mut obs)
            .unwrap_err();
        assert_eq!(err.to_string(), message);
    }
    let mut now = Vec::new();
    batch.observe(&mut now);
    assert_eq!(bits(&now), bits(&before));
}
