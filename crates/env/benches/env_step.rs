//! Criterion benchmarks: one env step of the seed models and the 6-DOF arm, the raw
//! physics step underneath it (the simulator's own limit), and reset.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use gymfleet_env::{
    ActionType, EnvConfig, ReachTarget, RobotEnv, TaskKind, TaskSpec, DEFAULT_DT, DEFAULT_SUBSTEPS,
};
use gymfleet_physics::{ActionMode, RobotWorld, WorldOptions};

mod common;

use common::{ARM2, MODELS};

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

/// What a task adds to an arm2 step: none, a reach task (a target box, the tip as the
/// point, an action cost) and a track task. Zero torque, as in `env/step`, so that all
/// three integrate the same states and differ only by the task.
fn bench_task_cost(c: &mut Criterion) {
    let reach = TaskKind::Reach {
        end_effector: "forearm".into(),
        point: Some([1.5, 1.5, 25.0]),
        target: ReachTarget::Box {
            min: [15.0, 0.0, 30.0],
            max: [30.0, 0.0, 45.0],
        },
        success_radius: 5.0,
        terminate_on_success: false,
    };
    let track = TaskKind::Track {
        targets: vec![30.0, -45.0],
        tolerance: 1.0,
        terminate_on_success: false,
    };
    let mut group = c.benchmark_group("task_cost");
    for (name, task) in [
        ("none", None),
        ("reach", Some(reach)),
        ("track", Some(track)),
    ] {
        let config = EnvConfig {
            end_effector_ids: vec!["forearm".into()],
            task: task.map(|kind| TaskSpec {
                kind,
                action_cost: 0.01,
            }),
            ..EnvConfig::default()
        };
        let mut env = RobotEnv::from_json(ARM2, config).unwrap();
        let mut obs = vec![0.0; env.spec().observation_dim];
        group.bench_function(format!("arm2/{name}"), |b| {
            b.iter(|| {
                let flags = env
                    .step_into(ActionType::Torque, &[0.0, 0.0], &mut obs)
                    .unwrap();
                if flags.done() {
                    env.reset_into(None, &mut obs);
                }
            })
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
        let action = vec![0.0f32; world.actuated_dofs()];
        let mut steps = 0;
        group.bench_function(format!("step/{name}"), |b| {
            b.iter(|| {
                world.set_command(ActionMode::Torque, &action);
                world.step().expect("no contact limit");
                steps += 1;
                if steps % 1000 == 0 {
                    world.reset();
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_env, bench_physics, bench_task_cost);
criterion_main!(benches);
