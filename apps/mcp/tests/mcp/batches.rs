//! Batches over MCP: the guide's 16-env arm batch with one action array per env and
//! results grouped by env, reset, same-step autoreset, and close.

use serde_json::{json, Value};

use crate::{assert_clean_numbers, doc, floats, Adapter, ARM2};

/// The guide's action shape: one `[shoulder, elbow]` pair per env.
fn actions(n: usize) -> Value {
    let rows: Vec<Value> = (0..n)
        .map(|i| {
            if i % 2 == 0 {
                json!([0.5, -0.3])
            } else {
                json!([0.1, 0.2])
            }
        })
        .collect();
    Value::Array(rows)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sixteen_env_batch() {
    let adapter = Adapter::embedded().await;
    let created = adapter
        .ok(
            "batch_create_envs",
            json!({"document": doc(ARM2), "n_envs": 16, "end_effector_ids": ["forearm"]}),
        )
        .await;
    let guide_fields = json!({
        "batch_id": "batch_1",
        "n_envs": 16,
        "action_dim": 2,
        "observation_dim": 11,
        "num_joints": 2
    });
    for (key, value) in guide_fields.as_object().expect("object") {
        assert_eq!(&created[key], value, "{key} in {created}");
    }
    assert_eq!(created["autoreset"], "disabled");

    let reset = adapter
        .ok("batch_reset", json!({"batch_id": "batch_1", "seed": 3}))
        .await;
    let observations = reset["observations"].as_array().expect("observations");
    assert_eq!(observations.len(), 16);
    for obs in observations {
        assert_eq!(obs["joint_positions"], json!([0.0, 0.0]));
        assert_eq!(
            obs["end_effector_poses"].as_array().expect("poses").len(),
            1
        );
    }

    let mut step = json!(null);
    for _ in 0..10 {
        step = adapter
            .ok(
                "batch_step",
                json!({"batch_id": "batch_1", "action_type": "torque", "actions": actions(16)}),
            )
            .await;
    }
    assert_eq!(step["batch_id"], "batch_1");
    let results = step["results"].as_array().expect("results grouped by env");
    assert_eq!(results.len(), 16);
    for (i, result) in results.iter().enumerate() {
        assert_eq!(result["env_index"], json!(i));
        assert_eq!(result["reward"], json!(0.0));
        assert_eq!(result["done"], json!(false));
        assert_eq!(result["terminated"], json!(false));
        assert_eq!(result["truncated"], json!(false));
        let observation = &result["observation"];
        assert_eq!(floats(&observation["joint_positions"]).len(), 2);
        assert_eq!(floats(&observation["joint_velocities"]).len(), 2);
        assert_eq!(floats(&observation["end_effector_poses"][0]).len(), 7);
        // Same actions, same physics: every even env matches env 0, every odd env env 1.
        assert_eq!(observation, &results[i % 2]["observation"], "env {i}");
    }
    assert_ne!(results[0]["observation"], results[1]["observation"]);
    let shoulder = floats(&results[0]["observation"]["joint_positions"])[0];
    assert!(shoulder > 0.0, "positive shoulder torque: {shoulder}");
    assert_clean_numbers(&step);

    let closed = adapter
        .ok("batch_close", json!({"batch_id": "batch_1"}))
        .await;
    assert_eq!(closed, json!({"batch_id": "batch_1", "closed": true}));
    let err = adapter
        .err(
            "batch_step",
            json!({"batch_id": "batch_1", "action_type": "torque", "actions": actions(16)}),
        )
        .await;
    assert_eq!(
        err,
        "unknown batch_id \"batch_1\": no open batch has this id (open: none). Create one \
         with batch_create_envs."
    );
    adapter.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn same_step_autoreset_reports_the_final_observation() {
    let adapter = Adapter::embedded().await;
    let created = adapter
        .ok(
            "batch_create_envs",
            json!({
                "document": doc(ARM2),
                "n_envs": 2,
                "end_effector_ids": ["forearm"],
                "max_steps": 2,
                "autoreset": "same_step"
            }),
        )
        .await;
    assert_eq!(created["autoreset"], "same_step");
    let args = json!({
        "batch_id": "batch_1",
        "action_type": "velocity",
        "actions": [[30, -30], [30, -30]]
    });
    let first = adapter.ok("batch_step", args.clone()).await;
    assert_eq!(first["results"][0]["done"], json!(false));
    assert!(first["results"][0].get("final_observation").is_none());
    let second = adapter.ok("batch_step", args).await;
    for result in second["results"].as_array().expect("results") {
        assert_eq!(result["truncated"], json!(true), "{result}");
        assert_eq!(result["done"], json!(true), "{result}");
        // Reset within the step: the observation is the fresh start, the final one is not.
        assert_eq!(result["observation"]["joint_positions"], json!([0.0, 0.0]));
        let last = floats(&result["final_observation"]["joint_positions"]);
        assert!(last[0] > 0.0, "{result}");
    }
    adapter
        .ok("batch_close", json!({"batch_id": "batch_1"}))
        .await;
    adapter.stop().await;
}

/// A terms task over MCP: a forward-velocity term on the pendulum's hinge, the control
/// cost and a healthy range, each step reporting every term's value by name, single and
/// batched; the pendulum tipping past 30° ends the episode as `unhealthy`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn terms_tasks_report_each_term_and_end_unhealthy_episodes() {
    let adapter = Adapter::embedded().await;
    let task = json!({
        "terms": {
            "terms": [
                {"name": "swing", "weight": 1.0, "velocity": {"joint": "arm"}},
                {"name": "effort", "weight": -2.0, "ctrl_cost": {}},
                {"name": "alive", "healthy": {}}
            ],
            "healthy": {"ranges": [{"of": {"joint": "arm"}, "min": -30, "max": 30}]}
        }
    });
    adapter
        .ok(
            "create_robot_env",
            json!({"document": doc(crate::PENDULUM), "task": task}),
        )
        .await;
    let mut ended = false;
    for _ in 0..400 {
        let step = adapter
            .ok(
                "gym_step",
                json!({"env_id": "sim_1", "action_type": "torque", "values": [0.0002]}),
            )
            .await;
        let terms = &step["terms"];
        let (swing, effort, alive) = (
            terms["swing"].as_f64().expect("swing"),
            terms["effort"].as_f64().expect("effort"),
            terms["alive"].as_f64().expect("alive"),
        );
        assert!((effort - 4e-8).abs() < 1e-12, "{effort}");
        let reward = step["reward"].as_f64().expect("reward");
        assert!((reward - (swing - 2.0 * effort + alive)).abs() < 1e-3 * swing.abs().max(1.0));
        if step["terminated"] == true {
            assert_eq!(step["termination_reason"], "unhealthy");
            assert_eq!(alive, 0.0);
            ended = true;
            break;
        }
        assert_eq!(alive, 1.0);
    }
    assert!(ended, "the pendulum never tipped past 30°");
    adapter
        .ok(
            "batch_create_envs",
            json!({"document": doc(crate::PENDULUM), "n_envs": 2, "task": task}),
        )
        .await;
    let step = adapter
        .ok(
            "batch_step",
            json!({"batch_id": "batch_1", "action_type": "torque", "actions": [[0.0001], [0.0]]}),
        )
        .await;
    let results = step["results"].as_array().expect("results");
    let effort = results[0]["terms"]["effort"].as_f64().expect("effort");
    assert!((effort - 1e-8).abs() < 1e-13, "{effort}");
    assert_eq!(results[1]["terms"]["effort"].as_f64(), Some(0.0));
    assert_eq!(results[1]["terms"]["alive"].as_f64(), Some(1.0));
    adapter.stop().await;
}

/// A task over MCP: the guide's reaching loop (target [20, 0, 40] mm, reward −distance)
/// as one `task` field, a batch that ends episodes with `goal_reached`, and randomised
/// masses.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tasks_compute_rewards_and_show_the_target() {
    let adapter = Adapter::embedded().await;
    let pendulum = crate::PENDULUM;
    adapter
        .ok(
            "create_robot_env",
            json!({
                "document": doc(pendulum),
                "end_effector_ids": ["arm"],
                "task": {"reach": {"end_effector": "arm", "target": {"x": 20, "y": 0, "z": 40}}}
            }),
        )
        .await;
    let step = adapter
        .ok(
            "gym_step",
            json!({"env_id": "sim_1", "action_type": "torque", "values": [0.0]}),
        )
        .await;
    assert_eq!(step["observation"]["target"], json!([20.0, 0.0, 40.0]));
    let reward = step["reward"].as_f64().expect("reward");
    assert!((reward + 425f64.sqrt()).abs() < 1e-3, "{reward}");

    adapter
        .ok(
            "batch_create_envs",
            json!({
                "document": doc(pendulum),
                "n_envs": 2,
                "task": {
                    "reach": {"end_effector": "arm", "target": {"x": 10, "y": 10, "z": 25},
                              "success_radius": 1, "terminate_on_success": true},
                    "action_cost": 0.5
                }
            }),
        )
        .await;
    let step = adapter
        .ok(
            "batch_step",
            json!({"batch_id": "batch_1", "action_type": "torque", "actions": [[0.0], [0.0]]}),
        )
        .await;
    for result in step["results"].as_array().expect("results") {
        assert_eq!(result["termination_reason"], "goal_reached");
        assert_eq!(result["observation"]["target"], json!([10.0, 10.0, 25.0]));
    }
    // Randomised masses: a 2× heavier arm turns half as far under the same push.
    let mut turns = Vec::new();
    for factor in [1.0, 2.0] {
        let created = adapter
            .ok(
                "create_robot_env",
                json!({
                    "document": doc(pendulum),
                    "randomize": {"mass_scale": {"min": factor, "max": factor}}
                }),
            )
            .await;
        let env_id = created["env_id"].as_str().expect("env_id").to_string();
        let step = adapter
            .ok(
                "gym_step",
                json!({"env_id": env_id, "action_type": "torque", "values": [1e-4]}),
            )
            .await;
        turns.push(
            step["observation"]["joint_positions"][0]
                .as_f64()
                .expect("angle"),
        );
    }
    assert!((turns[1] / turns[0] - 0.5).abs() < 0.01, "{turns:?}");
    let error = adapter
        .call(
            "create_robot_env",
            json!({"document": doc(pendulum), "task": {"reach": {"end_effector": "arm"}, "upright": {"instance": "arm", "max_tilt_deg": 10}}}),
        )
        .await;
    let text = crate::text_of("create_robot_env", &error);
    assert!(
        text.contains("task: give exactly one of \"reach\", \"track\", \"upright\" or \"terms\""),
        "{text}"
    );
}
