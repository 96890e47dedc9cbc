//! Criterion benchmarks: one env step of the seed models, and reset.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use gymfleet_env::{ActionType, EnvConfig, RobotEnv};

const PENDULUM: &str = include_str!("../../../models/pendulum.json");
const ARM2: &str = include_str!("../../../models/arm2.json");

fn bench_env(c: &mut Criterion) {
    let mut group = c.benchmark_group("env");
    for (name, doc, ee, action) in [
        ("pendulum", PENDULUM, "arm", vec![0.0f32]),
        ("arm2", ARM2, "forearm", vec![0.0f32, 0.0]),
    ] {
        let mut env = RobotEnv::from_json(doc, EnvConfig::with_end_effectors([ee])).unwrap();
        let mut obs = vec![0.0; env.spec().observation_dim];
        group.bench_function(format!("step/{name}"), |b| {
            b.iter(|| {
                let flags = env
                    .step_into(ActionType::Torque, &action, &mut obs)
                    .unwrap();
                if flags.done() {
                    env.reset_into(None, &mut obs);
                }
            })
        });
        group.bench_function(format!("reset/{name}"), |b| {
            b.iter(|| env.reset_into(None, &mut obs))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_env);
criterion_main!(benches);
