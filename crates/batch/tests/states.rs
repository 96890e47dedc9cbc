//! Saving and loading the states of a batch's envs, and forking a batch from one state:
//! bitwise continuations, whatever the thread count and chunking; bad lists and foreign
//! states load nothing.

mod common;

use common::*;
use gymfleet_batch::{Autoreset, BatchError, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::RobotEnv;

const N_ENVS: usize = 6;

fn step_all(batch: &mut EnvBatch, pool: &StepPool, t: usize, out: &mut BatchStepOutput) {
    let (action_type, values) = actions(t, batch.n_envs(), batch.spec().action_dim);
    batch
        .step(pool, action_type, &values, out)
        .expect("valid actions");
}

/// `steps` steps from step `start`, every observation as bits.
fn trace(batch: &mut EnvBatch, pool: &StepPool, start: usize, steps: usize) -> Vec<Vec<u32>> {
    let mut out = BatchStepOutput::default();
    (start..start + steps)
        .map(|t| {
            step_all(batch, pool, t, &mut out);
            bits(&out.observations)
        })
        .collect()
}

fn seeded(pool: &StepPool, chunk_size: usize) -> EnvBatch {
    let template = noisy_arm2(25, 5.0);
    let mut batch =
        EnvBatch::with_chunk_size(&template, N_ENVS, Autoreset::SameStep, chunk_size).unwrap();
    batch.reset(pool, Some(3), 0, &mut Vec::new()).unwrap();
    batch
}

#[test]
fn states_saved_from_one_batch_load_into_another_of_other_chunking() {
    let (one, two) = (StepPool::new(1).unwrap(), StepPool::new(2).unwrap());
    let mut source = seeded(&one, 1);
    trace(&mut source, &one, 0, 10);
    let states = source.save_states(&[]).expect("every env saves");
    assert_eq!(states.len(), N_ENVS);

    // Another batch, other chunks and threads, other episodes: loading makes it the source.
    let mut target = seeded(&two, 4);
    trace(&mut target, &two, 100, 17);
    target
        .load_states(&[], &states)
        .expect("same document and options");
    // 40 steps cross the 25-step episodes' ends: the seeded generators came along too.
    assert_eq!(
        trace(&mut target, &two, 10, 40),
        trace(&mut source, &one, 10, 40)
    );
}

#[test]
fn some_envs_save_and_load_by_index() {
    let pool = StepPool::new(2).unwrap();
    let mut batch = seeded(&pool, 2);
    trace(&mut batch, &pool, 0, 5);
    let saved = batch.save_states(&[1, 4]).expect("saves two");
    let mut observed = Vec::new();
    batch.observe(&mut observed);
    let dim = batch.spec().observation_dim;
    let at_save: Vec<Vec<f32>> = [1, 4]
        .iter()
        .map(|&i| observed[i * dim..(i + 1) * dim].to_vec())
        .collect();
    trace(&mut batch, &pool, 5, 8);
    // Load them crosswise: env 1 gets env 4's state and env 4 env 1's.
    batch
        .load_states(&[1, 4], &[saved[1].clone(), saved[0].clone()])
        .expect("loads");
    batch.observe(&mut observed);
    assert_eq!(observed[dim..2 * dim], at_save[1][..]);
    assert_eq!(observed[4 * dim..5 * dim], at_save[0][..]);
}

#[test]
fn a_fork_is_n_copies_that_continue_like_their_parent() {
    let pool = StepPool::new(2).unwrap();
    let mut parent = noisy_arm2(1000, 5.0);
    parent.reset(Some(11));
    for t in 0..30 {
        let (action_type, values) = actions(t, 1, 2);
        parent.step(action_type, &values).expect("valid");
    }
    let state = parent.save().expect("saves");
    let template = RobotEnv::from_state(&state).expect("loads");
    let mut fork = EnvBatch::copies_of(&template, 5, Autoreset::Disabled, &pool).unwrap();
    let mut obs = Vec::new();
    fork.observe(&mut obs);
    let dim = fork.spec().observation_dim;
    for i in 0..5 {
        assert_eq!(obs[i * dim..(i + 1) * dim], parent.observe().to_flat()[..]);
    }
    let mut out = BatchStepOutput::default();
    for t in 30..90 {
        // The same action for every copy and the parent.
        let (action_type, one) = actions(t, 1, 2);
        let values: Vec<f32> = one.iter().cycle().take(5 * 2).copied().collect();
        fork.step(&pool, action_type, &values, &mut out)
            .expect("valid");
        let expected = bits(
            &parent
                .step(action_type, &one)
                .expect("valid")
                .observation
                .to_flat(),
        );
        for i in 0..5 {
            assert_eq!(
                bits(&out.observations[i * dim..(i + 1) * dim]),
                expected,
                "copy {i}, step {t}"
            );
        }
    }
}

#[test]
fn bad_lists_and_foreign_states_load_nothing() {
    let pool = StepPool::new(1).unwrap();
    let mut batch = seeded(&pool, 2);
    let states = batch.save_states(&[0, 1]).expect("saves");
    let mut before = Vec::new();
    batch.observe(&mut before);

    assert_eq!(
        batch
            .load_states(&[0, 1, 2], &states)
            .unwrap_err()
            .to_string(),
        "states: expected one state per env index (3), got 2"
    );
    assert_eq!(
        batch.load_states(&[], &states).unwrap_err().to_string(),
        "states: expected one state per env index (6), got 2"
    );
    assert_eq!(
        batch.load_states(&[2, 1], &states).unwrap_err().to_string(),
        "env_indices[1]: expected ascending, distinct indices, got 1 after 2"
    );
    assert_eq!(
        batch.save_states(&[9]).unwrap_err().to_string(),
        "env_indices[0]: env 9 is out of range: the batch has 6 envs"
    );
    // A pendulum's state in an arm batch: the second fails, so the first is not loaded.
    let mut pendulum = pendulum(100, 5);
    let foreign = pendulum.save().expect("saves");
    let err = batch
        .load_states(&[3, 4], &[states[0].clone(), foreign])
        .unwrap_err();
    assert!(matches!(err, BatchError::Env { env: 4, .. }), "{err}");
    assert_eq!(
        err.to_string(),
        "env 4: state.document: the state was saved from an env of another document"
    );
    let mut after = Vec::new();
    batch.observe(&mut after);
    assert_eq!(bits(&after), bits(&before), "nothing was loaded");
}
