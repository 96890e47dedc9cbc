//! `gym_save_state` and `gym_load_state`: an agent tries actions and takes them back, and
//! the env continues exactly as if they never happened; a bad state is a tool error.

use serde_json::{json, Value};

use crate::{doc, Adapter, ARM2};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_agent_tries_an_action_and_takes_it_back() {
    let adapter = Adapter::embedded().await;
    let created = adapter
        .ok(
            "create_robot_env",
            json!({"document": doc(ARM2), "end_effector_ids": ["forearm"]}),
        )
        .await;
    let env_id = created["env_id"].as_str().expect("env_id").to_string();
    adapter.ok("gym_reset", json!({"env_id": env_id})).await;
    let step = |values: Value| json!({"env_id": env_id, "action_type": "torque", "values": values});
    adapter.ok("gym_step", step(json!([0.02, -0.01]))).await;

    let saved = adapter
        .ok("gym_save_state", json!({"env_id": env_id}))
        .await;
    assert_eq!(saved["env_id"], env_id.as_str());
    let state = saved["state"].as_str().expect("base64 state").to_string();
    assert!(saved["bytes"].as_u64().expect("bytes") > 100, "{saved}");
    let here = adapter.ok("gym_observe", json!({"env_id": env_id})).await;

    // Try a hard push, then take it back: the observation is the saved one again.
    let tried = adapter.ok("gym_step", step(json!([0.5, 0.5]))).await;
    assert_ne!(tried["observation"], here, "the try moved the arm");
    let back = adapter
        .ok("gym_load_state", json!({"env_id": env_id, "state": state}))
        .await;
    assert_eq!(back, here);
    // The same gentle step from here twice gives the same result both times.
    let first = adapter.ok("gym_step", step(json!([0.01, 0.01]))).await;
    adapter
        .ok("gym_load_state", json!({"env_id": env_id, "state": state}))
        .await;
    let again = adapter.ok("gym_step", step(json!([0.01, 0.01]))).await;
    assert_eq!(first, again);

    let err = adapter
        .err(
            "gym_load_state",
            json!({"env_id": env_id, "state": "not base64!"}),
        )
        .await;
    assert!(
        err.starts_with("state: not the base64 text gym_save_state returns"),
        "{err}"
    );
    let err = adapter
        .err(
            "gym_load_state",
            json!({"env_id": env_id, "state": "R0ZTVAEAAAA="}),
        )
        .await;
    assert!(
        err.contains("shorter than a state's 12-byte header"),
        "{err}"
    );
    adapter.stop().await;
}
