//! Criterion benchmarks: one step of a batch of seed arms, by batch size, thread count
//! and chunk size. Steps run inside the pool ([`StepPool::install`]), as the server
//! runs them, so "1 thread" means one thread doing physics.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_env::{ActionType, EnvConfig, RobotEnv};

const ARM2: &str = include_str!("../../../models/arm2.json");

fn arm2() -> RobotEnv {
    RobotEnv::from_json(ARM2, EnvConfig::with_end_effectors(["forearm"])).unwrap()
}

/// Position targets that differ per env and per step, so the arms keep moving.
fn action_cycle(n_envs: usize) -> Vec<Vec<f32>> {
    (0..64)
        .map(|t| {
            (0..2 * n_envs)
                .map(|k| 60.0 * ((k * 7 + t * 13) as f32 * 0.37).sin())
                .collect()
        })
        .collect()
}

/// Benchmarks `n_envs` arms with `chunk_size` (0: the default rule) on `threads`
/// (0: one per core).
fn bench_step(c: &mut Criterion, group: &str, n_envs: usize, threads: usize, chunk_size: usize) {
    let pool = StepPool::new(threads).unwrap();
    let mut batch =
        EnvBatch::with_chunk_size(&arm2(), n_envs, Autoreset::SameStep, chunk_size).unwrap();
    let actions = action_cycle(n_envs);
    let mut out = BatchStepOutput::default();
    let mut t = 0;
    let mut group = c.benchmark_group(group);
    group.throughput(Throughput::Elements(n_envs as u64));
    let name = format!(
        "{n_envs}_envs/{}_threads/chunk_{}",
        pool.threads(),
        batch.chunk_size()
    );
    group.bench_function(name, |b| {
        b.iter(|| {
            t = (t + 1) % actions.len();
            pool.install(|| batch.step(&pool, ActionType::Position, &actions[t], &mut out))
                .unwrap();
        })
    });
    group.finish();
}

fn bench_batch_step(c: &mut Criterion) {
    for (n_envs, threads) in [(256, 1), (256, 2), (16, 0), (1024, 0)] {
        bench_step(c, "batch_step", n_envs, threads, 0);
    }
}

fn bench_chunk_size(c: &mut Criterion) {
    for chunk_size in [1, 4, 16, 64] {
        bench_step(c, "chunk_size", 256, 2, chunk_size);
    }
}

criterion_group!(benches, bench_batch_step, bench_chunk_size);
criterion_main!(benches);
