//! Fixed tendons (`assembly.tendons`, MJCF's `<tendon><fixed>`): the length Σ coef · q and
//! its rate read by terms in SI, and a tendon's spring and damper acting on its joints as
//! coef × their force, checked against closed forms on spheres spinning about vertical
//! hinges (no gravity torque, no coupling but the tendon's).

mod common;

use std::f64::consts::PI;

use common::env_with;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, TaskKind, TaskSpec, TermsTask, Units};
use serde_json::{json, Value};

fn inertia() -> f64 {
    common::turntable_inertia()
}

/// The turntables (`a` from `initial_a` degrees) with one tendon `t`.
fn turntables(tendon: Value, initial_a: f64) -> Value {
    common::turntables(initial_a, json!({"tendons": [tendon]}))
}

const TASK: &str = r#"{"terms": [
    {"name": "length", "weight": 0, "value": {"tendon_length": "t"}},
    {"name": "rate", "weight": 0, "value": {"tendon_velocity": "t"}}
]}"#;

fn env(doc: &Value, units: Units) -> RobotEnv {
    env_with(
        doc,
        EnvConfig {
            dt: 0.01,
            substeps: 10,
            units,
            task: Some(TaskSpec {
                kind: TaskKind::Terms(TermsTask::from_json(TASK).expect("a terms task")),
                action_cost: 0.0,
            }),
            ..EnvConfig::default()
        },
    )
}

#[test]
fn a_tendons_length_and_rate_are_its_joints_combination_in_si() {
    let tendon =
        json!({"name": "t", "joints": [{"joint": "a", "coef": 2.0}, {"joint": "b", "coef": -0.5}]});
    for units in [Units::Si, Units::Document] {
        let mut e = env(&turntables(tendon.clone(), 0.0), units);
        for k in 0..50 {
            e.step(ActionType::Torque, &[0.002, -0.001]).expect("steps");
            let o = e.observe();
            let (q, v) = (&o.joint_positions, &o.joint_velocities);
            let si = |x: f32| match units {
                Units::Si => f64::from(x),
                Units::Document => f64::from(x).to_radians(),
            };
            let length = 2.0 * si(q[0]) - 0.5 * si(q[1]);
            let rate = 2.0 * si(v[0]) - 0.5 * si(v[1]);
            let terms = e.term_values();
            assert!(
                (f64::from(terms[0]) - length).abs() < 1e-5,
                "{units:?} step {k}: {terms:?}, {length}"
            );
            assert!(
                (f64::from(terms[1]) - rate).abs() < 1e-4,
                "{units:?} step {k}: {terms:?}, {rate}"
            );
        }
    }
}

/// The angle of hinge `a` (rad) every 10 ms for `seconds`, released from 30°.
fn swing(tendon: Value, seconds: f64) -> Vec<f64> {
    let mut e = env(&turntables(tendon, 30.0), Units::Si);
    (0..(seconds / 0.01).round() as usize)
        .map(|_| {
            e.step(ActionType::Torque, &[0.0, 0.0]).expect("steps");
            f64::from(e.observe().joint_positions[0])
        })
        .collect()
}

#[test]
fn a_springy_tendon_makes_its_joint_oscillate_at_coef_squared_stiffness() {
    // Only joint a in the tendon: I·θ'' = −c²·k·θ about the document's pose.
    let (c, k) = (2.0, 0.05);
    let omega = c * (k / inertia()).sqrt();
    let angles = swing(
        json!({"name": "t", "joints": [{"joint": "a", "coef": c}], "stiffness": k}),
        2.0,
    );
    let a0 = 30f64.to_radians();
    // Within 2 % of the amplitude at every step (the integrator lags half a substep)...
    for (step, angle) in angles.iter().enumerate() {
        let t = (step + 1) as f64 * 0.01;
        let expected = a0 * (omega * t).cos();
        assert!(
            (angle - expected).abs() < 0.02 * a0,
            "t = {t} s: {angle} rad, expected {expected} (ω = {omega} rad/s)"
        );
    }
    // ... and the period, from the first to the last upward zero crossing, within 0.1 %.
    let crossings: Vec<f64> = angles
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
        .map(|(s, w)| (s + 1) as f64 * 0.01 + 0.01 * (-w[0] / (w[1] - w[0])))
        .collect();
    let periods = (crossings.len() - 1) as f64;
    let period = (crossings[crossings.len() - 1] - crossings[0]) / periods;
    let expected = 2.0 * PI / omega;
    assert!(
        (period / expected - 1.0).abs() < 1e-3,
        "period {period} s, expected {expected} s"
    );
    // A rest length moves the centre: the spring holds it at L/c.
    let angles = swing(
        json!({"name": "t", "joints": [{"joint": "a", "coef": c}], "stiffness": k, "damping": 0.05, "spring_length": 0.2}),
        8.0,
    );
    let last = *angles.last().unwrap();
    assert!(
        (last - 0.1).abs() < 1e-3,
        "settles at {last} rad, expected 0.1"
    );
}

