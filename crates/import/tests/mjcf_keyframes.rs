//! `<keyframe><key>` (issue Z2): keys become the document's keyframes in MuJoCo's qpos
//! layout (joints, the floating base, free bodies) and mocap poses; a wrong count is
//! refused, and what a keyframe cannot set yet is warned about.

mod common;

use common::error;
use gymfleet_import::mjcf_to_document;
use serde_json::json;

/// A hinge, a ball joint, and a free object beside them; then `keys`.
fn model(keys: &str) -> String {
    format!(
        r#"<mujoco><worldbody>
  <body name="arm"><joint name="hinge" type="hinge" axis="0 1 0"/><geom size=".1"/>
    <body name="hand" pos="0 0 -.3"><joint name="wrist" type="ball"/><geom size=".05"/></body>
  </body>
  <body name="box" pos="1 0 0"><freejoint/><geom type="box" size=".1 .1 .1"/></body>
</worldbody>
<keyframe>{keys}</keyframe>
</mujoco>"#
    )
}

#[test]
fn a_key_sets_the_hinge_the_ball_joint_and_the_free_body() {
    let xml = model(
        r#"<key name="k" qpos="0.5 0.7071068 0.7071068 0 0 1 0 0.5 1 0 0 0"/>
<key qpos="0.25 1 0 0 0 1 0 0 1 0 0 0"/>"#,
    );
    let c = mjcf_to_document(&xml).expect("converts");
    let keyframes = &c.document["assembly"]["keyframes"];
    assert_eq!(keyframes[0]["name"], "k");
    assert_eq!(
        keyframes[1]["name"], "key1",
        "an unnamed key is named by its index"
    );
    let degrees = keyframes[0]["positions"]["hinge"]
        .as_f64()
        .expect("the hinge");
    assert!((degrees - 0.5f64.to_degrees()).abs() < 1e-9, "{degrees}");
    assert_eq!(
        keyframes[1]["positions"],
        json!({"hinge": 0.25f64.to_degrees()})
    );
    let warned = |needle: &str| c.warnings.iter().any(|w| w.contains(needle));
    // The ball joint's rotation is kept as MuJoCo's quaternion.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let rotation: Vec<f64> = keyframes[0]["rotations"]["wrist"]
        .as_array()
        .expect("the wrist's rotation")
        .iter()
        .filter_map(serde_json::Value::as_f64)
        .collect();
    assert_eq!(rotation.len(), 4);
    for (got, want) in rotation.iter().zip([h, h, 0.0, 0.0]) {
        assert!((got - want).abs() < 1e-7, "{rotation:?}");
    }
    // The free body is placed: its qpos is its observed pose (mm), at rest.
    assert_eq!(
        keyframes[0]["free_bodies"]["box"],
        json!({"position": {"x": 1000.0, "y": 0.0, "z": 500.0}, "orientation": [1.0, 0.0, 0.0, 0.0],
               "linear_velocity": {"x": 0.0, "y": 0.0, "z": 0.0},
               "angular_velocity": {"x": 0.0, "y": 0.0, "z": 0.0}})
    );
    // The second key leaves the ball and the box where the model puts them: no warning.
    assert!(!warned("key1:"), "{:?}", c.warnings);
}

#[test]
fn a_key_of_the_wrong_size_is_refused_with_the_models_count() {
    let err = error(&model(r#"<key qpos="0.5"/>"#));
    assert!(
        err.contains("qpos") && err.contains("expected 12 numbers (the model's nq), got 1"),
        "{err}"
    );
    let err = error(&model(r#"<key qvel="0 0"/>"#));
    assert!(
        err.contains("expected 10 numbers (the model's nv), got 2"),
        "{err}"
    );
}

#[test]
fn a_keys_mocap_poses_convert_and_a_wrong_count_is_refused() {
    let xml = |key: &str| {
        format!(
            r#"<mujoco><worldbody>
  <body name="arm"><joint name="hinge" type="hinge" axis="0 1 0"/><geom size=".1"/></body>
  <body name="target" mocap="true" pos="0 1 0"><geom size=".05"/></body>
  <body name="still" mocap="true" pos="0 2 0"><geom size=".05"/></body>
</worldbody>
<keyframe>{key}</keyframe>
</mujoco>"#
        )
    };
    let c = mjcf_to_document(&xml(r#"<key name="k" mpos="0 1 0.5 0 2 0"/>"#)).expect("converts");
    let key = &c.document["assembly"]["keyframes"][0];
    assert_eq!(
        key["mocap"],
        json!({"target": {"position": {"x": 0.0, "y": 1000.0, "z": 500.0}, "orientation": [1.0, 0.0, 0.0, 0.0]}}),
        "the body the key does not move is left out"
    );
    assert!(
        c.warnings.iter().all(|w| !w.contains("mpos")),
        "{:?}",
        c.warnings
    );
    let err = error(&xml(r#"<key mquat="1 0 0 0"/>"#));
    assert!(
        err.contains("mquat") && err.contains("expected 8 numbers (4 per mocap body), got 4"),
        "{err}"
    );
}

#[test]
fn a_keys_ctrl_and_act_convert_by_actuator_and_a_wrong_count_is_refused() {
    let xml = |key: &str| {
        format!(
            r#"<mujoco><worldbody>
  <body name="arm"><joint name="hinge" type="hinge" axis="0 1 0"/><geom size=".1"/>
    <body name="hand" pos="0 0 -.3"><joint name="wrist" type="hinge" axis="0 1 0"/><geom size=".05"/></body>
  </body>
</worldbody>
<actuator>
  <motor name="lift" joint="hinge"/>
  <general name="slow" joint="wrist" dyntype="filter" dynprm="0.5"/>
</actuator>
<keyframe>{key}</keyframe>
</mujoco>"#
        )
    };
    let c = mjcf_to_document(&xml(r#"<key name="k" ctrl="0.5 0" act="0.25"/>"#)).expect("converts");
    let key = &c.document["assembly"]["keyframes"][0];
    assert_eq!(
        key["controls"],
        json!({"lift": 0.5}),
        "a zero control is left out"
    );
    assert_eq!(key["activations"], json!({"slow": 0.25}));
    let err = error(&xml(r#"<key act="1 2"/>"#));
    assert!(
        err.contains("act")
            && err.contains("expected 1 numbers (one per actuator with dynamics), got 2"),
        "{err}"
    );
    let err = error(&xml(r#"<key ctrl="1"/>"#));
    assert!(
        err.contains("expected 2 numbers (one per actuator), got 1"),
        "{err}"
    );
}
