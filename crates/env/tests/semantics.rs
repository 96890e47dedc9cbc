//! Environment semantics of docs/design.md §2: metadata, the seed observations, signs,
//! action validation, truncation, reset, determinism and divergence.

mod common;

use common::*;
use gymfleet_env::{ActionType, EnvConfig, EnvError, RobotEnv, Termination};
use serde_json::{json, Value};

fn seed_env(doc: &str, ee: &str) -> RobotEnv {
    RobotEnv::from_json(doc, EnvConfig::with_end_effectors([ee])).unwrap()
}

#[test]
fn seed_pendulum_metadata_and_reset_observation() {
    let mut env = seed_env(PENDULUM, "arm");
    let spec = env.spec().clone();
    assert_eq!(
        (spec.num_joints, spec.action_dim, spec.observation_dim),
        (1, 1, 9)
    );
    assert_eq!(spec.joint_names, ["arm"]);
    assert_eq!((spec.substeps, spec.max_steps), (5, 1000));
    assert!((spec.dt - 1.0 / 240.0).abs() < 1e-12);
    let obs = env.reset(None);
    assert_eq!(obs.joint_positions, [0.0]);
    assert_eq!(obs.joint_velocities, [0.0]);
    let expected = [10.0, 10.0, 25.0, 1.0, 0.0, 0.0, 0.0];
    for (got, want) in obs.end_effector_poses[0].iter().zip(expected) {
        assert!(
            (got - want).abs() < 1e-4,
            "pose {:?}",
            obs.end_effector_poses[0]
        );
    }
}

#[test]
fn seed_arm_metadata_and_limits() {
    let env = seed_env(ARM2, "forearm");
    let spec = env.spec();
    assert_eq!(
        (spec.num_joints, spec.action_dim, spec.observation_dim),
        (2, 2, 11)
    );
    assert_eq!(spec.joint_names, ["upper", "forearm"]);
    let limits: Vec<_> = spec.dofs.iter().map(|d| d.limits.unwrap()).collect();
    for (got, want) in limits.iter().zip([[-90.0, 90.0], [-120.0, 0.0]]) {
        assert!((got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9);
    }
    // Exactly as the document wrote them, not -119.99999999999999 from a trip through SI.
    assert_eq!(limits, [[-90.0, 90.0], [-120.0, 0.0]]);
    // The forearm's centre of mass: x, y centred on the joint axis, z = 35 + 12.5.
    let pose = env.observe().end_effector_poses[0];
    assert!(pose[0].abs() < 1e-4 && pose[1].abs() < 1e-4 && (pose[2] - 47.5).abs() < 1e-4);
}

#[test]
fn positive_torque_about_y_increases_the_angle_and_moves_towards_plus_x() {
    let mut env = seed_env(PENDULUM, "arm");
    let obs = env.step(ActionType::Torque, &[1e-4]).unwrap().observation;
    assert!(obs.joint_positions[0] > 0.0 && obs.joint_velocities[0] > 0.0);
    assert!(
        obs.end_effector_poses[0][0] > 10.0,
        "x {}",
        obs.end_effector_poses[0][0]
    );
    let mut env = seed_env(PENDULUM, "arm");
    let obs = env.step(ActionType::Torque, &[-1e-4]).unwrap().observation;
    assert!(obs.joint_positions[0] < 0.0 && obs.end_effector_poses[0][0] < 10.0);
}

#[test]
fn observations_are_measured_not_targets() {
    let mut env = seed_env(ARM2, "forearm");
    let obs = env
        .step(ActionType::Position, &[45.0, -60.0])
        .unwrap()
        .observation;
    // One step of a PD motor cannot have reached the target.
    assert!(obs.joint_positions[0] > 0.0 && obs.joint_positions[0] < 45.0);
    assert!(obs.joint_positions[1] < 0.0 && obs.joint_positions[1] > -60.0);
}

#[test]
fn wrong_action_length_is_rejected_with_expected_and_got() {
    let mut env = seed_env(ARM2, "forearm");
    let err = env.step(ActionType::Torque, &[0.5]).unwrap_err();
    assert_eq!(
        err,
        EnvError::ActionLength {
            expected: 2,
            got: 1
        }
    );
    assert_eq!(
        err.to_string(),
        "values: expected 2 action values (one per actuated DOF), got 1"
    );
    // Nothing moved.
    assert_eq!(env.elapsed_steps(), 0);
}

#[test]
fn non_finite_actions_are_rejected_with_their_index() {
    let mut env = seed_env(ARM2, "forearm");
    let err = env
        .step(ActionType::Position, &[0.0, f32::NAN])
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "values[1]: expected a finite number, got NaN"
    );
    let err = env
        .step(ActionType::Velocity, &[f32::INFINITY, 0.0])
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "values[0]: expected a finite number, got inf"
    );
}

