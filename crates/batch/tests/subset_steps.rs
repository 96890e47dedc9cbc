//! Stepping some envs of a batch (`EnvBatch::step_envs`): each env's trajectory is the
//! one a whole-batch step gives it, bit for bit, in every autoreset mode and however the
//! envs are grouped; the others do not move; every mistake is refused before anything
//! changes.

mod common;

use common::*;
use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::ActionType;

const N: usize = 6;
const STEPS: usize = 12;
const OBS: usize = 11;

/// Env `e`'s torque at its own step `k` (arm2: two DOF).
fn action(e: usize, k: usize) -> [f32; 2] {
    [
        2e-3 * ((e * 7 + k * 13) as f32 * 0.37).sin(),
        -1e-3 * ((e + k) as f32).cos(),
    ]
}

/// What one env saw at one of its steps: its row, reward, flags and final row, as bits.
type Seen = (Vec<u32>, u32, bool, bool, Option<Vec<u32>>, Option<String>);

fn seen(out: &BatchStepOutput, row: usize, env: usize) -> Seen {
    let finals = out
        .final_env_indices
        .iter()
        .position(|&f| f as usize == env);
    (
        bits(&out.observations[row * OBS..(row + 1) * OBS]),
        out.rewards[row].to_bits(),
        out.terminated[row],
        out.truncated[row],
        finals.map(|k| bits(&out.final_observations[k * OBS..(k + 1) * OBS])),
        out.termination_reasons
            .get(&(env as u32))
            .map(|t| t.as_str().to_string()),
    )
}

fn seeded(autoreset: Autoreset) -> (StepPool, EnvBatch) {
    let pool = StepPool::new(2).unwrap();
    let mut batch = EnvBatch::with_chunk_size(&noisy_arm2(5, 20.0), N, autoreset, 2).unwrap();
    let mut obs = Vec::new();
    batch.reset(&pool, Some(7), 0, &mut obs).unwrap();
    (pool, batch)
}

/// Every env's steps in whole-batch steps.
fn whole(autoreset: Autoreset) -> Vec<Vec<Seen>> {
    let (pool, mut batch) = seeded(autoreset);
    let mut out = BatchStepOutput::default();
    let mut per_env = vec![Vec::new(); N];
    for k in 0..STEPS {
        let actions: Vec<f32> = (0..N).flat_map(|e| action(e, k)).collect();
        batch
            .step(&pool, ActionType::Torque, &actions, &mut out)
            .unwrap();
        for (e, steps) in per_env.iter_mut().enumerate() {
            steps.push(seen(&out, e, e));
        }
    }
    per_env
}

#[test]
fn each_env_steps_as_in_whole_batch_steps_however_grouped() {
    for autoreset in [
        Autoreset::Disabled,
        Autoreset::SameStep,
        Autoreset::NextStep,
    ] {
        let want = whole(autoreset);
        let (pool, mut batch) = seeded(autoreset);
        let mut out = BatchStepOutput::default();
        let mut per_env: Vec<Vec<Seen>> = vec![Vec::new(); N];
        let mut round = 0;
        while per_env.iter().any(|s| s.len() < STEPS) {
            // Uneven groups that change every round, across chunk boundaries.
            let group: Vec<u32> = (0..N)
                .filter(|&e| per_env[e].len() < STEPS && !(e + round).is_multiple_of(3))
                .map(|e| e as u32)
                .collect();
            round += 1;
            if group.is_empty() {
                continue;
            }
            let actions: Vec<f32> = group
                .iter()
                .flat_map(|&e| action(e as usize, per_env[e as usize].len()))
                .collect();
            let mut before = Vec::new();
            batch.observe(&mut before);
            batch
                .step_envs(&pool, ActionType::Torque, &group, &actions, &[], &mut out)
                .unwrap();
            assert_eq!(out.rewards.len(), group.len());
            let mut after = Vec::new();
            batch.observe(&mut after);
            for e in (0..N).filter(|e| !group.contains(&(*e as u32))) {
                assert_eq!(
                    bits(&before[e * OBS..(e + 1) * OBS]),
                    bits(&after[e * OBS..(e + 1) * OBS]),
                    "{autoreset:?}: env {e} was not listed and must not move"
                );
            }
            for (row, &e) in group.iter().enumerate() {
                per_env[e as usize].push(seen(&out, row, e as usize));
            }
        }
        assert_eq!(per_env, want, "{autoreset:?}");
        if autoreset == Autoreset::SameStep {
            assert!(
                want.iter().flatten().any(|s| s.4.is_some()),
                "episodes ended and reset"
            );
        }
    }
}

#[test]
fn bad_subsets_are_refused_before_anything_changes() {
    let (pool, mut batch) = seeded(Autoreset::SameStep);
    let mut before = Vec::new();
    batch.observe(&mut before);
    let mut out = BatchStepOutput::default();
    let cases: [(&[u32], Vec<f32>, &str); 6] = [
        (
            &[],
            vec![],
            "env_indices[0]: expected at least one env to step",
        ),
        (
            &[6],
            vec![0.0; 2],
            "env_indices[0]: env 6 is out of range: the batch has 6 envs",
        ),
        (
            &[3, 1],
            vec![0.0; 4],
            "env_indices[1]: expected ascending, distinct indices, got 1 after 3",
        ),
        (
            &[1, 1],
            vec![0.0; 4],
            "env_indices[1]: expected ascending, distinct indices, got 1 after 1",
        ),
        (
            &[0, 4],
            vec![0.0; 3],
            "actions: expected 4 values (2 envs × 2 DOF), got 3",
        ),
        (
            &[0, 4],
            vec![0.0, 0.0, 0.0, f32::NAN],
            "actions[3] (env 4, value 1): expected a finite number, got NaN",
        ),
    ];
    for (envs, actions, message) in cases {
        let err = batch
            .step_envs(&pool, ActionType::Torque, envs, &actions, &[], &mut out)
            .unwrap_err()
            .to_string();
        assert_eq!(err, message);
    }
    let err = batch
        .step_envs(
            &pool,
            ActionType::Torque,
            &[2],
            &[0.0; 2],
            &[0.0; 7],
            &mut out,
        )
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("mocap_poses: expected 0 values (1 env × 0 mocap bodies × 7"),
        "{err}"
    );
    let mut after = Vec::new();
    batch.observe(&mut after);
    assert_eq!(bits(&before), bits(&after), "nothing stepped");
}
