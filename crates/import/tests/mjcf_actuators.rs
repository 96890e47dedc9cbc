//! `<actuator>` (issue Z1b): each element converts to MuJoCo's compiled general form, class
//! defaults as MuJoCo's reader applies them (one actuator default per class, whatever the
//! tag), actions in `<actuator>` order. (Forces and activations are compared with MuJoCo
//! itself in `client/python/tests/test_actuators.py`.)

mod common;

use common::env;
use gymfleet_env::ActionType;
use gymfleet_import::mjcf_to_document;
use serde_json::{json, Value};

/// Two hinges about y hanging from the world (`a`, then `b`), a fixed tendon over both, and
/// `actuators`.
fn model(defaults: &str, actuators: &str) -> String {
    format!(
        r#"<mujoco>
  <default>{defaults}</default>
  <worldbody>
    <body name="upper" pos="0 0 1"><joint name="a" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" contype="0" conaffinity="0"/>
      <body name="lower" pos="0.2 0 0"><joint name="b" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <tendon><fixed name="t"><joint joint="a" coef="1"/><joint joint="b" coef="-0.5"/></fixed></tendon>
  <actuator>{actuators}</actuator>
</mujoco>"#
    )
}

fn actuators(xml: &str) -> Value {
    let converted = mjcf_to_document(xml).expect("converts");
    converted.document["assembly"]["actuators"].clone()
}

#[test]
fn motors_in_the_joints_order_drive_the_joints_directly() {
    let xml = model(
        "",
        r#"<motor joint="a" gear="2"/><motor joint="b" ctrlrange="-1 1"/>"#,
    );
    assert_eq!(
        actuators(&xml),
        Value::Null,
        "no actuators: the joints take the values"
    );
    let (env, _) = env(&xml, &[]);
    assert_eq!(env.spec().action_dim, 2);
    assert!(env.spec().dofs.iter().all(|d| d.actuated));
    assert_eq!(env.spec().dofs[0].gear, 2.0);
}

#[test]
fn any_other_actuator_makes_the_actions_mujocos_ctrl_in_actuator_order() {
    let xml = model(
        r#"<position kp="4" ctrlrange="-1 1"/>"#,
        r#"<motor name="m" joint="b" gear="3"/>
           <position name="p" joint="a" dampratio="0.5"/>
           <general name="g" tendon="t" dyntype="filter" dynprm="0.2" gear="2"/>"#,
    );
    let list = actuators(&xml);
    assert_eq!(
        list,
        json!([
            // The class's position default set gain and bias; <motor> resets them, but
            // keeps its ctrlrange.
            {"name": "m", "type": "general", "joint": "b", "gear": 3.0,
             "ctrl_range": [-1.0, 1.0], "gain": [1.0, 0.0, 0.0]},
            {"name": "p", "type": "general", "joint": "a", "ctrl_range": [-1.0, 1.0],
             "gain": [4.0, 0.0, 0.0], "bias": [0.0, -4.0, 0.0], "dampratio": 0.5},
            // <general> starts from the class default: position-like, with a filter.
            {"name": "g", "type": "general", "tendon": "t", "gear": 2.0,
             "ctrl_range": [-1.0, 1.0], "gain": [4.0, 0.0, 0.0], "bias": [0.0, -4.0, 0.0],
             "dynamics": "filter", "timeconst": 0.2}
        ])
    );
    let (mut env, _) = env(&xml, &[]);
    let spec = env.spec().clone();
    assert_eq!(spec.action_dim, 3);
    let targets: Vec<&str> = spec.actuators.iter().map(|a| a.target.as_str()).collect();
    assert_eq!(targets, ["b", "a", "t"]);
    assert!(spec.dofs.iter().all(|d| !d.actuated));
    // A control beyond the range is clamped, and the servo holds joint `a` near it.
    let mut last = None;
    for _ in 0..2400 {
        last = Some(
            env.step(ActionType::Torque, &[0.0, 3.0, 0.0])
                .expect("steps"),
        );
    }
    let angle = last.expect("stepped").observation.joint_positions[0];
    assert!(
        (angle.to_radians() - 1.0).abs() < 0.35,
        "the servo's joint sits at {angle} deg, its clamped target 1 rad (57.3 deg) less gravity's sag"
    );
}