#[test]
fn unknown_action_types_are_rejected() {
    let err = "force".parse::<ActionType>().unwrap_err();
    assert_eq!(
        err.to_string(),
        "action_type: expected one of \"torque\", \"position\", \"velocity\", got \"force\""
    );
    assert_eq!(
        "velocity".parse::<ActionType>().unwrap(),
        ActionType::Velocity
    );
}

#[test]
fn unknown_end_effectors_and_bad_configs_are_rejected() {
    let err = RobotEnv::from_json(PENDULUM, EnvConfig::with_end_effectors(["arm", "hand"]))
        .err()
        .unwrap();
    assert_eq!(
        err.to_string(),
        "end_effector_ids[1]: unknown instance \"hand\" (known: \"base\", \"arm\")"
    );
    for (config, message) in [
        (
            // 0 is "the document's, else the default"; a negative step is an error.
            EnvConfig {
                dt: -0.01,
                ..EnvConfig::default()
            },
            "dt: expected a step length in (0, 1] s, got -0.01",
        ),
        (
            EnvConfig {
                dt: f64::NAN,
                ..EnvConfig::default()
            },
            "dt: expected a step length in (0, 1] s, got NaN",
        ),
        (
            EnvConfig {
                substeps: 0,
                ..EnvConfig::default()
            },
            "substeps: expected 1 to 1000 substeps, got 0",
        ),
        (
            EnvConfig {
                max_steps: 0,
                ..EnvConfig::default()
            },
            "max_steps: expected at least 1 step, got 0",
        ),
        (
            EnvConfig {
                pd_gains: Some(gymfleet_env::PdGains {
                    kp: vec![1.0, 2.0],
                    kd: vec![],
                }),
                ..EnvConfig::default()
            },
            "pd_gains.kp: expected 1 values (one per DOF), got 2",
        ),
        (
            EnvConfig {
                pd_gains: Some(gymfleet_env::PdGains {
                    kp: vec![],
                    kd: vec![-1.0],
                }),
                ..EnvConfig::default()
            },
            "pd_gains.kd: expected finite gains >= 0, got -1 at index 0",
        ),
    ] {
        let err = RobotEnv::from_json(PENDULUM, config).err().unwrap();
        assert_eq!(err.to_string(), message);
    }
}

#[test]
fn bad_documents_surface_their_json_path() {
    let doc = PENDULUM.replace("\"child\": \"arm\"", "\"child\": \"forarm\"");
    let err = RobotEnv::from_json(&doc, EnvConfig::default())
        .err()
        .unwrap();
    assert!(matches!(err, EnvError::Document(_)));
    assert!(
        err.to_string()
            .starts_with("assembly.joints[0].child: unknown instance \"forarm\""),
        "{err}"
    );
}

#[test]
fn truncated_at_max_steps_and_done_follows() {
    let config = EnvConfig {
        max_steps: 3,
        ..EnvConfig::with_end_effectors(["arm"])
    };
    let mut env = RobotEnv::from_json(PENDULUM, config).unwrap();
    for i in 1..=4u32 {
        let flags = env.step(ActionType::Torque, &[0.0]).unwrap().flags;
        assert_eq!(flags.truncated, i >= 3, "step {i}");
        assert!(!flags.terminated);
        assert_eq!(flags.done(), i >= 3);
        assert_eq!(flags.reward, 0.0);
    }
    env.reset(None);
    assert_eq!(env.elapsed_steps(), 0);
    assert!(
        !env.step(ActionType::Torque, &[0.0])
            .unwrap()
            .flags
            .truncated
    );
}

