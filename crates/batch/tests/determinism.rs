//! Results do not depend on the thread count or the chunking, and a batch is exactly
//! its envs stepped one by one.

mod common;

use common::*;
use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::RobotEnv;

const N_ENVS: usize = 10;
const STEPS: usize = 24;

/// Resets with a seed, then steps `STEPS` times; every output, as bits.
fn run(
    threads: usize,
    chunk_size: usize,
    autoreset: Autoreset,
) -> Vec<impl PartialEq + std::fmt::Debug> {
    // Seeded reset noise: env i's start must depend on its seed only, not on the chunking.
    run_template(&noisy_arm2(7, 5.0), threads, chunk_size, autoreset)
}

fn run_template(
    template: &RobotEnv,
    threads: usize,
    chunk_size: usize,
    autoreset: Autoreset,
) -> Vec<impl PartialEq + std::fmt::Debug> {
    let (pool, mut batch) = seeded_batch(template, threads, chunk_size, autoreset);
    let mut out = BatchStepOutput::default();
    let mut trace = Vec::new();
    for t in 0..STEPS {
        let (action_type, values) = actions(t, N_ENVS, template.spec().action_dim);
        batch.step(&pool, action_type, &values, &mut out).unwrap();
        trace.push(output_bits(&out));
    }
    trace
}

/// A pool of `threads` and a batch of `template` reset with seed 42.
fn seeded_batch(
    template: &RobotEnv,
    threads: usize,
    chunk_size: usize,
    autoreset: Autoreset,
) -> (StepPool, EnvBatch) {
    let pool = StepPool::new(threads).unwrap();
    let mut batch = EnvBatch::with_chunk_size(template, N_ENVS, autoreset, chunk_size).unwrap();
    let mut obs = Vec::new();
    batch.reset(&pool, Some(42), 0, &mut obs).unwrap();
    (pool, batch)
}

#[test]
fn results_are_identical_for_any_thread_count_and_chunk_size() {
    for autoreset in [
        Autoreset::Disabled,
        Autoreset::SameStep,
        Autoreset::NextStep,
    ] {
        let reference = run(1, 1, autoreset);
        for threads in [1, 2, 4] {
            for chunk_size in [1, 3, 64] {
                assert!(
                    run(threads, chunk_size, autoreset) == reference,
                    "{autoreset:?}: {threads} threads, chunk size {chunk_size} differ from 1 thread, chunk size 1"
                );
            }
        }
    }
}

/// A caller that runs its own pool jobs (`run_jobs_here`, the Python package's calls to
/// its embedded server) steps a batch of one chunk itself and leaves one of several to the
/// pool: the same bits either way.
#[test]
fn a_caller_that_runs_its_jobs_itself_gets_the_same_bits() {
    let reference = run(2, 3, Autoreset::SameStep);
    for chunk_size in [3, N_ENVS] {
        let marked = gymfleet_batch::run_jobs_here(|| run(2, chunk_size, Autoreset::SameStep));
        assert!(marked == reference, "chunk size {chunk_size}");
    }
}

/// Past 64 envs a pool thread, each chunk prefetches its next env's state while the env before
/// it steps (`RobotEnv::prefetch`): a hint, so the same bits as a batch that does not.
#[test]
fn a_batch_large_enough_to_prefetch_steps_the_same_bits_as_one_that_does_not() {
    const LARGE: usize = 130;
    let template = noisy_arm2(7, 5.0);
    // One thread: 130 > 64 envs a thread, prefetched. Four: 130 ≤ 256, not.
    let trace = |threads: usize| {
        let pool = StepPool::new(threads).unwrap();
        let mut batch =
            EnvBatch::with_chunk_size(&template, LARGE, Autoreset::SameStep, 16).unwrap();
        let mut obs = Vec::new();
        batch.reset(&pool, Some(42), 0, &mut obs).unwrap();
        let mut out = BatchStepOutput::default();
        (0..8)
            .map(|t| {
                let (action_type, values) = actions(t, LARGE, template.spec().action_dim);
                batch.step(&pool, action_type, &values, &mut out).unwrap();
                output_bits(&out)
            })
            .collect::<Vec<_>>()
    };
    assert!(trace(1) == trace(4));
}

