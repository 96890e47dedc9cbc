//! Couplings (`assembly.couplings`, MJCF's `<equality><joint>` and `<equality><tendon>`):
//! a joint's displacement held at `offset + ratio ·` another's, or a fixed tendon's length
//! at its pose's, as hard constraints, checked against closed forms on two spheres
//! spinning about vertical hinges (no gravity, no other coupling); and the errors.

mod common;

use common::env_with;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, Units};
use serde_json::{json, Value};

fn inertia() -> f64 {
    common::turntable_inertia()
}

/// The turntables with a tendon `t` = a + b, and `couplings`.
fn turntables(couplings: Value) -> Value {
    common::turntables(
        0.0,
        json!({
            "tendons": [{"name": "t", "joints": [{"joint": "a", "coef": 1}, {"joint": "b", "coef": 1}]}],
            "couplings": couplings
        }),
    )
}

fn env(doc: &Value) -> RobotEnv {
    env_with(
        doc,
        EnvConfig {
            dt: 0.01,
            substeps: 10,
            units: Units::Si,
            ..EnvConfig::default()
        },
    )
}

/// Joint angles (a, b) after each of `steps` steps with torque `torque` on `a`.
fn spin(doc: &Value, torque: f32, steps: usize) -> Vec<(f64, f64)> {
    let mut e = env(doc);
    (0..steps)
        .map(|_| {
            e.step(ActionType::Torque, &[torque, 0.0]).expect("steps");
            let q = e.observe().joint_positions;
            (f64::from(q[0]), f64::from(q[1]))
        })
        .collect()
}

#[test]
fn a_joint_coupling_holds_and_spins_both_at_the_shared_inertia() {
    // a = 0.1 + 2·b is held from the first substep; a torque τ on a turns the pair as one
    // body of inertia I·(1 + 1/4) seen from a: a'' = τ / (1.25·I).
    let (offset, ratio, torque) = (0.1, 2.0, 0.002f32);
    let doc = turntables(
        json!([{"name": "gear", "joint1": "a", "joint2": "b", "polycoef": [offset, ratio]}]),
    );
    let angles = spin(&doc, torque, 100);
    for (k, &(a, b)) in angles.iter().enumerate().skip(1) {
        assert!(
            (a - offset - ratio * b).abs() < 1e-5,
            "step {k}: a = {a}, b = {b}: the coupling slipped"
        );
    }
    // From the first step's state on (the offset is reached there), the pair accelerates
    // at the closed form's rate.
    let alpha = f64::from(torque) / ((1.0 + 1.0 / (ratio * ratio)) * inertia());
    let (a1, a100) = (angles[0].0, angles[99].0);
    let moved = a100 - a1;
    let t = 0.99;
    // a(t) − a(t₁) = ½α(t² − t₁²), the first step at 0.01 s.
    let expected = 0.5 * alpha * (1.0 - 0.01f64.powi(2));
    assert!(
        (moved / expected - 1.0).abs() < 0.02,
        "a moved {moved} rad in {t} s, expected {expected} (α = {alpha})"
    );
    // Uncoupled, a alone turns faster: the test can tell.
    let free = spin(&turntables(json!([])), torque, 100);
    assert!(free[99].0 - free[0].0 > 1.2 * moved);
}

#[test]
fn a_tendon_coupling_holds_the_tendon_at_its_pose_length() {
    // t = a + b held at 0: b = −a, and a torque on a turns both at τ / (2·I).
    let torque = 0.002f32;
    let doc = turntables(json!([{"name": "hold", "tendon1": "t"}]));
    let angles = spin(&doc, torque, 100);
    for (k, &(a, b)) in angles.iter().enumerate() {
        assert!((a + b).abs() < 1e-5, "step {k}: a = {a}, b = {b}");
    }
    let alpha = f64::from(torque) / (2.0 * inertia());
    let expected = 0.5 * alpha * 1.0;
    let a = angles[99].0;
    assert!(
        (a / expected - 1.0).abs() < 0.02,
        "a = {a} rad at 1 s, expected {expected}"
    );
}

#[test]
fn a_bad_coupling_is_refused_with_its_path() {
    let cases = [
        (
            json!({"name": "c", "joint1": "a", "tendon1": "t"}),
            "assembly.couplings[0].tendon1: a coupling holds a joint (joint1) or a tendon (tendon1), not both",
        ),
        (
            json!({"name": "c"}),
            "assembly.couplings[0].joint1: missing: a coupling holds a joint (joint1) or a fixed tendon (tendon1)",
        ),
        (
            json!({"name": "c", "joint1": "a", "joint2": "a"}),
            "assembly.couplings[0].joint2: \"a\" is joint1 too; a coupling is between two joints",
        ),
        (
            json!({"name": "c", "joint1": "z"}),
            "assembly.couplings[0].joint1: no joint is named \"z\"",
        ),
        (
            json!({"name": "c", "joint1": "a", "tendon2": "t"}),
            "assembly.couplings[0].tendon2: a joint coupling follows a joint (joint2), not a tendon",
        ),
        (
            json!({"name": "c", "tendon1": "u"}),
            "assembly.couplings[0].tendon1: no tendon is named \"u\"",
        ),
        (
            json!({"name": "c", "joint1": "a", "polycoef": [0, 1, 2]}),
            "assembly.couplings[0].polycoef: expected [offset] or [offset, ratio], got 3 terms",
        ),
        (
            json!({"name": "c", "joint1": "a", "polycoef": [1e9]}),
            "assembly.couplings[0].polycoef[0]: expected a number within ±1000000, got 1000000000",
        ),
        (
            json!({"name": "c", "tendon1": "t", "tendon2": "t"}),
            "assembly.couplings[0].polycoef: the coupling's two sides cancel: it holds nothing",
        ),
    ];
    for (coupling, expected) in cases {
        common::assert_refused(&turntables(json!([coupling])), expected);
    }
}

#[test]
fn a_coupling_across_two_moving_trees_is_refused() {
    // Two free bases, each with an arm on a hinge: trees no static body holds, which one
    // coupling cannot join.
    let block = |name: &str, x: f64| json!({"part": "Block", "name": name, "position": {"x": x, "y": 0, "z": 100}});
    let hinge = |name: &str, parent: &str, child: &str, x: f64| {
        json!({"type": "revolute", "name": name, "parent": parent, "child": child,
               "anchor": {"x": x, "y": 0, "z": 110}, "axis": {"x": 0, "y": 1, "z": 0}})
    };
    let doc = json!({
        "parts": [
            {"name": "Ground", "primitive": {"type": "plane"}},
            {"name": "Block", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Ground", "name": "ground"},
                block("base_a", 0.0), block("arm_a", 10.0),
                block("base_b", 100.0), block("arm_b", 110.0)
            ],
            "joints": [hinge("a", "base_a", "arm_a", 10.0), hinge("b", "base_b", "arm_b", 110.0)],
            "couplings": [{"name": "c", "joint1": "a", "joint2": "b"}]
        }
    });
    common::assert_refused(
        &doc,
        "coupling \"c\" joins joints of different kinematic trees; its joints must share one",
    );
}