fn rollout(env: &mut RobotEnv, steps: usize) -> Vec<Vec<f32>> {
    (0..steps)
        .map(|i| {
            let t = i as f32 * 0.1;
            let action = [2e-4 * t.sin(), -1e-4 * (1.3 * t).cos()];
            let kind = [
                ActionType::Torque,
                ActionType::Position,
                ActionType::Velocity,
            ][i / 40 % 3];
            let action = if kind == ActionType::Torque {
                action
            } else {
                [30.0 * t.sin(), -40.0]
            };
            env.step(kind, &action).unwrap().observation.to_flat()
        })
        .collect()
}

fn bits(rows: &[Vec<f32>]) -> Vec<u32> {
    rows.iter().flatten().map(|v| v.to_bits()).collect()
}

#[test]
fn same_document_and_actions_give_bitwise_identical_observations() {
    let mut a = seed_env(ARM2, "forearm");
    let mut b = seed_env(ARM2, "forearm");
    assert_eq!(bits(&rollout(&mut a, 200)), bits(&rollout(&mut b, 200)));
}

#[test]
fn reset_restores_the_initial_state_exactly() {
    let mut env = seed_env(ARM2, "forearm");
    let first = env.reset(Some(7)).to_flat();
    let run1 = rollout(&mut env, 150);
    let again = env.reset(Some(7)).to_flat();
    assert_eq!(first, again);
    let run2 = rollout(&mut env, 150);
    assert_eq!(bits(&run1), bits(&run2), "replay after reset differs");
    // A clone is an independent env in the same state.
    let mut clone = env.clone();
    assert_eq!(bits(&rollout(&mut env, 20)), bits(&rollout(&mut clone, 20)));
}

#[test]
fn a_physics_blow_up_terminates_with_a_finite_observation() {
    let mut env = seed_env(PENDULUM, "arm");
    let before = env.observe().to_flat();
    let result = env.step(ActionType::Torque, &[1e35]).unwrap();
    assert!(result.flags.terminated);
    assert_eq!(result.flags.termination, Some(Termination::PhysicsDiverged));
    let obs = result.observation.to_flat();
    assert!(obs.iter().all(|v| v.is_finite()));
    assert_eq!(obs, before, "the last finite observation is returned");
    assert!(env.observe().to_flat().iter().all(|v| v.is_finite()));
    let err = env.step(ActionType::Torque, &[0.0]).unwrap_err();
    assert_eq!(err, EnvError::NeedsReset);
    // Reset brings it back.
    env.reset(None);
    assert!(
        !env.step(ActionType::Torque, &[0.0])
            .unwrap()
            .flags
            .terminated
    );
}

fn two_bodies(joint: Value) -> Value {
    json!({
        "parts": [
            {"name": "Base", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 5}}},
            {"name": "Link", "primitive": {"type": "cube", "size": {"x": 4, "y": 4, "z": 40}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Base", "name": "base"},
                {"part": "Link", "name": "link", "position": {"x": 8, "y": 8, "z": 5}}
            ],
            "joints": [joint]
        }
    })
}

#[test]
fn ball_joint_reports_a_rotation_vector_in_degrees() {
    let doc = two_bodies(json!({"type": "ball", "parent": "base", "child": "link",
                                "anchor": {"x": 10, "y": 10, "z": 5}}));
    let mut env = env(&doc, &["link"]);
    assert_eq!(
        (
            env.spec().action_dim,
            env.spec().observation_dim,
            env.spec().num_joints
        ),
        (3, 13, 1)
    );
    // A torque about +X tips the link about +X: the rotation vector grows along X only.
    let obs = step(&mut env, ActionType::Torque, &[1e-4, 0.0, 0.0]);
    assert!(
        obs[0] > 0.0 && obs[1].abs() < 1e-3 && obs[2].abs() < 1e-3,
        "{obs:?}"
    );
    assert!(obs[3] > 0.0, "angular velocity about X {}", obs[3]);
    // Rotating about +X moves the top of the link towards −Y.
    assert!(obs[7] < 10.0);
    // A position target is approached (gravity pulls it further; it must move).
    let mut env2 = env.clone();
    env2.reset(None);
    let mut last = Vec::new();
    for _ in 0..60 {
        last = step(&mut env2, ActionType::Position, &[0.0, 10.0, 0.0]);
    }
    assert!(
        last[1] > 5.0,
        "ball did not turn towards the target: {last:?}"
    );
}

