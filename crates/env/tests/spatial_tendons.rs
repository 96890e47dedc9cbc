//! Spatial tendons (`assembly.tendons` with `sites`, MJCF's `<tendon><spatial>`): the
//! length of the path through sites and its rate, a spring along it, and a range as a
//! rope, checked against closed forms on a ball sliding along x away from a post (no
//! gravity); and the errors.

mod common;

use std::f64::consts::PI;

use common::env_with;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, TaskKind, TaskSpec, TermsTask, Units};
use serde_json::{json, Value};

const R: f64 = 0.05;
/// The ball's mass (radius `R`, 1000 kg/m³), kg.
fn mass() -> f64 {
    4.0 / 3.0 * PI * R.powi(3) * 1000.0
}

/// A ball on a slide along x, its centre 300 mm from a post's site (both on the slide's
/// line), and one tendon `t` from the post's site to the ball's (extra fields merged).
fn slide(tendon: Value) -> Value {
    let mut t = json!({"name": "t", "sites": ["anchor", "ball"]});
    for (k, v) in tendon.as_object().expect("fields") {
        t[k] = v.clone();
    }
    json!({
        "simulation": {"gravity": {"x": 0, "y": 0, "z": 0}},
        "parts": [
            {"name": "Post", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": R * 1000.0}}
        ],
        "assembly": {
            "instances": [
                {"part": "Post", "name": "post", "position": {"x": -5, "y": -5, "z": -5}},
                {"part": "Ball", "name": "ball", "position": {"x": 300, "y": 0, "z": 0}}
            ],
            "joints": [
                {"type": "prismatic", "name": "x", "parent": "post", "child": "ball",
                 "anchor": {"x": 300, "y": 0, "z": 0}, "axis": {"x": 1, "y": 0, "z": 0}}
            ],
            "sites": [
                {"name": "anchor", "instance": "post", "point": {"x": 5, "y": 5, "z": 5}},
                {"name": "ball", "instance": "ball", "point": {"x": 0, "y": 0, "z": 0}}
            ],
            "tendons": [t]
        }
    })
}

const TASK: &str = r#"{"terms": [
    {"name": "length", "weight": 0, "value": {"tendon_length": "t"}},
    {"name": "rate", "weight": 0, "value": {"tendon_velocity": "t"}}
]}"#;

fn env(doc: &Value) -> RobotEnv {
    env_with(
        doc,
        EnvConfig {
            dt: 0.002,
            substeps: 2,
            units: Units::Si,
            task: Some(TaskSpec {
                kind: TaskKind::Terms(TermsTask::from_json(TASK).expect("a terms task")),
                action_cost: 0.0,
            }),
            ..EnvConfig::default()
        },
    )
}

#[test]
fn a_spatial_tendons_length_and_rate_follow_its_sites() {
    let mut e = env(&slide(json!({})));
    for k in 0..100 {
        e.step(ActionType::Torque, &[0.5]).expect("steps");
        let o = e.observe();
        let (x, v) = (
            f64::from(o.joint_positions[0]),
            f64::from(o.joint_velocities[0]),
        );
        let terms = e.term_values();
        assert!(
            (f64::from(terms[0]) - (0.3 + x)).abs() < 1e-5,
            "step {k}: {terms:?}, x = {x}"
        );
        assert!(
            (f64::from(terms[1]) - v).abs() < 1e-4,
            "step {k}: {terms:?}, v = {v}"
        );
    }
}

#[test]
fn a_springy_spatial_tendon_makes_the_ball_oscillate_at_its_stiffness() {
    // Rest length 0.25 m: the ball starts 0.05 m out and swings about x = −0.05 with
    // ω = √(k/m).
    let k = 2.0;
    let mut e = env(&slide(json!({"stiffness": k, "spring_length": 0.25})));
    let omega = (k / mass()).sqrt();
    let mut worst: f64 = 0.0;
    for step in 1..=1000 {
        e.step(ActionType::Torque, &[0.0]).expect("steps");
        let x = f64::from(e.observe().joint_positions[0]);
        let t = step as f64 * 0.002;
        worst = worst.max((x - (-0.05 + 0.05 * (omega * t).cos())).abs());
    }
    assert!(
        worst < 0.02 * 0.05,
        "{worst} m from the closed form (ω = {omega})"
    );
}

#[test]
fn a_ranged_spatial_tendon_is_a_rope() {
    // Pushed outward, the ball stops where the path reaches 0.35 m and stays there; pushed
    // inward, the rope goes slack and does nothing.
    let mut e = env(&slide(json!({"range": [0, 0.35]})));
    for _ in 0..500 {
        e.step(ActionType::Torque, &[0.5]).expect("steps");
        let length = f64::from(e.term_values()[0]);
        assert!(length <= 0.35 + 1e-5, "the rope stretched to {length} m");
    }
    let length = f64::from(e.term_values()[0]);
    assert!(
        (length - 0.35).abs() < 1e-5,
        "at rest on the rope: {length}"
    );
    assert!(f64::from(e.term_values()[1]).abs() < 1e-3);
    for _ in 0..200 {
        e.step(ActionType::Torque, &[-0.5]).expect("steps");
    }
    assert!(
        f64::from(e.term_values()[0]) < 0.3,
        "a slack rope does not push"
    );
}

#[test]
fn a_rope_to_a_free_body_is_refused() {
    // A puck with nothing above it moves outside the trees: no rope may tie it to the ball.
    let mut doc = slide(json!({"sites": ["ball", "puck"], "range": [0, 0.5]}));
    let assembly = &mut doc["assembly"];
    assembly["instances"]
        .as_array_mut()
        .expect("instances")
        .push(json!({"part": "Ball", "name": "puck", "position": {"x": 0, "y": 300, "z": 0}}));
    assembly["sites"]
        .as_array_mut()
        .expect("sites")
        .push(json!({"name": "puck", "instance": "puck", "point": {"x": 0, "y": 0, "z": 0}}));
    common::assert_refused(
        &doc,
        "tendon \"t\" has a range, and its sites move with different kinematic trees or with a free body; a ranged spatial tendon's moving sites must share one tree",
    );
    // Without the range the same tendon is a spring's path, and builds.
    doc["assembly"]["tendons"][0]
        .as_object_mut()
        .expect("tendon")
        .remove("range");
    RobotEnv::from_json(&doc.to_string(), EnvConfig::default()).expect("builds");
}

#[test]
fn a_bad_spatial_tendon_is_refused_with_its_path() {
    let cases = [
        (
            json!({"sites": ["anchor"]}),
            "assembly.tendons[0].sites: expected 2 to 64 sites, got 1",
        ),
        (
            json!({"sites": ["anchor", "nowhere"]}),
            "assembly.tendons[0].sites[1]: no site is named \"nowhere\"",
        ),
        (
            json!({"joints": [{"joint": "x", "coef": 1}]}),
            "assembly.tendons[0].sites: a tendon names joints (a fixed tendon) or sites (a spatial tendon), not both",
        ),
        (
            json!({"range": [0.1, 0.4]}),
            "assembly.tendons[0].range: a spatial tendon's range is a rope's: only its max holds, and min must be 0 or less, got 0.1",
        ),
    ];
    for (tendon, expected) in cases {
        common::assert_refused(&slide(tendon), expected);
    }
}
