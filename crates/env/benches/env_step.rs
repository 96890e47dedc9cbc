//! Criterion benchmarks: one env step of the seed models and the 6-DOF arm, the raw
//! physics step underneath it (the simulator's own limit), and reset.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, DEFAULT_DT, DEFAULT_SUBSTEPS};
use gymfleet_physics::{ActionMode, RobotWorld, WorldOptions};

const PENDULUM: &str = include_str!("../../../models/pendulum.json");
const ARM2: &str = include_str!("../../../models/arm2.json");
const ARM6: &str = include_str!("../../../models/arm6.json");
const CHAIN20: &str = include_str!("../../../models/chain20.json");

const MODELS: [(&str, &str, &str); 4] = [
    ("pendulum", PENDULUM, "arm"),
    ("arm2", ARM2, "forearm"),
    ("arm6", ARM6, "tool"),
    ("chain20", CHAIN20, "link20"),
];

fn bench_env(c: &mut Criterion) {
    let mut group = c.benchmark_group("env");
    for (name, doc, ee) in MODELS {
        let mut env = RobotEnv::from_json(doc, EnvConfig::with_end_effectors([ee])).unwrap();
        let action = vec![0.0f32; env.spec().action_dim];
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

/// The same step without the gym layer: set the command, run the substeps. Reset every
/// 1000 steps, as the env does at its default `max_steps`.
fn bench_physics(c: &mut Criterion) {
    let mut group = c.benchmark_group("physics");
    for (name, doc, _) in MODELS {
        let assembly = gymfleet_assembly::parse(doc).unwrap();
        let options = WorldOptions {
            dt: DEFAULT_DT,
            substeps: DEFAULT_SUBSTEPS,
            gains: None,
        };
        let mut world = RobotWorld::new(&assembly, &options).unwrap();
        let action = vec![0.0f32; world.dofs().len()];
        let mut steps = 0;
        group.bench_function(format!("step/{name}"), |b| {
            b.iter(|| {
                world.set_command(ActionMode::Torque, &action);
                world.step();
                steps += 1;
                if steps % 1000 == 0 {
                    world.reset();
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_env, bench_physics);
criterion_main!(benches);
