//! Every error case is a tool error (`isError: true`) whose message says how to fix the
//! call, and the adapter keeps answering after each one.

use serde_json::{json, Value};

use crate::{doc, Adapter, ARM2, PENDULUM};

/// Asserts that the adapter still answers: `sim_1` can be observed.
async fn still_answers(adapter: &Adapter) {
    let obs = adapter.ok("gym_observe", json!({"env_id": "sim_1"})).await;
    assert_eq!(obs["joint_positions"], json!([0.0]));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn errors_are_tool_errors_an_agent_can_act_on() {
    let adapter = Adapter::embedded().await;
    adapter
        .ok(
            "create_robot_env",
            json!({"document": doc(PENDULUM), "end_effector_ids": ["arm"]}),
        )
        .await;
    adapter
        .ok(
            "create_robot_env",
            json!({"document": doc(ARM2), "end_effector_ids": ["forearm"]}),
        )
        .await;
    adapter
        .ok(
            "batch_create_envs",
            json!({"document": doc(ARM2), "n_envs": 16}),
        )
        .await;

    // A bad document: the server's JSON path, passed through.
    let typo = PENDULUM.replace(r#""child": "arm""#, r#""child": "arn""#);
    let err = adapter
        .err(
            "create_robot_env",
            json!({"document": doc(&typo), "end_effector_ids": ["arm"]}),
        )
        .await;
    assert_eq!(
        err,
        "invalid argument: assembly.joints[0].child: unknown instance \"arn\" (known: \"arm\", \
         \"base\")"
    );
    still_answers(&adapter).await;
    let err = adapter
        .err("create_robot_env", json!({"document": "{ not json"}))
        .await;
    assert!(err.starts_with("invalid argument: document"), "{err}");
    let err = adapter
        .err(
            "batch_create_envs",
            json!({"document": [1, 2], "n_envs": 2}),
        )
        .await;
    assert!(
        err.starts_with("document must be the assembly document"),
        "{err}"
    );
    assert!(err.ends_with("got an array"), "{err}");
    let err = adapter
        .err(
            "create_robot_env",
            json!({"document": doc(PENDULUM), "end_effector_ids": ["hand"]}),
        )
        .await;
    assert!(err.contains("end_effector_ids[0]"), "{err}");
    assert!(err.contains("unknown instance \"hand\""), "{err}");
    still_answers(&adapter).await;

    // Unknown ids, named; a batch id where an env id belongs, and back.
    let step = |env_id: &str, values: Value| json!({"env_id": env_id, "action_type": "torque", "values": values});
    let err = adapter.err("gym_step", step("sim_9", json!([0.0]))).await;
    assert_eq!(
        err,
        "unknown env_id \"sim_9\": no open environment has this id (open: sim_1, sim_2). \
         Create one with create_robot_env."
    );
    let err = adapter.err("gym_reset", json!({"env_id": "batch_1"})).await;
    assert!(
        err.starts_with("\"batch_1\" is a batch_id, not an env_id"),
        "{err}"
    );
    let err = adapter
        .err("batch_reset", json!({"batch_id": "sim_2"}))
        .await;
    assert!(
        err.starts_with("\"sim_2\" is an env_id, not a batch_id"),
        "{err}"
    );
    still_answers(&adapter).await;

    // Wrong action counts: expected vs got, checked before any call.
    let err = adapter
        .err("gym_step", step("sim_1", json!([1.0, 2.0])))
        .await;
    assert_eq!(err, "sim_1 expects 1 action value (action_dim), got 2");
    let err = adapter
        .err("gym_step", step("sim_2", json!([1, 2, 3])))
        .await;
    assert_eq!(err, "sim_2 expects 2 action values (action_dim), got 3");
    let mut actions = vec![json!([0.0, 0.0]); 16];
    actions[4] = json!([0.0, 0.0, 0.0]);
    let batch_step = |actions: Value| json!({"batch_id": "batch_1", "action_type": "torque", "actions": actions});
    let err = adapter.err("batch_step", batch_step(json!(actions))).await;
    assert_eq!(err, "batch_1 expects 16 arrays of 2 values; array 4 has 3");
    let err = adapter
        .err("batch_step", batch_step(json!(actions[..15])))
        .await;
    assert_eq!(
        err,
        "batch_1 expects 16 arrays of 2 values (one array per env, action_dim values each); \
         got 15 arrays"
    );
    still_answers(&adapter).await;

    // Non-finite values (JSON has no NaN: agents send strings or null).
    let err = adapter.err("gym_step", step("sim_1", json!(["NaN"]))).await;
    assert_eq!(
        err,
        "values[0] is NaN; every action value must be a finite number"
    );
    let err = adapter
        .err("gym_step", step("sim_2", json!([0.0, null])))
        .await;
    assert_eq!(
        err,
        "values[1] is null; every action value must be a finite number"
    );
    let err = adapter.err("gym_step", step("sim_1", json!([1e39]))).await;
    assert!(err.starts_with("values[0] = 1e39 is out of range"), "{err}");
    actions[4] = json!([0.0, "-Infinity"]);
    let err = adapter.err("batch_step", batch_step(json!(actions))).await;
    assert_eq!(
        err,
        "actions[4][1] is infinite (-inf); every action value must be a finite number"
    );
    still_answers(&adapter).await;

    // Arguments that do not parse are tool errors too.
    let err = adapter
        .err(
            "gym_step",
            json!({"env_id": "sim_1", "action_type": "torq", "values": [0.0]}),
        )
        .await;
    assert!(err.contains("unknown variant `torq`"), "{err}");
    assert!(err.contains("torque"), "{err}");
    let err = adapter.err("gym_observe", json!({})).await;
    assert!(err.contains("missing field `env_id`"), "{err}");
    still_answers(&adapter).await;
    adapter.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_unreachable_server_is_named_and_the_adapter_keeps_answering() {
    let adapter = Adapter::spawn(&["--server", "127.0.0.1:1"]).await;
    let args = json!({"document": doc(PENDULUM), "end_effector_ids": ["arm"]});
    for _ in 0..2 {
        let err = adapter.err("create_robot_env", args.clone()).await;
        // The words every gymfleet client uses, with the adapter's way of pointing elsewhere.
        assert!(
            err.starts_with("cannot connect to the gymfleet server at 127.0.0.1:1: "),
            "{err}"
        );
        assert!(
            err.ends_with(
                ". Is the server running? To use another one, pass --server ADDR to the \
                 adapter (or set GYMFLEET_SERVER); gymfleet-server --listen ADDR starts one."
            ),
            "{err}"
        );
    }
    let err = adapter
        .err(
            "batch_create_envs",
            json!({"document": doc(ARM2), "n_envs": 4}),
        )
        .await;
    assert!(
        err.starts_with("cannot connect to the gymfleet server at 127.0.0.1:1"),
        "{err}"
    );
    let tools = adapter
        .session
        .list_all_tools()
        .await
        .expect("still answers");
    assert_eq!(tools.len(), 14);
    adapter.stop().await;
}