#[test]
fn a_damped_tendon_slows_its_joints_at_coef_squared_damping() {
    // A torque τ on a: the rate settles where c²·b·ω = τ.
    let (c, b, torque) = (2.0, 0.01, 0.004f32);
    let tendon = json!({"name": "t", "joints": [{"joint": "a", "coef": c}], "damping": b});
    let mut e = env(&turntables(tendon, 0.0), Units::Si);
    for _ in 0..400 {
        e.step(ActionType::Torque, &[torque, 0.0]).expect("steps");
    }
    let rate = f64::from(e.observe().joint_velocities[0]);
    let expected = f64::from(torque) / (c * c * b);
    assert!(
        (rate / expected - 1.0).abs() < 1e-3,
        "{rate} rad/s, expected {expected}"
    );
}

fn refused(tendon: Value) -> String {
    RobotEnv::from_json(&turntables(tendon, 0.0).to_string(), EnvConfig::default())
        .err()
        .expect("refused")
        .to_string()
}

#[test]
fn a_bad_tendon_is_refused_with_its_path() {
    let cases = [
        (
            json!({"name": "t", "joints": [{"joint": "c", "coef": 1}]}),
            "assembly.tendons[0].joints[0].joint: no joint is named \"c\"",
        ),
        (
            json!({"name": "t", "joints": [{"joint": "a", "coef": 1}, {"joint": "a", "coef": 2}]}),
            "assembly.tendons[0].joints[1].joint: \"a\" is listed twice",
        ),
        (
            json!({"name": "t", "joints": []}),
            "assembly.tendons[0].joints: expected 1 to 64 joints (a fixed tendon) or 2 to 64 sites (a spatial tendon), got 0 joints",
        ),
        (
            json!({"name": "t", "joints": [{"joint": "a", "coef": 1}], "stiffness": -1}),
            "assembly.tendons[0].stiffness: expected a stiffness in [0, 1000000000], got -1",
        ),
    ];
    for (tendon, expected) in cases {
        let message = refused(tendon);
        assert!(
            message.contains(expected),
            "{message}\nexpected: {expected}"
        );
    }
    // A task naming a tendon the document lacks.
    let doc = turntables(
        json!({"name": "u", "joints": [{"joint": "a", "coef": 1}]}),
        0.0,
    );
    let config = EnvConfig {
        task: Some(TaskSpec {
            kind: TaskKind::Terms(TermsTask::from_json(TASK).expect("a terms task")),
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    let message = RobotEnv::from_json(&doc.to_string(), config)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        message.contains("unknown tendon \"t\" (tendons: \"u\")"),
        "{message}"
    );
}

#[test]
fn a_ranged_tendon_stops_its_joints_at_the_range() {
    // Driven by a torque, joint a stops where 2·θa − 0.5·θb reaches the range's end.
    let tendon = json!({"name": "t", "joints": [{"joint": "a", "coef": 2.0}, {"joint": "b", "coef": -0.5}],
                        "range": [-0.3, 0.2]});
    let mut e = env(&turntables(tendon, 0.0), Units::Si);
    for (torque, bound) in [(0.01f32, 0.2), (-0.01, -0.3)] {
        for _ in 0..200 {
            e.step(ActionType::Torque, &[torque, 0.0]).expect("steps");
            let length = f64::from(e.term_values()[0]);
            let (lo, hi) = (-0.3 - 1e-4, 0.2 + 1e-4);
            assert!(
                lo <= length && length <= hi,
                "the length {length} left the range"
            );
        }
        let length = f64::from(e.term_values()[0]);
        assert!(
            (length - bound).abs() < 1e-4,
            "at rest on the stop: {length} vs {bound}"
        );
        let rate = f64::from(e.term_values()[1]);
        assert!(rate.abs() < 1e-3, "and still: {rate}");
    }
    // Without the range the same push goes far past it.
    let free =
        json!({"name": "t", "joints": [{"joint": "a", "coef": 2.0}, {"joint": "b", "coef": -0.5}]});
    let mut e = env(&turntables(free, 0.0), Units::Si);
    for _ in 0..200 {
        e.step(ActionType::Torque, &[0.01, 0.0]).expect("steps");
    }
    assert!(f64::from(e.term_values()[0]) > 1.0);
    let message =
        refused(json!({"name": "t", "joints": [{"joint": "a", "coef": 1}], "range": [1, 0]}));
    assert!(
        message.contains("assembly.tendons[0].range: expected [min, max] with min < max, each within ±1000000 (m or rad), got [1, 0]"),
        "{message}"
    );
}
