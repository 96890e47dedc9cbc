//! An agent hands the adapter a MuJoCo or ROS description as text (with its mesh files as
//! a base64 archive): the server converts it.

use serde_json::json;

use crate::Adapter;

const REACHER: &str = include_str!("../../../../crates/import/tests/data/reacher.xml");

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
            json!({"document": "<mujoco><worldbody><body><geom size=\".1\"/><body><freejoint/></body></body></worldbody></mujoco>"}),
        )
        .await;
    assert!(
        err.contains(
            "<freejoint>: a free joint belongs to a top-level body (a child of <worldbody>)"
        ),
        "{err}"
    );
    adapter.stop().await;
}

const ANT: &str = include_str!("../../../../crates/import/tests/data/ant.xml");

/// Gymnasium's Ant through the adapter: its free joint is a floating base, whose pose and
/// velocity every observation shows, single env and batch alike.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_floating_base_is_observed_by_every_tool() {
    let adapter = Adapter::embedded().await;
    let created = adapter
        .ok("create_robot_env", json!({"document": ANT}))
        .await;
    assert_eq!(created["action_dim"], 8, "{created}");
    assert_eq!(created["observation_dim"], 29, "{created}");
    // Its motors are not in joint order: they are actuators, MuJoCo's ctrl in order.
    assert_eq!(
        created["actuators"][0],
        json!({"name": "actuator0", "type": "general", "target": "hip_4", "ctrl_range": [-1.0, 1.0]}),
        "{created}"
    );
    assert_eq!(created["actuators"].as_array().map(Vec::len), Some(8));
    let env_id = created["env_id"].clone();
    let observed = adapter.ok("gym_observe", json!({"env_id": env_id})).await;
    assert_eq!(
        observed["base_pose"],
        json!([0.0, 0.0, 750.0, 1.0, 0.0, 0.0, 0.0]),
        "{observed}"
    );
    let stepped = adapter
        .ok(
            "gym_step",
            json!({"env_id": env_id, "action_type": "torque", "values": [0, 0, 0, 0, 0, 0, 0, 0]}),
        )
        .await;
    let vz = stepped["observation"]["base_velocity"][2]
        .as_f64()
        .expect("a base velocity");
    assert!(vz < 0.0, "falling: {stepped}");
    let batch = adapter
        .ok("batch_create_envs", json!({"document": ANT, "n_envs": 2}))
        .await;
    let reset = adapter
        .ok("batch_reset", json!({"batch_id": batch["batch_id"]}))
        .await;
    assert_eq!(
        reset["observations"][1]["base_pose"],
        json!([0.0, 0.0, 750.0, 1.0, 0.0, 0.0, 0.0]),
        "{reset}"
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

/// A two-link URDF whose arm is a mesh file (a tetrahedron in OBJ).
const URDF: &str = r#"<robot name="tet">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.02"/></geometry></collision></link>
  <link name="arm"><inertial><mass value="0.1"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><mesh filename="package://tet/meshes/arm.obj"/></geometry></collision></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="2" velocity="1"/></joint>
</robot>"#;

fn tar_with(name: &str, bytes: &[u8]) -> Vec<u8> {
    let mut out = tar::Builder::new(Vec::new());
    let mut header = tar::Header::new_gnu();
    header.set_size(bytes.len() as u64);
    header.set_mode(0o644);
    header.set_cksum();
    out.append_data(&mut header, name, bytes).expect("tar");
    out.into_inner().expect("tar")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_urdf_with_a_mesh_archive_makes_an_env() {
    use base64::Engine as _;
    let adapter = Adapter::embedded().await;
    let obj = "v 0 0 0\nv 0.05 0 0\nv 0 0.05 0\nv 0 0 0.2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    let assets = base64::engine::general_purpose::STANDARD
        .encode(tar_with("tet/meshes/arm.obj", obj.as_bytes()));
    let created = adapter
        .ok(
            "create_robot_env",
            json!({"document": URDF, "assets_base64": assets, "end_effector_ids": ["arm"]}),
        )
        .await;
    assert_eq!(created["action_dim"], 1, "{created}");
    let batch = adapter
        .ok(
            "batch_create_envs",
            json!({"document": URDF, "assets_base64": assets, "n_envs": 2}),
        )
        .await;
    assert_eq!(batch["n_envs"], 2, "{batch}");
    let err = adapter
        .err("create_robot_env", json!({"document": URDF}))
        .await;
    assert!(
        err.contains(
            "\"package://tet/meshes/arm.obj\": a mesh file is read from the request's assets"
        ),
        "{err}"
    );
    let err = adapter
        .err(
            "create_robot_env",
            json!({"document": URDF, "assets_base64": "%%%"}),
        )
        .await;
    assert!(err.contains("assets_base64: not base64"), "{err}");
    adapter.stop().await;
}

/// `--models DIR` gives the embedded server a model library that `list_models` shows and
/// `model` names.
#[cfg(feature = "embedded")]
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_embedded_server_takes_a_model_library() {
    let dir = std::env::temp_dir().join(format!("gymfleet-mcp-models-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("reacher.xml"), REACHER).expect("write");
    std::fs::write(
        dir.join("tet.urdf"),
        URDF.replace("package://tet/meshes/arm.obj", "arm.obj"),
    )
    .expect("write");
    std::fs::write(
        dir.join("arm.obj"),
        "v 0 0 0\nv 0.05 0 0\nv 0 0.05 0\nv 0 0 0.2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .expect("write");
    let adapter =
        Adapter::spawn(&["--threads", "1", "--models", dir.to_str().expect("utf-8")]).await;
    let listed = adapter.ok("list_models", json!({})).await;
    let names: Vec<&str> = listed["models"]
        .as_array()
        .expect("models")
        .iter()
        .map(|m| m["name"].as_str().expect("a name"))
        .collect();
    assert_eq!(names, ["reacher", "tet"], "{listed}");
    let created = adapter
        .ok("create_robot_env", json!({"model": "tet"}))
        .await;
    assert_eq!(created["action_dim"], 1, "{created}");
    adapter.stop().await;
    let _ = std::fs::remove_dir_all(&dir);
}

const FOURBAR: &str = include_str!("../../../../models/fourbar.json");

/// A closed chain through the adapter: the four-bar's four joints are observed (the loop's
/// closing pin too), one is driven, and driving it swings the rocker through the loop.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_four_bar_is_driven_through_its_loop() {
    let adapter = Adapter::embedded().await;
    let created = adapter
        .ok(
            "create_robot_env",
            json!({"document": FOURBAR, "end_effector_ids": ["coupler"]}),
        )
        .await;
    assert_eq!(created["action_dim"], 1, "{created}");
    let env_id = created["env_id"].clone();
    let mut stepped = json!(null);
    for _ in 0..30 {
        stepped = adapter
            .ok(
                "gym_step",
                json!({"env_id": env_id, "action_type": "velocity", "values": [360]}),
            )
            .await;
    }
    let positions = stepped["observation"]["joint_positions"]
        .as_array()
        .expect("joint positions")
        .clone();
    assert_eq!(positions.len(), 4, "{stepped}");
    let rocker = positions[2].as_f64().expect("a number");
    assert!(
        rocker.abs() > 1.0,
        "the rocker swings with the crank: {stepped}"
    );
    adapter.stop().await;
}

/// A scene with a mocap paddle under a free box: the agent lifts the paddle with
/// gym_set_mocap_pose and sees the box ride on it in free_body_poses.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_agent_moves_a_mocap_body_and_sees_a_free_body_follow() {
    let adapter = Adapter::embedded().await;
    let document = json!({
        "parts": [
            {"name": "Anchor", "primitive": {"type": "sphere", "radius": 1}},
            {"name": "Paddle", "primitive": {"type": "cube", "size": {"x": 40, "y": 40, "z": 10}}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}
        ],
        "assembly": {"instances": [
            {"part": "Anchor", "name": "anchor", "collision": {"group": 0, "mask": 0}},
            {"part": "Paddle", "name": "paddle", "position": {"x": -20, "y": -20, "z": 0}, "mocap": true},
            {"part": "Cube", "name": "box", "position": {"x": -10, "y": -10, "z": 10}}
        ], "joints": []}
    });
    let created = adapter
        .ok(
            "create_robot_env",
            json!({"document": document.to_string()}),
        )
        .await;
    assert_eq!(created["mocap_bodies"], json!(["paddle"]), "{created}");
    assert_eq!(created["free_bodies"], json!(["box"]), "{created}");
    let env_id = created["env_id"].clone();
    let mut observed = json!(null);
    for k in 1..=60 {
        let z = 5.0 + 30.0 * f64::from(k) / 60.0;
        adapter
            .ok(
                "gym_set_mocap_pose",
                json!({"env_id": env_id, "body": "paddle", "position": [0, 0, z]}),
            )
            .await;
        observed = adapter
            .ok(
                "gym_step",
                json!({"env_id": env_id, "action_type": "torque", "values": []}),
            )
            .await;
    }
    let z = observed["observation"]["free_body_poses"][0][2]
        .as_f64()
        .expect("the box's height");
    assert!(
        (z - 50.0).abs() < 0.5,
        "the box rides on the paddle at {z} mm: {observed}"
    );
    let err = adapter
        .err(
            "gym_set_mocap_pose",
            json!({"env_id": env_id, "body": "hand", "position": [0, 0, 0]}),
        )
        .await;
    assert!(
        err.contains("unknown mocap body \"hand\" (known: \"paddle\")"),
        "{err}"
    );
    adapter.stop().await;
}
