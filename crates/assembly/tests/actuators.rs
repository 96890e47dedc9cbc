//! Actuators in the assembly JSON (issue Z1b): MuJoCo's shortcuts reduced to the general
//! form `gain · input + bias`, on a joint or a fixed tendon, and every misuse refused with
//! its JSON path.

mod common;

use common::{assert_issue, base_doc, ok};
use gymfleet_assembly::{Dynamics, Transmission};
use serde_json::{json, Value};

/// The pendulum with `actuators`.
fn with(actuators: Value) -> Value {
    let mut doc = base_doc();
    doc["assembly"]["joints"][0]["name"] = json!("hinge");
    doc["assembly"]["actuators"] = actuators;
    doc
}

#[test]
fn shortcuts_reduce_to_mujocos_general_form() {
    let a = ok(with(json!([
        {"name": "servo", "type": "position", "joint": "hinge", "kp": 5, "kv": 0.5,
         "ctrl_range": [-1, 1]},
        {"name": "speed", "type": "velocity", "joint": "hinge", "kv": 2},
        {"name": "iv", "type": "intvelocity", "joint": "hinge", "kp": 3, "act_range": [-0.5, 0.5]},
        {"name": "damp", "type": "damper", "joint": "hinge", "kv": 0.3, "ctrl_range": [0, 1]},
        {"name": "cyl", "type": "cylinder", "joint": "hinge", "diameter": 0.1, "timeconst": 0.2},
        {"name": "gen", "type": "general", "joint": "hinge", "gain": [1, 2, 3],
         "bias": [4, 5, 6], "dynamics": "filterexact", "timeconst": 0.05, "gear": -2},
        {"name": "push", "joint": "hinge", "force_range": [-1, 2]}
    ])));
    let by = |name: &str| a.actuators.iter().find(|x| x.name == name).unwrap();
    let servo = by("servo");
    assert_eq!(servo.transmission, Transmission::Joint(0));
    assert_eq!(
        (servo.gain, servo.bias),
        ([5.0, 0.0, 0.0], [0.0, -5.0, -0.5])
    );
    assert_eq!(servo.ctrl_range, Some([-1.0, 1.0]));
    assert_eq!(servo.dynamics, Dynamics::None);
    assert_eq!(
        (by("speed").gain, by("speed").bias),
        ([2.0, 0.0, 0.0], [0.0, 0.0, -2.0])
    );
    assert_eq!(by("iv").dynamics, Dynamics::Integrator);
    assert_eq!(by("iv").act_range, Some([-0.5, 0.5]));
    assert_eq!(by("damp").gain, [0.0, 0.0, -0.3]);
    let cyl = by("cyl");
    assert!((cyl.gain[0] - std::f64::consts::PI / 4.0 * 0.01).abs() < 1e-15);
    assert_eq!(cyl.dynamics, Dynamics::Filter { timeconst: 0.2 });
    let gen = by("gen");
    assert_eq!(
        (gen.gain, gen.bias, gen.gear),
        ([1.0, 2.0, 3.0], [4.0, 5.0, 6.0], -2.0)
    );
    assert_eq!(gen.dynamics, Dynamics::FilterExact { timeconst: 0.05 });
    assert_eq!(by("push").gain, [1.0, 0.0, 0.0]);
    assert_eq!(by("push").force_range, Some([-1.0, 2.0]));
    // The driven joint takes no action of its own: the actions are the 7 controls.
    assert!(!a.joints[0].actuated);
    assert_eq!(a.action_dim(), 7);
}

#[test]
fn an_actuator_pulls_a_fixed_tendon() {
    let mut doc = with(json!([{"name": "pull", "tendon": "t", "gear": 2}]));
    doc["assembly"]["tendons"] =
        json!([{"name": "t", "joints": [{"joint": "hinge", "coef": 0.5}]}]);
    let a = ok(doc);
    assert_eq!(a.actuators[0].transmission, Transmission::Tendon(0));
    // The tendon's joint keeps its own action: only an actuator on a joint takes it.
    assert!(a.joints[0].actuated);
    assert_eq!(a.action_dim(), 2);
}

