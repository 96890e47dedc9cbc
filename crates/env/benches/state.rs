//! Criterion benchmarks of saved states (BENCHMARKS.md J1): saving (with the re-seat and
//! the encoding), loading into an env of the same document, and building an env from a
//! state (parse, build, load: what `Fork` and a recovery do), for the seed models. Each
//! state's size is printed first.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, SavedState};

mod common;

use common::MODELS;

fn bench_state(c: &mut Criterion) {
    let mut group = c.benchmark_group("state");
    for (name, doc, ee) in MODELS {
        let mut env = RobotEnv::from_json(doc, EnvConfig::with_end_effectors([ee])).unwrap();
        let action: Vec<f32> = (0..env.spec().action_dim)
            .map(|k| 1e-4 * (k as f32 + 1.0))
            .collect();
        for _ in 0..20 {
            env.step(ActionType::Torque, &action).unwrap();
        }
        let bytes = env.save().unwrap().encode();
        println!(
            "state/{name}: {} bytes ({} of them the document)",
            bytes.len(),
            doc.len()
        );
        group.bench_function(format!("save/{name}"), |b| {
            b.iter(|| env.save().unwrap().encode())
        });
        group.bench_function(format!("load/{name}"), |b| {
            b.iter(|| {
                let state = SavedState::decode(&bytes).unwrap();
                env.load(&state).unwrap();
            })
        });
        group.bench_function(format!("from_state/{name}"), |b| {
            b.iter(|| RobotEnv::from_state(&SavedState::decode(&bytes).unwrap()).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench_state);
criterion_main!(benches);
