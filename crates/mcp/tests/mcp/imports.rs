//! An agent hands the adapter a MuJoCo description as text: the server converts it.

use serde_json::json;

use crate::Adapter;

const REACHER: &str = include_str!("../../../import/tests/data/reacher.xml");

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_mjcf_document_makes_an_env() {
    let adapter = Adapter::embedded().await;
    let created = adapter
        .ok(
            "create_robot_env",
            json!({"document": REACHER, "end_effector_ids": ["fingertip"]}),
        )
        .await;
    assert_eq!(created["action_dim"], 2, "{created}");
    let err = adapter
        .err(
            "create_robot_env",
            json!({"document": "<mujoco><worldbody><body><freejoint/></body></worldbody></mujoco>"}),
        )
        .await;
    assert!(
        err.contains("<freejoint>: a free joint (floating base) is not supported yet"),
        "{err}"
    );
    adapter.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn list_models_and_model_names() {
    let adapter = Adapter::embedded().await;
    let listed = adapter.ok("list_models", json!({})).await;
    assert_eq!(
        listed,
        json!({"models": []}),
        "the embedded server has no library"
    );
    let err = adapter
        .err("create_robot_env", json!({"model": "reacher"}))
        .await;
    assert!(
        err.contains("model: \"reacher\" is not in this server's model library"),
        "{err}"
    );
    let err = adapter.err("create_robot_env", json!({})).await;
    assert!(err.contains("document is required"), "{err}");
    let err = adapter
        .err(
            "batch_create_envs",
            json!({"n_envs": 2, "model": "a", "document": "{}"}),
        )
        .await;
    assert!(err.contains("give document or model, not both"), "{err}");
    adapter.stop().await;
}
