//! `<sensor>` (issue Z2): MuJoCo's sensors become the document's `assembly.sensors`, in
//! order, on the sites, instances, joints, actuators and tendons the conversion made; what
//! gymfleet has no sensor for is skipped with a warning; a sensor naming nothing is refused.

mod common;

use common::error;
use gymfleet_import::mjcf_to_document;
use serde_json::json;

/// A hinge arm with a site, a geom named `palm`, a world site, a fixed tendon and a motor;
/// then `sensors`.
fn model(sensors: &str) -> String {
    format!(
        r#"<mujoco><option magnetic="0 0 -0.4"/><worldbody>
  <site name="mark" pos="1 0 0"/>
  <body name="arm"><joint name="hinge" type="hinge" axis="0 1 0"/><geom name="palm" size=".1"/>
    <site name="tip" pos="0 0 -.3"/>
    <body name="hand" pos="0 0 -.3"><joint name="wrist" type="ball"/><geom size=".05"/></body>
  </body>
</worldbody>
<tendon><fixed name="t"><joint joint="hinge" coef="2"/></fixed></tendon>
<actuator><motor name="m" joint="hinge" gear="3"/></actuator>
<sensor>{sensors}</sensor>
</mujoco>"#
    )
}

#[test]
fn sensors_convert_in_order_onto_what_the_conversion_made() {
    let xml = model(
        r#"<jointpos name="angle" joint="hinge"/>
<actuatorfrc actuator="m" cutoff="2" noise="0.1"/>
<tendonvel tendon="t"/>
<framepos name="tip_pos" objtype="site" objname="tip" reftype="site" refname="mark"/>
<framequat name="arm_quat" objtype="xbody" objname="arm"/>
<frameyaxis name="palm_y" objtype="geom" objname="palm"/>
<subtreecom name="com" body="arm"/>
<touch name="pad" site="tip"/>
<ballquat name="wrist_quat" joint="wrist"/>
<rangefinder name="look" site="tip"/>"#,
    );
    let c = mjcf_to_document(&xml).expect("converts");
    let sensors = &c.document["assembly"]["sensors"];
    assert_eq!(
        sensors,
        &json!([
            {"name": "angle", "type": "jointpos", "joint": "hinge"},
            // Plain joint motors are the joints' own actions: the motor reads its joint's.
            {"name": "sensor1", "type": "actuatorfrc", "actuator": "hinge", "cutoff": 2.0, "noise": 0.1},
            {"name": "sensor2", "type": "tendonvel", "tendon": "t"},
            {"name": "tip_pos", "type": "framepos", "site": "tip", "reference": {"site": "mark"}},
            {"name": "arm_quat", "type": "framequat", "site": "arm"},
            {"name": "palm_y", "type": "frameyaxis", "instance": "palm"},
            {"name": "com", "type": "subtreecom", "instance": "palm"},
            {"name": "pad", "type": "touch", "site": "tip"},
            {"name": "look", "type": "rangefinder", "site": "tip"}
        ])
    );
    assert_eq!(
        c.document["simulation"]["magnetic"],
        json!({"x": 0.0, "y": 0.0, "z": -0.4})
    );
    let warned = |needle: &str| c.warnings.iter().any(|w| w.contains(needle));
    assert!(
        warned("<ballquat> skipped: gymfleet has no such sensor yet"),
        "{:?}",
        c.warnings
    );
    // The touch sensor's site keeps its volume (MuJoCo's default: a 5 mm sphere).
    let tip = c.document["assembly"]["sites"]
        .as_array()
        .and_then(|s| s.iter().find(|s| s["name"] == "tip"))
        .expect("the tip site");
    assert_eq!(
        tip["volume"],
        json!({"type": "sphere", "size": {"x": 5.0, "y": 5.0, "z": 5.0}})
    );
    assert!(!warned("magnetic"), "{:?}", c.warnings);
    // The converted document validates: every sensor names what exists.
    gymfleet_assembly::parse(&c.document.to_string()).expect("a valid document");
}

#[test]
fn an_inertial_body_frame_is_skipped_with_a_warning() {
    let c = mjcf_to_document(&model(
        r#"<framepos name="p" objtype="body" objname="arm"/><jointvel joint="hinge"/>"#,
    ))
    .expect("converts");
    assert_eq!(
        c.document["assembly"]["sensors"],
        json!([{"name": "sensor1", "type": "jointvel", "joint": "hinge"}]),
        "the unnamed sensor keeps its index among the model's sensors"
    );
    assert!(
        c.warnings
            .iter()
            .any(|w| w.contains("skipped: objtype=\"body\" (MuJoCo's inertial body frame, or a camera) is not converted yet")),
        "{:?}",
        c.warnings
    );
}

#[test]
fn a_sensor_naming_nothing_is_refused_with_its_line() {
    for (sensor, expected) in [
        (
            r#"<touch site="nowhere"/>"#,
            "<touch site=…>: no site is named \"nowhere\"",
        ),
        (r#"<gyro/>"#, "<gyro site=…>: missing"),
        (
            r#"<jointpos joint="wrist"/>"#,
            "<jointpos joint=…>: no hinge or slide joint is named \"wrist\"",
        ),
        (
            r#"<subtreecom body="leg"/>"#,
            "<subtreecom body=…>: no body is named \"leg\"",
        ),
        (
            r#"<framepos objtype="joint" objname="hinge"/>"#,
            "<framepos objtype=…>: expected site, xbody, body, geom or camera, got \"joint\"",
        ),
        (
            r#"<framepos objtype="geom" objname="fist"/>"#,
            "<framepos objname=…>: no geom is named \"fist\"",
        ),
        (
            r#"<touch site="tip" cutoff="-1"/>"#,
            "<touch cutoff=…>: expected a number ≥ 0, got -1",
        ),
    ] {
        let e = error(&model(sensor));
        assert!(e.contains("line 10: "), "{e}");
        assert!(e.contains(expected), "{e}\nexpected: {expected}");
    }
}