#[test]
fn misused_actuators_are_refused_with_their_paths() {
    assert_issue(
        with(json!([{"name": "a", "joint": "elbow"}])),
        r#"assembly.actuators[0].joint: no joint is named "elbow" (joints: "hinge")"#,
    );
    assert_issue(
        with(json!([{"name": "a"}])),
        "assembly.actuators[0].joint: expected the joint (or the tendon) the actuator drives",
    );
    assert_issue(
        with(json!([{"name": "a", "joint": "hinge", "tendon": "t"}])),
        "assembly.actuators[0].tendon: an actuator drives one joint or one tendon, not both",
    );
    assert_issue(
        with(json!([{"name": "a", "tendon": "t"}])),
        r#"assembly.actuators[0].tendon: no tendon is named "t" (tendons: none)"#,
    );
    assert_issue(
        with(json!([{"name": "a", "joint": "hinge", "kp": 1}])),
        "assembly.actuators[0].kp: a motor actuator has no kp (it reads only gear, ctrl_range and force_range)",
    );
    assert_issue(
        with(json!([{"name": "a", "type": "position", "joint": "hinge", "kv": 1, "dampratio": 1}])),
        "assembly.actuators[0].dampratio: give kv or dampratio, not both (kv is the damping, dampratio the damping as a ratio of critical)",
    );
    assert_issue(
        with(json!([{"name": "a", "type": "general", "joint": "hinge", "dampratio": 1}])),
        "assembly.actuators[0].dampratio: dampratio needs a position-like actuator (gain[0] = −bias[1]), got gain[0] = 1 and bias[1] = 0",
    );
    assert_issue(
        with(json!([{"name": "a", "type": "damper", "joint": "hinge", "kv": 1}])),
        "assembly.actuators[0].ctrl_range: a damper needs a ctrl_range, its coefficient's bounds (min >= 0)",
    );
    assert_issue(
        with(json!([{"name": "a", "type": "general", "joint": "hinge", "act_range": [0, 1]}])),
        "assembly.actuators[0].act_range: an actuator without activation dynamics has no activation to clamp",
    );
    assert_issue(
        with(
            json!([{"name": "a", "type": "general", "joint": "hinge", "dynamics": "filter", "timeconst": 0}]),
        ),
        "assembly.actuators[0].timeconst: expected a filter time constant in (0, 1e9] s, got 0",
    );
    assert_issue(
        with(json!([{"name": "a", "joint": "hinge", "ctrl_range": [1, -1]}])),
        "assembly.actuators[0].ctrl_range: expected [min, max] with min < max, each within ±1e9, got [1, -1]",
    );
    assert_issue(
        with(json!([{"name": "a", "joint": "hinge", "gear": 1e10}])),
        "assembly.actuators[0].gear: expected a number within ±1e9, got 10000000000",
    );
    assert_issue(
        with(
            json!([{"name": "a", "type": "cylinder", "joint": "hinge", "area": 1, "diameter": 1}]),
        ),
        "assembly.actuators[0].diameter: give area or diameter, not both",
    );
    let mut doc = with(json!([{"name": "a", "joint": "hinge"}]));
    doc["assembly"]["joints"][0]["type"] = json!("ball");
    doc["assembly"]["joints"][0]
        .as_object_mut()
        .unwrap()
        .remove("axis");
    assert_issue(
        doc,
        r#"assembly.actuators[0].joint: "hinge" is a ball joint; an actuator drives a revolute or prismatic joint"#,
    );
    let mut doc = with(json!([{"name": "a", "joint": "hinge"}]));
    doc["assembly"]["joints"][0]["gear"] = json!(2);
    assert_issue(
        doc,
        r#"assembly.joints[0].gear: joint "hinge" is driven by actuator "a", and takes no action of its own; put gear and ranges on the actuator and remove gear"#,
    );
}
