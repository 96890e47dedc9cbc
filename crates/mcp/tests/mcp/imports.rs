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
