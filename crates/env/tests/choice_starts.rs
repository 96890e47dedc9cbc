//! Starts that choose (dm_control's manipulator): `reset_noise.choice` places some joints
//! by one of several options (a box with velocities, or a frame's pose read after the
//! other draws), `reset_noise.equal` starts a joint where another is drawn, and a mocap
//! draw's `turn` orients its body.

mod common;

use common::env_with;
use gymfleet_env::{EnvConfig, RobotEnv, TaskKind, TaskSpec, TermsTask, Units};
use serde_json::{json, Value};

/// The hanging pendulum (`hinge` about +Y, a site `tip` at the arm's end), a second arm
/// (`follower`, about +Y) and a block sliding along X (`slide`), neither colliding, and a
/// mocap `target`.
fn doc() -> Value {
    let mut doc = common::hanging_pendulum(json!({"name": "hinge"}));
    let a = &mut doc["assembly"];
    a["sites"] = json!([{"name": "tip", "instance": "arm", "point": {"x": 2, "y": 2, "z": 0}}]);
    let none = json!({"group": 0, "mask": 0});
    for (name, part, x, mocap) in [
        ("arm2", "Arm", 108, false),
        ("block", "Base", 0, false),
        ("target", "Base", 0, true),
    ] {
        a["instances"]
            .as_array_mut()
            .expect("instances")
            .push(json!({
                "part": part, "name": name, "position": {"x": x, "y": 80, "z": -40},
                "collision": none, "mocap": mocap
            }));
    }
    a["joints"].as_array_mut().expect("joints").extend([
        json!({"type": "revolute", "name": "follower", "parent": "base", "child": "arm2",
               "anchor": {"x": 110, "y": 82, "z": 0}, "axis": {"x": 0, "y": 1, "z": 0}}),
        json!({"type": "prismatic", "name": "slide", "parent": "base", "child": "block",
               "anchor": {"x": 0, "y": 90, "z": -35}, "axis": {"x": 1, "y": 0, "z": 0}}),
    ]);
    doc
}

