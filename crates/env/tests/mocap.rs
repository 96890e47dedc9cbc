//! Mocap bodies: kinematic bodies moved by pose targets, pulling what a constraint joins to
//! them, and free bodies observed as MuJoCo observes a free joint.

use gymfleet_env::{ActionType, EnvConfig, EnvError, RobotEnv};
use serde_json::json;

/// A 100 mm arm on a hinge about y at the origin, lying along +x, its tip welded to a mocap
/// handle there.
fn arm_on_a_handle() -> serde_json::Value {
    json!({
        "parts": [
            {"name": "Base", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}},
            {"name": "Arm", "primitive": {"type": "cube", "size": {"x": 100, "y": 10, "z": 10}}},
            {"name": "Handle", "primitive": {"type": "sphere", "radius": 5}}
        ],
        "assembly": {
            "instances": [
                {"part": "Base", "name": "base", "position": {"x": -10, "y": -10, "z": -30}},
                {"part": "Arm", "name": "arm", "position": {"x": 0, "y": -5, "z": -5},
                 "collision": {"group": 0, "mask": 0}},
                {"part": "Handle", "name": "handle", "position": {"x": 100, "y": 0, "z": 0},
                 "mocap": true, "collision": {"group": 0, "mask": 0}}
            ],
            "joints": [
                {"type": "revolute", "name": "hinge", "parent": "base", "child": "arm",
                 "anchor": {"x": 0, "y": 0, "z": 0}, "axis": {"x": 0, "y": 1, "z": 0}},
                {"type": "fixed", "name": "grip", "parent": "handle", "child": "arm",
                 "anchor": {"x": 100, "y": 0, "z": 0}, "actuated": false}
            ]
        },
        "simulation": {"gravity": {"x": 0, "y": 0, "z": 0}}
    })
}

fn env(doc: &serde_json::Value) -> RobotEnv {
    RobotEnv::from_json(&doc.to_string(), EnvConfig::with_end_effectors(["handle"]))
        .expect("builds")
}

#[test]
fn a_mocap_target_pulls_what_is_welded_to_it() {
    let mut env = env(&arm_on_a_handle());
    assert_eq!(env.spec().mocap_bodies, ["handle"]);
    assert_eq!(env.spec().action_dim, 1);
    env.reset(None);
    // The handle goes up 10 mm over a step and stays: the arm turns about its hinge to
    // follow (a hinge about +y turns +x towards −z for a positive angle).
    let up = [100.0f32, 0.0, 10.0, 1.0, 0.0, 0.0, 0.0];
    env.set_mocap_pose("handle", up).expect("a target");
    let mut angle = 0.0;
    for _ in 0..240 {
        let r = env.step(ActionType::Torque, &[0.0]).expect("steps");
        angle = r.observation.joint_positions[0];
    }
    let expected = -(10.0f32 / 100.0).atan().to_degrees();
    assert!(
        (angle - expected).abs() < 0.2,
        "the arm turned to {angle}°, the handle's place asks {expected}°"
    );
    let handle = env.observe().end_effector_poses[0];
    assert!(
        (handle[2] - 10.0).abs() < 1e-3,
        "the handle is at {handle:?}"
    );
    // A reset puts the handle back where the document put it.
    env.reset(None);
    let handle = env.observe().end_effector_poses[0];
    assert!(handle[2].abs() < 1e-4, "after a reset: {handle:?}");
}

#[test]
fn mocap_targets_are_checked_before_anything_moves() {
    let mut env = env(&arm_on_a_handle());
    env.reset(None);
    let err = env
        .set_mocap_pose("hand", [0.0; 7])
        .expect_err("no such body");
    assert_eq!(
        err.to_string(),
        "unknown mocap body \"hand\" (known: \"handle\")"
    );
    let err = env
        .set_mocap_pose("handle", [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        .expect_err("no orientation");
    assert_eq!(
        err.to_string(),
        "mocap body \"handle\": the quaternion [qw, qx, qy, qz] is zero: no orientation"
    );
    let err = env
        .set_mocap_pose("handle", [f32::NAN, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
        .expect_err("not finite");
    assert_eq!(
        err.to_string(),
        "mocap body \"handle\": value 0 is NaN, expected a finite number"
    );
    let mut out = vec![0.0; env.spec().observation_dim];
    let err = env
        .step_with_mocap_into(ActionType::Torque, &[0.0], &[1.0; 6], &mut out)
        .expect_err("one value short");
    assert!(matches!(
        err,
        EnvError::MocapPosesLength {
            expected: 7,
            got: 6,
            bodies: 1
        }
    ));
    assert_eq!(
        err.to_string(),
        "mocap_poses: expected 7 values (7 per mocap body: x, y, z, qw, qx, qy, qz; the env has 1), or none to keep the targets, got 6"
    );
    // A bad action with good targets moves nothing either.
    let good = [100.0f32, 0.0, 50.0, 1.0, 0.0, 0.0, 0.0];
    env.step_with_mocap_into(ActionType::Torque, &[], &good, &mut out)
        .expect_err("no action");
    env.step(ActionType::Torque, &[0.0]).expect("steps");
    let handle = env.observe().end_effector_poses[0];
    assert!(
        handle[2].abs() < 1e-4,
        "the refused target moved it: {handle:?}"
    );
}
