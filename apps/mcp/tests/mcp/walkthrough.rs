//! The user guide's walkthroughs over MCP: the pendulum (create, reset, a torque push, a
//! free swing, observe, close, then the unknown-id error) and the 2-DOF arm.

use serde_json::json;

use crate::{assert_clean_numbers, assert_close, doc, floats, Adapter, ARM2, PENDULUM};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pendulum_walkthrough() {
    let adapter = Adapter::embedded().await;
    let result = adapter
        .call(
            "create_robot_env",
            json!({
                "document": doc(PENDULUM),
                "end_effector_ids": ["arm"],
                "dt": 0.004166,
                "substeps": 4,
                "max_steps": 1000
            }),
        )
        .await;
    // The text is the guide's JSON, in the guide's order, with dt printed as given.
    let text = crate::text_of("create_robot_env", &result);
    assert!(
        text.starts_with(
            r#"{"env_id":"sim_1","num_joints":1,"action_dim":1,"observation_dim":9,"end_effector_ids":["arm"],"dt":0.004166,"substeps":4,"max_steps":1000,"joints":["#
        ),
        "{text}"
    );
    let created = crate::expect_ok("create_robot_env", result);
    let guide_fields = json!({
        "env_id": "sim_1",
        "num_joints": 1,
        "action_dim": 1,
        "observation_dim": 9,
        "end_effector_ids": ["arm"],
        "dt": 0.004166,
        "substeps": 4,
        "max_steps": 1000
    });
    for (key, value) in guide_fields.as_object().expect("object") {
        assert_eq!(&created[key], value, "{key} in {created}");
    }
    assert_eq!(created["joints"][0]["type"], "revolute");
    assert_eq!(created["joints"][0]["child"], "arm");

    let first = adapter.ok("gym_reset", json!({"env_id": "sim_1"})).await;
    assert_eq!(first["joint_positions"], json!([0.0]));
    assert_eq!(first["joint_velocities"], json!([0.0]));
    let poses = first["end_effector_poses"].as_array().expect("poses");
    assert_eq!(poses.len(), 1);
    assert_close(
        &floats(&poses[0]),
        &[10.0, 10.0, 25.0, 1.0, 0.0, 0.0, 0.0],
        1e-4,
    );

    let result = adapter
        .call(
            "gym_step",
            json!({"env_id": "sim_1", "action_type": "torque", "values": [2.0]}),
        )
        .await;
    let text = crate::text_of("gym_step", &result);
    assert!(
        text.starts_with(r#"{"observation":{"joint_positions":["#),
        "{text}"
    );
    assert!(
        text.contains(r#"]]},"reward":0.0,"done":false,"terminated":false"#),
        "{text}"
    );
    let pushed = crate::expect_ok("gym_step", result);
    let mut angle = floats(&pushed["observation"]["joint_positions"])[0];
    assert!(angle > 0.0, "positive torque raises the angle: {pushed}");
    assert!(floats(&pushed["observation"]["joint_velocities"])[0] > 0.0);
    assert_eq!(pushed["reward"], json!(0.0));
    assert_eq!(pushed["done"], json!(false));
    assert_eq!(pushed["terminated"], json!(false));
    assert_eq!(pushed["truncated"], json!(false));
    assert_clean_numbers(&pushed);

    for _ in 0..2 {
        let swing = adapter
            .ok(
                "gym_step",
                json!({"env_id": "sim_1", "action_type": "torque", "values": [0.0]}),
            )
            .await;
        let next = floats(&swing["observation"]["joint_positions"])[0];
        assert!(next > angle, "still swinging forward: {next} after {angle}");
        angle = next;
    }
    let mut last = json!(null);
    for _ in 0..100 {
        last = adapter
            .ok(
                "gym_step",
                json!({"env_id": "sim_1", "action_type": "torque", "values": [0]}),
            )
            .await;
        assert_eq!(last["done"], json!(false));
    }
    let observed = adapter.ok("gym_observe", json!({"env_id": "sim_1"})).await;
    assert_eq!(observed, last["observation"], "observe does not step");
    assert_ne!(observed["joint_positions"], first["joint_positions"]);

    let closed = adapter.ok("gym_close", json!({"env_id": "sim_1"})).await;
    assert_eq!(closed, json!({"env_id": "sim_1", "closed": true}));
    let err = adapter
        .err(
            "gym_step",
            json!({"env_id": "sim_1", "action_type": "torque", "values": [0.0]}),
        )
        .await;
    assert_eq!(
        err,
        "unknown env_id \"sim_1\": no open environment has this id (open: none). Create one \
         with create_robot_env."
    );
    adapter.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_dof_arm() {
    let adapter = Adapter::embedded().await;
    // The document may also be given as a string holding the JSON.
    let created = adapter
        .ok(
            "create_robot_env",
            json!({"document": ARM2, "end_effector_ids": ["forearm"], "seed": 7}),
        )
        .await;
    assert_eq!(created["env_id"], "sim_1");
    assert_eq!(
        (
            &created["num_joints"],
            &created["action_dim"],
            &created["observation_dim"]
        ),
        (&json!(2), &json!(2), &json!(11))
    );
    assert_eq!(
        (&created["substeps"], &created["max_steps"]),
        (&json!(5), &json!(1000))
    );
    let limits = &created["joints"][0]["limits"][0];
    assert_eq!(limits, &json!({"unit": "deg", "min": -90.0, "max": 90.0}));
    // The seed arm has no max_effort: each joint still tells an agent what torque is
    // sensible (twice what holds its subtree level), the shoulder more than the elbow.
    let bound = |j: usize| {
        created["joints"][j]["torque_bounds"][0]
            .as_f64()
            .expect("a bound")
    };
    assert!(
        bound(0) > bound(1) && bound(1) > 0.0 && bound(0) < 1e-2,
        "{created}"
    );

    let first = adapter.ok("gym_reset", json!({"env_id": "sim_1"})).await;
    assert_eq!(first["joint_positions"], json!([0.0, 0.0]));
    assert_eq!(
        first["end_effector_poses"].as_array().expect("poses").len(),
        1
    );

    let mut step = json!(null);
    for _ in 0..20 {
        step = adapter
            .ok(
                "gym_step",
                json!({"env_id": "sim_1", "action_type": "torque", "values": [0.5, -0.3]}),
            )
            .await;
    }
    let positions = floats(&step["observation"]["joint_positions"]);
    assert_eq!(positions.len(), 2);
    assert!(positions[0] > 0.0, "shoulder pushed forward: {positions:?}");
    assert!(positions[1] < 0.0, "elbow pushed back: {positions:?}");
    assert_eq!(floats(&step["observation"]["joint_velocities"]).len(), 2);
    assert_eq!(
        floats(&step["observation"]["end_effector_poses"][0]).len(),
        7
    );

    // Position targets in degrees, tracked by the PD controller.
    for _ in 0..240 {
        step = adapter
            .ok(
                "gym_step",
                json!({"env_id": "sim_1", "action_type": "position", "values": [20, -30]}),
            )
            .await;
    }
    let positions = floats(&step["observation"]["joint_positions"]);
    assert_close(&positions, &[20.0, -30.0], 3.0);
    assert_clean_numbers(&step["observation"]);

    adapter.ok("gym_close", json!({"env_id": "sim_1"})).await;

    // reset_noise: seeded random start poses, replayed by the same seed.
    let noisy = adapter
        .ok(
            "create_robot_env",
            json!({"document": ARM2, "end_effector_ids": ["forearm"], "reset_noise": 10}),
        )
        .await;
    let id = noisy["env_id"].as_str().expect("env id").to_string();
    let first = adapter
        .ok("gym_reset", json!({"env_id": id, "seed": 3}))
        .await;
    let again = adapter
        .ok("gym_reset", json!({"env_id": id, "seed": 3}))
        .await;
    let start = floats(&first["joint_positions"]);
    assert_eq!(first, again, "the same seed gives the same start");
    assert!(start[0] != 0.0 && start[0].abs() <= 10.0, "{start:?}");
    assert!(
        (-10.0..=0.0).contains(&start[1]),
        "elbow within its limits: {start:?}"
    );
    adapter.stop().await;
}