#[test]
fn cylindrical_joint_has_slide_then_turn() {
    let doc = two_bodies(
        json!({"type": "cylindrical", "parent": "base", "child": "link",
                                "anchor": {"x": 10, "y": 10, "z": 5}, "axis": {"x": 0, "y": 0, "z": 1}}),
    );
    let mut env = env(&doc, &["link"]);
    assert_eq!((env.spec().action_dim, env.spec().observation_dim), (2, 11));
    // Push up with more than the weight, and twist.
    let weight = 1000.0 * 0.004 * 0.004 * 0.04 * 9.81;
    let obs = step(&mut env, ActionType::Torque, &[(3.0 * weight) as f32, 1e-5]);
    assert!(obs[0] > 0.0, "slide {}", obs[0]);
    assert!(obs[1] > 0.0, "turn {}", obs[1]);
}

#[test]
fn fixed_joints_have_no_dof_and_carry_their_child() {
    let mut doc = two_bodies(
        json!({"type": "revolute", "parent": "base", "child": "link",
                                    "anchor": {"x": 10, "y": 10, "z": 5}, "axis": {"x": 0, "y": 1, "z": 0}}),
    );
    doc["parts"]
        .as_array_mut()
        .unwrap()
        .push(json!({"name": "Tip", "primitive": {"type": "sphere", "radius": 3}}));
    doc["assembly"]["instances"]
        .as_array_mut()
        .unwrap()
        .push(json!({"part": "Tip", "name": "tip", "position": {"x": 10, "y": 10, "z": 48}}));
    doc["assembly"]["joints"]
        .as_array_mut()
        .unwrap()
        .push(json!({"type": "fixed", "parent": "link", "child": "tip"}));
    let mut env = env(&doc, &["tip"]);
    assert_eq!(
        (
            env.spec().num_joints,
            env.spec().action_dim,
            env.spec().observation_dim
        ),
        (1, 1, 9)
    );
    let before = env.observe().end_effector_poses[0];
    let mut obs = Vec::new();
    for _ in 0..10 {
        obs = step(&mut env, ActionType::Torque, &[1e-4]);
    }
    // The tip turned with the link: 43 mm above the pivot at the link's angle.
    let theta = f64::from(obs[0]).to_radians();
    assert!(theta > 0.01);
    let x = 10.0 + 43.0 * theta.sin();
    assert!(
        (f64::from(obs[2]) - x).abs() < 1e-2,
        "tip x {} vs {x}, before {before:?}",
        obs[2]
    );
}

#[test]
fn instance_rotation_and_materials_change_the_physics() {
    // Heavier material, same shape: the same torque turns it less.
    let mut heavy = two_bodies(
        json!({"type": "revolute", "parent": "base", "child": "link",
                                      "anchor": {"x": 10, "y": 10, "z": 5}, "axis": {"x": 0, "y": 1, "z": 0}}),
    );
    heavy["materials"] = json!({"steel": {"density": 7850}});
    heavy["parts"][1]["material"] = json!("steel");
    let light = two_bodies(heavy["assembly"]["joints"][0].clone());
    let (mut h, mut l) = (env(&heavy, &["link"]), env(&light, &["link"]));
    let (oh, ol) = (
        step(&mut h, ActionType::Torque, &[1e-4]),
        step(&mut l, ActionType::Torque, &[1e-4]),
    );
    let ratio = f64::from(ol[1]) / f64::from(oh[1]);
    assert!((ratio - 7.85).abs() < 0.05, "velocity ratio {ratio}");

    // A link rotated 90° about X lies along −Y: its centre of mass moves accordingly.
    let mut rotated = light.clone();
    rotated["assembly"]["instances"][1]["rotation"] = json!({"x": 90, "y": 0, "z": 0});
    let env = env(&rotated, &["link"]);
    let pose = env.observe().end_effector_poses[0];
    // Local centre (2, 2, 20) rotated by +90° about X is (2, −20, 2); plus (8, 8, 5).
    for (got, want) in pose[..3].iter().zip([10.0, -12.0, 7.0]) {
        assert!((got - want).abs() < 1e-3, "{pose:?}");
    }
}
