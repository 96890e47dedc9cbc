//! The seed walkthroughs: the pendulum (create, reset, torque, free swing, observe,
//! close, then NOT_FOUND) and the 2-DOF arm.

use gymfleet_client::{ActionType, EnvOptions};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};

use crate::{assert_close, assert_not_found, bits};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pendulum_walkthrough() {
    let server = TestServer::start_default().await;
    let client = server.client().await;

    let env = client
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await
        .expect("create the pendulum");
    let layout = env.info().observation_layout.clone();
    let info = env.info().clone();
    assert_eq!(
        (info.num_joints, info.action_dim, info.observation_dim),
        (1, 1, 9)
    );
    let n = info.env_id.strip_prefix("sim_").expect("env id is sim_<n>");
    n.parse::<u64>().expect("env id ends in a number");
    assert_eq!(info.end_effector_ids, ["arm"]);
    assert_eq!((info.substeps, info.max_steps), (5, 1000));
    assert!((info.dt - 1.0 / 240.0).abs() < 1e-12);
    assert_eq!(info.joints.len(), 1);
    assert_eq!(info.joints[0].joint_type, "revolute");
    assert_eq!(
        (
            info.joints[0].parent.as_str(),
            info.joints[0].child.as_str()
        ),
        ("base", "arm")
    );
    assert_eq!(info.joints[0].limits[0].unit, "deg");

    let first = env.reset(None).await.expect("reset");
    assert_close(&first.joint_positions, &[0.0], 1e-4);
    assert_close(&first.joint_velocities, &[0.0], 1e-4);
    assert_eq!(first.end_effector_poses.len(), 1);
    assert_close(
        &first.end_effector_poses[0],
        &[10.0, 10.0, 25.0, 1.0, 0.0, 0.0, 0.0],
        1e-4,
    );

    let pushed = env
        .step(ActionType::Torque, &[2.0])
        .await
        .expect("torque step");
    let angle = pushed.observation.joint_positions[0];
    assert!(
        angle > 0.0,
        "positive torque increases the angle, got {angle}"
    );
    assert!(pushed.observation.joint_velocities[0] > 0.0);
    assert_eq!(pushed.episode_step, 1);
    assert!(!pushed.done && !pushed.terminated && !pushed.truncated);
    assert_eq!(pushed.reward, 0.0);

    // Free swing: the upright pendulum keeps falling the way it was pushed.
    let mut last = pushed;
    for step in 2..=60u32 {
        let next = env
            .step(ActionType::Torque, &[0.0])
            .await
            .expect("free step");
        assert_eq!(next.episode_step, step);
        assert!(next
            .observation
            .to_flat(&layout)
            .iter()
            .all(|v| v.is_finite()));
        assert!(
            next.observation.joint_positions[0] > last.observation.joint_positions[0],
            "the pendulum keeps falling"
        );
        last = next;
    }

    let observed = env.observe().await.expect("observe");
    assert_eq!(
        bits(&observed.to_flat(&layout)),
        bits(&last.observation.to_flat(&layout))
    );

    env.close().await.expect("close");
    let id = info.env_id.as_str();
    let err = env.step(ActionType::Torque, &[0.0]).await.unwrap_err();
    assert_not_found(&err, &[id]);
    assert_not_found(&env.observe().await.unwrap_err(), &[id]);
    assert_not_found(&env.reset(None).await.unwrap_err(), &[id]);
    assert_not_found(&env.close().await.unwrap_err(), &[id]);

    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn arm2_walkthrough() {
    let server = TestServer::start_default().await;
    let client = server.client().await;

    let env = client
        .create_env(EnvOptions::new(ARM2).end_effectors(["forearm"]).seed(3))
        .await
        .expect("create the arm");
    let layout = env.info().observation_layout.clone();
    let info = env.info();
    assert_eq!(
        (info.num_joints, info.action_dim, info.observation_dim),
        (2, 2, 11)
    );
    assert_eq!(info.joints.len(), 2);
    // Limits round-trip through radians inside the physics: compare within 1e-9 deg.
    let limits: Vec<[f64; 2]> = info
        .joints
        .iter()
        .map(|j| [j.limits[0].min.expect("min"), j.limits[0].max.expect("max")])
        .collect();
    for (got, want) in limits.iter().zip([[-90.0, 90.0], [-120.0, 0.0]]) {
        assert!(
            (got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9,
            "{limits:?}"
        );
    }
    assert_eq!(info.joints[1].parent, "upper");

    let first = env.reset(Some(3)).await.expect("reset");
    assert_close(&first.joint_positions, &[0.0, 0.0], 1e-4);
    assert_close(&first.joint_velocities, &[0.0, 0.0], 1e-4);
    assert_eq!(first.end_effector_poses.len(), 1);

    for _ in 0..20 {
        let step = env
            .step(ActionType::Position, &[30.0, -30.0])
            .await
            .expect("step");
        assert_eq!(step.observation.to_flat(&layout).len(), 11);
    }
    let moved = env.observe().await.expect("observe");
    assert!(
        moved.joint_positions[0] > 0.0,
        "tracking +30 deg: {moved:?}"
    );
    assert!(
        moved.joint_positions[1] < 0.0,
        "tracking -30 deg: {moved:?}"
    );

    // Reset is exact.
    let again = env.reset(None).await.expect("reset again");
    assert_eq!(bits(&again.to_flat(&layout)), bits(&first.to_flat(&layout)));
    env.close().await.expect("close");
    server.stop().await.expect("clean shutdown");
}

/// A closed chain through the server: the four-bar's joints are described in document
/// order with their own parent and child, an unobserved loop-closing joint in their midst
/// takes no entry, and the rocker turns with the driven crank.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_four_bar_with_an_unobserved_loop_joint_is_described_joint_by_joint() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let mut doc: serde_json::Value =
        serde_json::from_str(include_str!("../../../models/fourbar.json")).expect("json");
    // The closing pin first and unobserved: a constraint only.
    let joints = doc["assembly"]["joints"].as_array_mut().expect("joints");
    let mut pin = joints.pop().expect("the pin");
    pin["observed"] = serde_json::json!(false);
    joints.insert(1, pin);
    let env = client
        .create_env(EnvOptions::new(doc.to_string()).end_effectors(["coupler"]))
        .await
        .expect("create the four-bar");
    let info = env.info().clone();
    let described: Vec<(&str, &str, &str)> = info
        .joints
        .iter()
        .map(|j| (j.name.as_str(), j.parent.as_str(), j.child.as_str()))
        .collect();
    assert_eq!(
        described,
        [
            ("crank", "frame", "crank"),
            ("elbow", "crank", "coupler"),
            ("rocker", "frame", "rocker")
        ]
    );
    assert_eq!(info.action_dim, 1);
    env.reset(None).await.expect("reset");
    let mut rocker = 0.0;
    for _ in 0..30 {
        let stepped = env
            .step(ActionType::Velocity, &[360.0])
            .await
            .expect("step");
        rocker = stepped.observation.joint_positions[2];
    }
    assert!(
        rocker.abs() > 1.0,
        "the rocker turns with the crank: {rocker}"
    );
}