fn config(task: Value) -> EnvConfig {
    EnvConfig {
        units: Units::Si,
        task: Some(TaskSpec {
            kind: TaskKind::Terms(TermsTask::from_json(&task.to_string()).expect("a terms task")),
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    }
}

fn refused(noise: Value) -> String {
    RobotEnv::from_json(
        &doc().to_string(),
        config(json!({"terms": [], "reset_noise": noise})),
    )
    .err()
    .expect("refused")
    .to_string()
}

/// A frame option puts `slide` at the tip's world x and `follower` at the arm's turn plus
/// 0.1 rad, at rest; a box option draws in its box with a velocity. Both are chosen.
#[test]
fn a_choice_places_joints_at_a_frame_or_in_a_box() {
    let task = json!({
        "terms": [{"name": "tip_x", "weight": 0, "observe": true,
                   "value": {"site": "tip", "axis": "x"}}],
        "reset_noise": {
            "set": [{"joints": ["hinge"], "low": [-1.0], "high": [1.0]}],
            "choice": {"joints": ["slide", "follower"], "options": [
                {"frame": "tip", "from": ["x", "angle_y"], "offset": [0.0, 0.1]},
                {"weight": 1.0, "low": [0.01, -0.2], "high": [0.02, 0.2],
                 "velocity_low": [1.0, 0.0], "velocity_high": [2.0, 0.0]}
            ]}
        }
    });
    let mut e = env_with(&doc(), config(task));
    let (mut at_frame, mut in_box) = (0, 0);
    for seed in 0..100 {
        let obs = e.reset(Some(seed));
        let [hinge, follower, slide] = [0, 1, 2].map(|k| f64::from(obs.joint_positions[k]));
        let v = [1, 2].map(|k| f64::from(obs.joint_velocities[k]));
        let tip_x = f64::from(obs.task[0]);
        if (slide - tip_x).abs() < 1e-6 {
            at_frame += 1;
            assert!(
                (follower - (hinge + 0.1)).abs() < 1e-5,
                "{follower} {hinge}"
            );
            assert_eq!(v, [0.0, 0.0]);
            // The tip swings about the anchor (x = 10 mm) on the 40 mm arm.
            assert!(
                (tip_x - (0.010 - 0.040 * hinge.sin())).abs() < 1e-6,
                "{tip_x}"
            );
        } else {
            in_box += 1;
            assert!((0.01 - 1e-7..=0.02 + 1e-7).contains(&slide), "{slide}");
            assert!((-0.2 - 1e-7..=0.2 + 1e-7).contains(&follower), "{follower}");
            assert!((1.0 - 1e-6..=2.0 + 1e-6).contains(&v[1]), "{v:?}");
            assert!(v[0].abs() < 1e-9, "{v:?}");
        }
    }
    assert!(at_frame > 30 && in_box > 30, "{at_frame} {in_box}");
}

/// `equal`: the follower starts at the hinge's drawn angle, whatever it is.
#[test]
fn an_equal_pair_starts_together() {
    let task = json!({"terms": [], "reset_noise": {
        "set": [{"joints": ["hinge"], "low": [-1.0], "high": [1.0]}],
        "equal": [["follower", "hinge"]]
    }});
    let mut e = env_with(&doc(), config(task));
    let mut seen = Vec::new();
    for seed in 0..20 {
        let obs = e.reset(Some(seed));
        let [hinge, follower] = [0, 1].map(|k| obs.joint_positions[k]);
        assert!((hinge - follower).abs() < 1e-6, "{hinge} {follower}");
        seen.push(hinge);
    }
    assert!(seen.iter().any(|&h| h < -0.5) && seen.iter().any(|&h| h > 0.5));
}

/// A mocap draw's `turn`: the target turns about +Y by an angle in its range, which its
/// frame's axes read back (`xmat` xz = sin, xx = cos).
#[test]
fn a_mocap_turn_orients_the_target() {
    let task = json!({
        "terms": [
            {"name": "xz", "weight": 0, "observe": true,
             "value": {"instance": "target", "axis": "x", "frame_axis": "z"}},
            {"name": "xx", "weight": 0, "observe": true,
             "value": {"instance": "target", "axis": "x", "frame_axis": "x"}}
        ],
        "reset_noise": {"mocap": [{"body": "target",
            "boxes": [{"low": [0.0, 0.0, 0.3], "high": [0.0, 0.0, 0.3]}],
            "turn": {"axis": [0.0, 2.0, 0.0], "angle": [-3.0, 3.0]}}]}
    });
    let mut e = env_with(&doc(), config(task));
    let angles: Vec<f64> = (0..200)
        .map(|seed| {
            let obs = e.reset(Some(seed));
            let [xz, xx] = [obs.task[0], obs.task[1]].map(f64::from);
            assert!((xz.hypot(xx) - 1.0).abs() < 1e-5, "a turn about y only");
            xz.atan2(xx)
        })
        .collect();
    assert!(angles
        .iter()
        .all(|a| (-3.0 - 1e-5..=3.0 + 1e-5).contains(a)));
    assert!(angles.iter().any(|&a| a < -2.5) && angles.iter().any(|&a| a > 2.5));
}

#[test]
fn bad_choices_equal_pairs_and_turns_are_refused_with_their_path() {
    let frame = |from: Value| {
        json!({"choice": {"joints": ["slide", "follower"], "options": [
            {"frame": "tip", "from": from}]}})
    };
    let cases = [
        (json!({"choice": {"joints": [], "options": []}}),
         "task.terms.reset_noise.choice.joints: expected 1 to 512 joints, got 0"),
        (json!({"choice": {"joints": ["slide"], "options": []}}),
         "task.terms.reset_noise.choice.options: expected at least one option"),
        (json!({"choice": {"joints": ["slide"], "options": [{"weight": 0, "low": [0], "high": [1]}]}}),
         "options[0].weight: expected a weight > 0, got 0"),
        (json!({"choice": {"joints": ["slide"], "options": [{"low": [0, 1], "high": [1]}]}}),
         "options[0].low: expected one value per joint (1), got 2"),
        (json!({"choice": {"joints": ["slide"], "options": [{"low": [2], "high": [1]}]}}),
         "options[0].high[0]: expected high >= low = 2, got 1"),
        (json!({"choice": {"joints": ["slide"], "options": [
            {"low": [0], "high": [1], "velocity_low": [0], "velocity_high": []}]}}),
         "options[0].velocity_high: expected one value per joint (1), got 0"),
        (json!({"choice": {"joints": ["slide"], "options": [
            {"low": [0], "high": [1], "frame": "tip", "from": ["x"]}]}}),
         "options[0]: expected exactly one of a box (low, high) or a frame"),
        (json!({"choice": {"joints": ["slide"], "options": [{"low": [0], "high": [1], "from": ["x"]}]}}),
         "options[0]: from and offset belong to a frame option"),
        (frame(json!(["x"])), "options[0].from: expected one coordinate per joint (2), got 1"),
        (frame(json!(["x", "pitch"])),
         "options[0].from[1]: expected x, y, z, angle_x, angle_y or angle_z, got \"pitch\""),
        (frame(json!(["angle_y", "angle_y"])),
         "options[0].from[0]: a prismatic joint takes a position (x, y or z)"),
        (frame(json!(["x", "z"])),
         "options[0].from[1]: a revolute joint takes a turn (angle_x, angle_y or angle_z)"),
        (json!({"choice": {"joints": ["slide"], "options": [{"frame": "nowhere", "from": ["x"]}]}}),
         "options[0].frame: unknown instance \"nowhere\""),
        (json!({"set": [{"joints": ["slide"], "low": [0], "high": [1]}],
                "choice": {"joints": ["slide"], "options": [{"low": [0], "high": [1]}]}}),
         "choice.joints[0]: the joint is set by an earlier entry too"),
        (json!({"equal": [["slide", "hinge"]]}),
         "task.terms.reset_noise.equal[0]: expected two joints of one kind (both revolute or both prismatic)"),
        (json!({"equal": [["follower", "elbow"]]}), "equal[0][1]: unknown joint \"elbow\""),
        (json!({"equal": [["follower", "hinge"], ["follower", "hinge"]]}),
         "equal[1][0]: the joint is set by an earlier entry too"),
        (json!({"mocap": [{"body": "target", "boxes": [{"low": [0, 0, 0], "high": [0, 0, 0]}],
                           "turn": {"axis": [0, 0, 0], "angle": [0, 1]}}]}),
         "task.terms.reset_noise.mocap[0].turn.axis: expected a non-zero axis"),
        (json!({"mocap": [{"body": "target", "boxes": [{"low": [0, 0, 0], "high": [0, 0, 0]}],
                           "turn": {"axis": [0, 1, 0], "angle": [1, 0]}}]}),
         "mocap[0].turn.angle: expected min <= max, got 1 and 0"),
    ];
    for (noise, message) in cases {
        let err = refused(noise.clone());
        assert!(err.contains(message), "{noise}: {err}");
    }
}