/// A closed chain (the four-bar of `models/`, its loop an impulse joint solved with the
/// tree) steps alike on any thread count and chunking too.
#[test]
fn a_four_bar_batch_is_identical_for_any_thread_count_and_chunk_size() {
    let config = gymfleet_env::EnvConfig {
        max_steps: 7,
        ..gymfleet_env::EnvConfig::with_end_effectors(["coupler"])
    };
    let template = RobotEnv::from_json(include_str!("../../../models/fourbar.json"), config)
        .expect("the four-bar is valid");
    let reference = run_template(&template, 1, 1, Autoreset::SameStep);
    for threads in [2, 4] {
        for chunk_size in [1, 3] {
            assert!(
                run_template(&template, threads, chunk_size, Autoreset::SameStep) == reference,
                "{threads} threads, chunk size {chunk_size} differ from 1 thread, chunk size 1"
            );
        }
    }
}

#[test]
fn an_output_taken_after_each_step_is_refilled_alike_at_its_exact_size() {
    // The server hands each step's buffers to its reply (`mem::take`), so every step
    // writes into an empty output; that must give the same bits as a reused one.
    let reused = run(2, 3, Autoreset::SameStep);
    let template = noisy_arm2(7, 5.0);
    let (pool, mut batch) = seeded_batch(&template, 2, 3, Autoreset::SameStep);
    let mut out = BatchStepOutput::default();
    let mut taken = Vec::new();
    for t in 0..STEPS {
        let (action_type, values) = actions(t, N_ENVS, template.spec().action_dim);
        batch.step(&pool, action_type, &values, &mut out).unwrap();
        let step = std::mem::take(&mut out);
        // One allocation of the whole step's size per field, not growth by doublings.
        assert_eq!(step.observations.capacity(), step.observations.len());
        assert_eq!(
            step.observations.len(),
            N_ENVS * template.spec().observation_dim
        );
        assert_eq!(step.rewards.capacity(), N_ENVS);
        assert_eq!(step.terminated.capacity(), N_ENVS);
        taken.push(output_bits(&step));
    }
    // Both are the same bits; compared as text since each helper returns its own opaque type.
    assert_eq!(format!("{taken:?}"), format!("{reused:?}"));
}

#[test]
fn a_batch_equals_its_envs_stepped_one_by_one() {
    let pool = StepPool::new(2).unwrap();
    let template = noisy_arm2(1000, 5.0);
    let mut batch = EnvBatch::with_chunk_size(&template, N_ENVS, Autoreset::Disabled, 3).unwrap();
    let mut envs: Vec<RobotEnv> = (0..N_ENVS).map(|_| template.clone()).collect();
    let dim = template.spec().observation_dim;
    assert_eq!(dim, 11);

    let mut batch_obs = Vec::new();
    batch.reset(&pool, Some(7), 100, &mut batch_obs).unwrap();
    let mut expected = vec![0.0; N_ENVS * dim];
    for (i, (env, row)) in envs
        .iter_mut()
        .zip(expected.chunks_exact_mut(dim))
        .enumerate()
    {
        env.reset_into(Some(107 + i as u64), row);
    }
    assert_eq!(bits(&batch_obs), bits(&expected));

    let mut out = BatchStepOutput::default();
    for t in 0..60 {
        let (action_type, values) = actions(t, N_ENVS, template.spec().action_dim);
        batch.step(&pool, action_type, &values, &mut out).unwrap();
        for (i, env) in envs.iter_mut().enumerate() {
            let row = &mut expected[i * dim..(i + 1) * dim];
            let flags = env
                .step_into(action_type, &values[2 * i..2 * i + 2], row)
                .unwrap();
            assert_eq!(out.rewards[i], flags.reward);
            assert_eq!(out.terminated[i], flags.terminated);
            assert_eq!(out.truncated[i], flags.truncated);
        }
        assert_eq!(bits(&out.observations), bits(&expected), "step {t}");
        assert!(out.termination_reasons.is_empty());
    }
    // The arm moved: the comparison above is not between two resting states.
    assert_ne!(bits(&out.observations[..2]), bits(&[0.0, 0.0]));

    let mut observed = Vec::new();
    batch.observe(&mut observed);
    assert_eq!(bits(&observed), bits(&expected));
}

