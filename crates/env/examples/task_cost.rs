//! What a task adds to an arm2 env step, measured interleaved: rounds of 2000 zero-torque
//! steps of an env with no task, with a reach task, with a track task and with a terms
//! task as Gymnasium's Hopper writes its reward (forward velocity, control cost, healthy
//! ranges and state range, two reported coordinates), in rotating order, so that this machine's drift hits all three alike. Prints each one's median
//! step time over the rounds and the ratios to no task.
//!
//! `cargo run --release -p gymfleet-env --example task_cost -- 200`
//! (the argument is the number of rounds; default 100). A benchmark, not a test.

use std::time::Instant;

use gymfleet_env::{ActionType, EnvConfig, ReachTarget, RobotEnv, TaskKind, TaskSpec, TermsTask};

const ARM2: &str = include_str!("../../../models/arm2.json");
const STEPS: u32 = 2000;

fn env(task: Option<TaskKind>) -> RobotEnv {
    let config = EnvConfig {
        end_effector_ids: vec!["forearm".into()],
        task: task.map(|kind| TaskSpec {
            kind,
            action_cost: 0.01,
        }),
        ..EnvConfig::default()
    };
    RobotEnv::from_json(ARM2, config).expect("arm2")
}

fn main() {
    let rounds: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100);
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
    let terms = TaskKind::Terms(
        TermsTask::from_json(
            r#"{"terms": [
                {"name": "x_velocity", "weight": 1.0, "velocity": {"joint": "upper"}},
                {"name": "ctrl_cost", "weight": -0.001, "ctrl_cost": {}},
                {"name": "healthy", "weight": 1.0, "healthy": {}},
                {"name": "tip_z", "weight": 0.0, "value": {"instance": "forearm", "axis": "z"}},
                {"name": "com_x", "weight": 0.0, "value": {"center_of_mass": true, "axis": "x"}}
            ],
            "healthy": {"ranges": [{"of": {"joint": "forearm"}, "min": -200.0}],
                        "state_range": {"min": -1e6, "max": 1e6, "skip_positions": 1}}}"#,
        )
        .expect("terms"),
    );
    let mut envs = [
        env(None),
        env(Some(reach)),
        env(Some(track)),
        env(Some(terms)),
    ];
    let names = ["none", "reach", "track", "terms"];
    let mut times: [Vec<f64>; 4] = Default::default();
    let mut obs: Vec<Vec<f32>> = envs
        .iter()
        .map(|e| vec![0.0; e.spec().observation_dim])
        .collect();
    for round in 0..rounds {
        for k in 0..4 {
            let i = (round + k) % 4;
            let start = Instant::now();
            for _ in 0..STEPS {
                let flags = envs[i]
                    .step_into(ActionType::Torque, &[0.0, 0.0], &mut obs[i])
                    .expect("step");
                if flags.done() {
                    envs[i].reset_into(None, &mut obs[i]);
                }
            }
            times[i].push(start.elapsed().as_secs_f64() / f64::from(STEPS));
        }
    }
    let medians: Vec<f64> = times
        .iter_mut()
        .map(|t| {
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        })
        .collect();
    println!("arm2 env step, zero torque, {rounds} interleaved rounds of {STEPS} steps:");
    for (name, median) in names.iter().zip(&medians) {
        println!(
            "  {name:6} {:7.3} µs  ({:+.2} % vs none)",
            median * 1e6,
            (median / medians[0] - 1.0) * 100.0
        );
    }
}
