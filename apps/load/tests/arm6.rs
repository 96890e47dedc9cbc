//! `models/arm6.json`, the 6-DOF arm: it parses to six revolute DOFs with their limits,
//! and steps stably — a few hundred steps of small actions in every mode, with finite
//! observations and no `physics_diverged` — both in process and on the server.

use gymfleet_env::{ActionType, EnvConfig, RobotEnv};
use gymfleet_load::{ActionKind, ActionPlan, ARM6};

fn arm6() -> RobotEnv {
    RobotEnv::from_json(ARM6, EnvConfig::with_end_effectors(["tool"])).expect("arm6 parses")
}

fn limits(env: &RobotEnv) -> Vec<Option<(f64, f64)>> {
    env.spec()
        .dofs
        .iter()
        .map(|d| d.limits.map(|[a, b]| (a, b)))
        .collect()
}

#[test]
fn arm6_has_six_limited_revolute_joints() {
    let env = arm6();
    let spec = env.spec();
    assert_eq!(
        (spec.num_joints, spec.action_dim, spec.observation_dim),
        (6, 6, 19)
    );
    assert_eq!(
        spec.joint_names,
        [
            "base_yaw",
            "shoulder_pitch",
            "elbow_pitch",
            "wrist_roll",
            "wrist_pitch",
            "tool_roll"
        ]
    );
    let limits = limits(&env);
    assert_eq!(limits[1], Some((-100.0, 100.0)));
    assert!(limits.iter().all(Option::is_some));
    // The tool starts upright above the base: centre of mass at (0, 0, 432.5) mm.
    let mut obs = vec![0.0; 19];
    let mut env = env;
    env.reset_into(None, &mut obs);
    let pose = &obs[12..19];
    assert!(pose[0].abs() < 1e-3 && pose[1].abs() < 1e-3, "{pose:?}");
    assert!((pose[2] - 432.5).abs() < 1e-2, "{pose:?}");
    assert_eq!(&obs[..12], &[0.0; 12]);
}

#[test]
fn arm6_steps_stably_in_every_action_mode() {
    // Torque: each DOF within its own action bound (the load client's default).
    for (kind, action_type, amplitude) in [
        (ActionKind::Torque, ActionType::Torque, None),
        (ActionKind::Position, ActionType::Position, Some(30.0)),
        (ActionKind::Velocity, ActionType::Velocity, Some(45.0)),
    ] {
        let mut env = arm6();
        let bounds: Vec<f64> = env.spec().dofs.iter().map(|d| d.action_bound).collect();
        let plan = ActionPlan::new(kind, amplitude, &limits(&env), &bounds, 1);
        let mut action = vec![0.0; 6];
        let mut obs = vec![0.0; 19];
        for step in 0..400 {
            plan.fill(step, 0, &mut action);
            let flags = env.step_into(action_type, &action, &mut obs).expect("step");
            assert!(
                !flags.terminated,
                "{kind:?} step {step}: {:?}",
                flags.termination
            );
            assert!(
                obs.iter().all(|v| v.is_finite()),
                "{kind:?} step {step}: {obs:?}"
            );
        }
        // Limits hold (with a little give at the hard stops).
        for (dof, limit) in limits(&env).iter().enumerate() {
            let (min, max) = limit.unwrap();
            let q = f64::from(obs[dof]);
            assert!(
                q >= min - 2.0 && q <= max + 2.0,
                "{kind:?} dof {dof} at {q}"
            );
        }
    }
}

#[cfg(feature = "embedded")]
#[test]
fn arm6_runs_on_the_embedded_server_in_every_mode() {
    use clap::Parser;
    for action_type in ["torque", "position", "velocity"] {
        let config = gymfleet_load::Cli::try_parse_from([
            "gymfleet-load",
            "--quiet",
            "--model",
            "arm6",
            "--n-envs",
            "4",
            "--steps",
            "300",
            "--action-type",
            action_type,
            "--threads",
            "2",
        ])
        .unwrap()
        .resolve()
        .unwrap();
        let report = gymfleet_load::run(&config).unwrap();
        let r = &report.runs[0];
        assert_eq!(
            (r.errors, r.terminations, r.env_steps),
            (0, 0, 1200),
            "{action_type}: {r:?}"
        );
    }
}