#[test]
fn reset_seeds_are_seed_plus_offset_plus_index_wrapping() {
    let pool = StepPool::new(1).unwrap();
    let template = arm2(1000);
    let mut batch = EnvBatch::with_chunk_size(&template, 3, Autoreset::Disabled, 2).unwrap();
    assert_eq!(batch.seeds(), [template.seed(); 3]);
    let mut obs = Vec::new();
    batch.reset(&pool, Some(u64::MAX - 1), 1, &mut obs).unwrap();
    assert_eq!(batch.seeds(), [u64::MAX, 0, 1]);
    assert_eq!(obs.len(), 3 * 11);
    // Without a seed, every env keeps its own.
    batch.reset(&pool, None, 5, &mut obs).unwrap();
    assert_eq!(batch.seeds(), [u64::MAX, 0, 1]);
    let mut first = vec![0.0; 11];
    template.clone().reset_into(None, &mut first);
    assert_eq!(bits(&obs[..11]), bits(&first));
}

#[test]
fn the_default_chunk_rule_gives_four_chunks_per_thread_up_to_sixteen_envs() {
    use gymfleet_batch::default_chunk_size;
    assert_eq!(default_chunk_size(1, 8), 1);
    assert_eq!(default_chunk_size(16, 2), 2);
    assert_eq!(default_chunk_size(100, 2), 13);
    assert_eq!(default_chunk_size(256, 2), 16);
    assert_eq!(default_chunk_size(100_000, 64), 16);
    assert_eq!(default_chunk_size(10, 0), 3);
    let batch = EnvBatch::with_chunk_size(&arm2(10), 5, Autoreset::Disabled, 64).unwrap();
    assert_eq!(batch.chunk_size(), 5);
}

#[test]
fn for_pool_chunks_by_the_pools_threads_not_the_machines_cores() {
    // 24 envs: four chunks per thread is chunks of 6 on one thread, 2 on three.
    for (threads, chunk) in [(1, 6), (3, 2)] {
        let pool = StepPool::new(threads).unwrap();
        let batch = EnvBatch::for_pool(&arm2(10), 24, Autoreset::Disabled, &pool).unwrap();
        assert_eq!(batch.chunk_size(), chunk, "{threads} threads");
    }
}

/// A floating robot (a free slab with a hinged arm) dropped onto a ground plane: its base
/// moves, lands and its contacts are solved, with the same bits for any thread count and
/// chunking.
#[test]
fn floating_robots_on_a_ground_are_identical_for_any_thread_count() {
    let document = r#"{
        "floating_base": true,
        "parts": [
            {"name": "Slab", "primitive": {"type": "cube", "size": {"x": 100, "y": 100, "z": 20}}},
            {"name": "Arm", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 200}}},
            {"name": "Floor", "primitive": {"type": "plane"}}
        ],
        "assembly": {
            "instances": [
                {"part": "Slab", "name": "base", "position": {"x": 0, "y": 0, "z": 30}},
                {"part": "Arm", "name": "arm", "position": {"x": 40, "y": 40, "z": 50}},
                {"part": "Floor", "name": "floor"}
            ],
            "joints": [
                {"type": "revolute", "parent": "base", "child": "arm",
                 "anchor": {"x": 50, "y": 50, "z": 50}, "axis": {"x": 1, "y": 0, "z": 0},
                 "min": -60, "max": 60}
            ]
        }
    }"#;
    let run = |threads: usize, chunk_size: usize| {
        let pool = StepPool::new(threads).unwrap();
        let config = gymfleet_env::EnvConfig {
            reset_noise: 10.0,
            ..gymfleet_env::EnvConfig::with_end_effectors(["arm"])
        };
        let template = RobotEnv::from_json(document, config).expect("valid");
        assert_eq!(template.spec().observation_dim, 2 + 13 + 7);
        let mut batch =
            EnvBatch::with_chunk_size(&template, 6, Autoreset::SameStep, chunk_size).unwrap();
        let mut obs = Vec::new();
        batch.reset(&pool, Some(3), 0, &mut obs).unwrap();
        let mut out = BatchStepOutput::default();
        let mut trace = Vec::new();
        for t in 0..48 {
            let (action_type, values) = actions(t, 6, 1);
            batch.step(&pool, action_type, &values, &mut out).unwrap();
            trace.push(output_bits(&out));
        }
        // The bases fell onto the floor: their centres (10 mm above it at rest) came down.
        for row in out.observations.chunks_exact(22) {
            assert!(row[4] < 35.0, "base centre at {} mm", row[4]);
        }
        trace
    };
    let reference = run(1, 1);
    for (threads, chunk_size) in [(2, 1), (2, 3), (4, 2)] {
        assert!(
            run(threads, chunk_size) == reference,
            "{threads} threads, chunk size {chunk_size} differ"
        );
    }
}