#[test]
fn unnamed_actuators_get_names_and_unknown_targets_name_their_line() {
    let xml = model(
        "",
        r#"<velocity joint="a"/><damper joint="b" kv="1" ctrlrange="0 1"/>"#,
    );
    let list = actuators(&xml);
    assert_eq!(list[0]["name"], "actuator0");
    assert_eq!(list[1]["name"], "actuator1");
    assert_eq!(list[1]["gain"], json!([0.0, 0.0, -1.0]));
    let err = mjcf_to_document(&model("", r#"<position joint="c"/>"#)).unwrap_err();
    assert_eq!(
        err.to_string(),
        "line 12: <position joint=…>: no hinge, slide or ball joint is named \"c\""
    );
}

#[test]
fn a_range_inherited_from_the_joint_is_refused_even_from_a_class() {
    let err = mjcf_to_document(&model(
        r#"<position inheritrange="1"/>"#,
        r#"<position joint="a"/>"#,
    ))
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "line 12: <position inheritrange=…>: \"1\": inheritrange is not supported yet; give ctrlrange"
    );
    // 0, MuJoCo's "off", is no range at all.
    let list = actuators(&model(
        r#"<position inheritrange="0"/>"#,
        r#"<position joint="a"/>"#,
    ));
    assert_eq!(list[0]["gain"], json!([1.0, 0.0, 0.0]));
}

#[test]
fn each_refused_actuator_names_its_element_line_and_reason() {
    let refused = |defaults: &str, actuators: &str| {
        mjcf_to_document(&model(defaults, actuators))
            .unwrap_err()
            .to_string()
    };
    for (actuator, expected) in [
        (
            r#"<motor joint="a" gear="1 0 0 1 0 0"/>"#,
            "line 12: <motor>: gear [1.0, 0.0, 0.0, 1.0, 0.0, 0.0]: only the first component of a gear is used by joint and tendon transmissions",
        ),
        (
            r#"<general joint="a" actdim="2"/>"#,
            "line 12: <general>: actdim \"2\": an actuator has one activation at most here",
        ),
        (
            r#"<adhesion body="upper"/>"#,
            "line 12: <adhesion>: adhesion actuators are not supported (they act on contacts)",
        ),
        (
            r#"<dcmotor joint="a"/>"#,
            "line 12: <dcmotor>: this actuator type is not supported (supported: motor, position, velocity, intvelocity, damper, cylinder, general)",
        ),
        (r#"<general/>"#, "line 12: <general>: an actuator must drive a joint or a tendon"),
        (
            r#"<general joint="a" body="upper"/>"#,
            "line 12: <general>: body transmissions are not supported (an actuator drives a joint or a tendon)",
        ),
        (r#"<position joint="a" kv="-1"/>"#, "line 12: <position kv=…>: cannot be negative, got -1"),
        (
            r#"<general joint="a" dyntype="filter" dynprm="0"/>"#,
            "line 12: <general timeconst=…>: a filter's time constant must be positive, got 0",
        ),
        (
            r#"<general joint="a" gainprm="1 0 0 2"/>"#,
            "line 12: <general>: gainprm [1.0, 0.0, 0.0, 2.0]: only the first three parameters are used by the affine form",
        ),
        (
            r#"<general joint="a" ctrllimited="yes"/>"#,
            "line 12: <general ctrllimited=…>: expected true, false or auto, got \"yes\"",
        ),
        (
            r#"<general joint="a" ctrlrange="1"/>"#,
            "line 12: <general ctrlrange=…>: expected 2 numbers, got 1",
        ),
        (
            r#"<general joint="a" class="servo"/>"#,
            "line 12: <general class=…>: no default class is named \"servo\"",
        ),
        (r#"<bogus joint="a"/>"#, "line 12: <bogus>: is not an actuator"),
    ] {
        assert_eq!(refused("", actuator), expected, "{actuator}");
    }
    // A default's bad value is named at the actuator that reads it.
    assert_eq!(
        refused(r#"<velocity kv="fast"/>"#, r#"<velocity joint="a"/>"#),
        "line 12: <velocity kv=…>: expected finite numbers, got \"fast\""
    );
}
