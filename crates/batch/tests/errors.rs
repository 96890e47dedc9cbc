//! Every error, with its exact message, and that a rejected step changes nothing.

mod common;

use common::*;
use gymfleet_batch::{Autoreset, BatchError, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::{ActionType, EnvError};

fn sixteen_arms() -> (StepPool, EnvBatch) {
    let batch = EnvBatch::with_chunk_size(&arm2(1000), 16, Autoreset::Disabled, 3).unwrap();
    (StepPool::new(2).unwrap(), batch)
}

#[test]
fn an_empty_batch_is_refused() {
    let err = EnvBatch::new(&arm2(1000), 0, Autoreset::Disabled).unwrap_err();
    assert_eq!(err, BatchError::NoEnvs);
    assert_eq!(
        err.to_string(),
        "n_envs: expected at least 1 environment, got 0"
    );
}

#[test]
fn a_wrong_action_length_names_envs_and_dofs() {
    let (pool, mut batch) = sixteen_arms();
    let mut out = BatchStepOutput::default();
    let err = batch
        .step(&pool, ActionType::Torque, &[0.0; 31], &mut out)
        .unwrap_err();
    assert_eq!(
        err,
        BatchError::ActionLength {
            expected: 32,
            got: 31,
            n_envs: 16,
            action_dim: 2
        }
    );
    assert_eq!(
        err.to_string(),
        "actions: expected 32 values (16 envs × 2 DOF), got 31"
    );

    let mut one = EnvBatch::new(&pendulum(1000, 4), 1, Autoreset::Disabled).unwrap();
    let err = one
        .step(&pool, ActionType::Torque, &[], &mut out)
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "actions: expected 1 value (1 env × 1 DOF), got 0"
    );
}

#[test]
fn a_non_finite_action_names_its_env_and_value() {
    let (pool, mut batch) = sixteen_arms();
    let mut out = BatchStepOutput::default();
    for (value, shown) in [
        (f32::NAN, "NaN"),
        (f32::INFINITY, "inf"),
        (f32::NEG_INFINITY, "-inf"),
    ] {
        let mut actions = vec![0.0; 32];
        actions[5] = value;
        actions[30] = f32::NAN; // only the first bad value is reported
        let err = batch
            .step(&pool, ActionType::Position, &actions, &mut out)
            .unwrap_err();
        match err {
            BatchError::NonFiniteAction {
                env: 2,
                index: 1,
                flat_index: 5,
                value: got,
            } => assert_eq!(got.to_bits(), value.to_bits()),
            other => panic!("unexpected {other:?}"),
        }
        assert_eq!(
            err.to_string(),
            format!("actions[5] (env 2, value 1): expected a finite number, got {shown}")
        );
    }
}

#[test]
fn a_rejected_step_steps_nothing() {
    let (pool, mut batch) = sixteen_arms();
    let mut before = Vec::new();
    batch.observe(&mut before);
    let chunks_before = pool.chunks_run();
    let mut actions = vec![50.0; 32];
    actions[31] = f32::NAN;
    let mut out = BatchStepOutput::default();
    batch
        .step(&pool, ActionType::Position, &actions, &mut out)
        .unwrap_err();
    assert_eq!(pool.chunks_run(), chunks_before);
    let mut after = Vec::new();
    batch.observe(&mut after);
    assert_eq!(bits(&after), bits(&before));
    assert_eq!(out, BatchStepOutput::default());
}

#[test]
fn env_and_pool_errors_read_well() {
    let err = BatchError::Env {
        env: 3,
        source: EnvError::NeedsReset,
    };
    assert_eq!(
        err.to_string(),
        "env 3: the simulation diverged (non-finite state) and was terminated; call reset before stepping again"
    );
    let source = std::error::Error::source(&err).expect("the env error is the source");
    assert_eq!(source.to_string(), EnvError::NeedsReset.to_string());

    let err = BatchError::PoolStart {
        threads: 4,
        reason: "out of memory".to_string(),
    };
    assert_eq!(
        err.to_string(),
        "step pool: cannot start 4 step threads: out of memory"
    );
    let err = BatchError::Panicked {
        first: 8,
        last: 15,
        message: "boom".to_string(),
    };
    assert_eq!(
        err.to_string(),
        "step pool: envs 8..=15 panicked (boom); reset the batch before stepping it again"
    );
    let err = BatchError::TooManyEnvs {
        n_envs: 1 << 33,
        max: u64::from(u32::MAX),
    };
    assert_eq!(
        err.to_string(),
        "n_envs: expected at most 4294967295 environments per batch, got 8589934592"
    );
}
