//! Semantic errors: each is reported once, with the JSON path of the offending field
//! and what was expected; several independent errors are all reported, in order.

mod common;

use common::{assert_issue, base_doc, blocks_doc, err, ok, revolute};
use serde_json::{json, Value};

/// `blocks_doc(names)` with the given joints.
fn jointed(names: &[&str], joints: Vec<Value>) -> Value {
    let mut doc = blocks_doc(names);
    doc["assembly"]["joints"] = Value::Array(joints);
    doc
}

/// The base document with one field of its only joint set.
fn with_joint_field(field: &str, value: Value) -> Value {
    let mut doc = base_doc();
    doc["assembly"]["joints"][0][field] = value;
    doc
}

/// The base document with its only joint of another type.
fn with_joint_type(kind: &str) -> Value {
    with_joint_field("type", json!(kind))
}

#[test]
fn unknown_part() {
    let mut doc = base_doc();
    doc["assembly"]["instances"][1]["part"] = json!("Forarm");
    assert_issue(
        doc,
        r#"assembly.instances[1].part: unknown part "Forarm" (known: "Arm", "Base")"#,
    );
}

#[test]
fn unknown_joint_child() {
    let names = ["base", "upper", "forearm"];
    let doc = jointed(
        &names,
        vec![revolute("base", "upper"), revolute("upper", "forarm")],
    );
    assert_issue(
        doc,
        r#"assembly.joints[1].child: unknown instance "forarm" (known: "base", "forearm", "upper")"#,
    );
}

#[test]
fn unknown_joint_parent() {
    let names = ["base", "upper", "forearm"];
    let doc = jointed(
        &names,
        vec![revolute("base", "upper"), revolute("uper", "forearm")],
    );
    assert_issue(
        doc,
        r#"assembly.joints[1].parent: unknown instance "uper" (known: "base", "forearm", "upper")"#,
    );
}

#[test]
fn duplicate_part_names() {
    let mut doc = base_doc();
    doc["parts"][1]["name"] = json!("Base");
    doc["assembly"]["instances"][1]["part"] = json!("Base");
    assert_issue(
        doc,
        r#"parts[1].name: duplicate part name "Base" (also parts[0]): part names must be unique"#,
    );
}

#[test]
fn duplicate_instance_names_point_at_the_first() {
    assert_issue(
        blocks_doc(&["a", "b", "a"]),
        r#"assembly.instances[2].name: duplicate instance name "a" (also assembly.instances[0]): instance names must be unique"#,
    );
    let e = err(blocks_doc(&["a", "a", "a"]));
    let also: Vec<bool> = e
        .issues()
        .iter()
        .map(|i| i.message.contains("(also assembly.instances[0])"))
        .collect();
    assert_eq!(also, [true, true], "{e}");
}

#[test]
fn empty_instance_name() {
    assert_issue(
        blocks_doc(&[""]),
        "assembly.instances[0].name: expected a non-empty instance name",
    );
}

#[test]
fn duplicate_joint_names() {
    let named = |parent, child| {
        let mut j = revolute(parent, child);
        j["name"] = json!("hinge");
        j
    };
    let doc = jointed(&["g", "a", "b"], vec![named("g", "a"), named("a", "b")]);
    assert_issue(
        doc,
        r#"assembly.joints[1].name: duplicate joint name "hinge" (also assembly.joints[0]); give one of them a "name""#,
    );
    // An explicit name may clash with another joint's default (its child's name).
    let mut second = revolute("a", "b");
    second["name"] = json!("a");
    let doc = jointed(&["g", "a", "b"], vec![revolute("g", "a"), second]);
    assert_issue(
        doc,
        r#"assembly.joints[1].name: duplicate joint name "a" (also assembly.joints[0]); give one of them a "name""#,
    );
}

#[test]
fn zero_axis() {
    assert_issue(
        with_joint_field("axis", json!({ "x": 0, "y": 0, "z": 0 })),
        "assembly.joints[0].axis: expected a non-zero finite direction, got {x: 0, y: 0, z: 0}",
    );
}

#[test]
fn missing_axis() {
    for kind in ["revolute", "prismatic", "cylindrical"] {
        let mut doc = with_joint_type(kind);
        doc["assembly"]["joints"][0]
            .as_object_mut()
            .unwrap()
            .remove("axis");
        assert_issue(
            doc,
            &format!("assembly.joints[0].axis: missing field `axis`: a {kind} joint needs an axis"),
        );
    }
}

#[test]
fn missing_anchor() {
    for kind in ["revolute", "ball"] {
        let mut doc = with_joint_type(kind);
        doc["assembly"]["joints"][0]
            .as_object_mut()
            .unwrap()
            .remove("anchor");
        assert_issue(
            doc,
            &format!("assembly.joints[0].anchor: missing field `anchor`: a {kind} joint needs an anchor (world mm)"),
        );
    }
}

#[test]
fn min_above_max() {
    let mut doc = with_joint_field("min", json!(10));
    doc["assembly"]["joints"][0]["max"] = json!(-10);
    assert_issue(
        doc.clone(),
        "assembly.joints[0].min: expected min <= max, got min 10 > max -10 (deg)",
    );
    doc["assembly"]["joints"][0]["type"] = json!("prismatic");
    assert_issue(
        doc,
        "assembly.joints[0].min: expected min <= max, got min 10 > max -10 (mm)",
    );
}

#[test]
fn non_positive_sizes() {
    let cases = [
        (
            json!({ "type": "cube", "size": { "x": -1, "y": 4, "z": 40 } }),
            "size.x",
            "-1",
        ),
        (
            json!({ "type": "cube", "size": { "x": 4, "y": 0, "z": 40 } }),
            "size.y",
            "0",
        ),
        (
            json!({ "type": "cylinder", "radius": 0, "height": 40 }),
            "radius",
            "0",
        ),
        (
            json!({ "type": "cylinder", "radius": 2, "height": -40 }),
            "height",
            "-40",
        ),
        (json!({ "type": "sphere", "radius": 0 }), "radius", "0"),
        (
            json!({ "type": "sphere", "radius": -3.5 }),
            "radius",
            "-3.5",
        ),
    ];
    for (primitive, field, got) in cases {
        let mut doc = base_doc();
        doc["parts"][1]["primitive"] = primitive;
        assert_issue(
            doc,
            &format!("parts[1].primitive.{field}: expected a positive length in mm, got {got}"),
        );
    }
}

#[test]
fn child_with_two_parents() {
    // "b" is a free body, not otherwise joined to "a": the second parent closes no loop.
    let doc = jointed(
        &["g", "a", "b"],
        vec![revolute("g", "a"), revolute("b", "a")],
    );
    assert_issue(
        doc,
        r#"assembly.joints[1].child: instance "a" already has parent "g"; a second parent is only for a joint that closes a kinematic loop, and "b" is not otherwise joined to "a""#,
    );
}

#[test]
fn a_kinematic_loop_is_accepted_and_closed_by_the_joint_the_tree_cannot_take() {
    let mut joints = vec![revolute("g", "a"), revolute("a", "b"), revolute("b", "c")];
    joints.push(revolute("c", "a"));
    joints[1]["actuated"] = json!(false);
    joints[3]["name"] = json!("c_a");
    let a = ok(jointed(&["g", "a", "b", "c"], joints));
    let closes: Vec<bool> = a.joints.iter().map(|j| j.closes_loop).collect();
    // The tree takes the actuated joints first: "g" -> "a", "b" -> "c" ("c" -> "a" would
    // give "a" a second parent), then the passive "a" -> "b". "c" -> "a" closes the loop.
    assert_eq!(closes, [false, false, false, true]);
    assert!(!a.joints[3].actuated, "a loop-closing joint is passive");
    assert_eq!(a.total_dof(), 4, "every joint is observed");
    assert_eq!(a.num_movable_joints(), 3, "three tree joints");
}

#[test]
fn a_loop_closing_joint_that_is_driven_is_refused() {
    let mut joints = vec![revolute("g", "a"), revolute("a", "b"), revolute("g", "b")];
    joints[2]["actuated"] = json!(true);
    joints[2]["name"] = json!("closer");
    assert_issue(
        jointed(&["g", "a", "b"], joints),
        r#"assembly.joints[2].actuated: joint "g" -> "b" closes a kinematic loop, and a loop-closing joint is passive; remove "actuated": true, or mark another joint of the loop "actuated": false so that this one joins the tree (the tree takes actuated joints first)"#,
    );
}

#[test]
fn a_joint_on_a_loop_starts_at_the_document_pose() {
    let mut joints = vec![revolute("g", "a"), revolute("a", "b"), revolute("g", "b")];
    joints[1]["initial"] = json!(10.0);
    joints[2]["name"] = json!("closer");
    assert_issue(
        jointed(&["g", "a", "b"], joints),
        r#"assembly.joints[1].initial: joint "b" is on the kinematic loop that joint "closer" closes; an initial position would open the loop (loops start at the document's pose): remove "initial""#,
    );
}

#[test]
fn only_a_loop_closing_joint_may_be_unobserved() {
    let mut joints = vec![revolute("g", "a")];
    joints[0]["observed"] = json!(false);
    assert_issue(
        jointed(&["g", "a"], joints),
        r#"assembly.joints[0].observed: only a joint that closes a kinematic loop may be unobserved, and "g" and "a" are not otherwise joined; remove "observed": false"#,
    );
}

#[test]
fn joint_to_itself() {
    let mut doc = with_joint_field("parent", json!("arm"));
    doc["assembly"]["joints"][0]["child"] = json!("arm");
    assert_issue(
        doc,
        r#"assembly.joints[0].child: joint connects instance "arm" to itself; parent and child must differ"#,
    );
}

#[test]
fn grounded_instance_as_child() {
    let mut doc = with_joint_field("parent", json!("arm"));
    doc["assembly"]["joints"][0]["child"] = json!("base");
    assert_issue(
        doc,
        r#"assembly.joints[0].child: instance "base" is grounded (the first instance) and cannot be a joint child; swap parent and child"#,
    );
}

#[test]
fn floating_base_as_child() {
    let mut doc = with_joint_field("parent", json!("arm"));
    doc["assembly"]["joints"][0]["child"] = json!("base");
    doc["floating_base"] = json!(true);
    assert_issue(
        doc,
        r#"assembly.joints[0].child: instance "base" is the floating base (the first instance), the root of the tree, and cannot be a joint child; swap parent and child"#,
    );
}

/// A plane is a ground wherever it is listed: a fixed body that no joint may move.
#[test]
fn plane_as_joint_child() {
    let mut doc = base_doc();
    doc["parts"][1]["primitive"] = json!({"type": "plane"});
    assert_issue(
        doc,
        r#"assembly.joints[0].child: instance "arm" is a plane or heightfield, a ground fixed to the world, and cannot be a joint child; swap parent and child"#,
    );
}

#[test]
fn plane_as_floating_base() {
    let mut doc = base_doc();
    doc["parts"][0]["primitive"] = json!({"type": "plane"});
    doc["floating_base"] = json!(true);
    assert_issue(
        doc,
        r#"assembly.instances[0].part: part "Base" is a plane (a half-space, a ground), which cannot be the floating base (the first instance); list the robot's base first"#,
    );
}

#[test]
fn floating_base_is_a_boolean() {
    let mut doc = base_doc();
    doc["floating_base"] = json!("yes");
    let e = err(doc);
    common::assert_malformed(
        &e,
        "floating_base",
        "invalid type: string \"yes\", expected a boolean",
    );
}

/// With a floating base the first instance is free and every plane is grounded, wherever
/// it is listed.
#[test]
fn floating_base_frees_the_first_instance_and_grounds_planes() {
    let mut doc = base_doc();
    doc["floating_base"] = json!(true);
    doc["parts"]
        .as_array_mut()
        .unwrap()
        .push(json!({"name": "Floor", "primitive": {"type": "plane"}}));
    doc["assembly"]["instances"]
        .as_array_mut()
        .unwrap()
        .push(json!({"part": "Floor", "name": "floor"}));
    let a = common::ok(doc.clone());
    assert!(a.floating_base);
    let grounded: Vec<bool> = a.instances.iter().map(|i| i.grounded).collect();
    assert_eq!(grounded, [false, false, true]);
    doc["floating_base"] = json!(false);
    let a = common::ok(doc);
    assert!(!a.floating_base);
    let grounded: Vec<bool> = a.instances.iter().map(|i| i.grounded).collect();
    assert_eq!(grounded, [true, false, true]);
}

#[test]
fn friction_errors_name_the_field() {
    assert_issue(
        with_joint_field("friction", json!(-0.5)),
        "assembly.joints[0].friction: expected a friction >= 0 (N·m or N), got -0.5",
    );
    let mut doc = with_joint_type("fixed");
    doc["assembly"]["joints"][0]["friction"] = json!(1);
    assert_issue(
        doc,
        "assembly.joints[0].friction: a fixed joint has no DOF to resist with friction",
    );
    let a = common::ok(with_joint_field("friction", json!(0.25)));
    assert_eq!(a.joints[0].friction, 0.25);
}

#[test]
fn gear_and_reference_errors_name_the_field() {
    assert_issue(
        with_joint_field("gear", json!(0)),
        "assembly.joints[0].gear: expected a finite, non-zero gear within ±1e9, got 0",
    );
    assert_issue(
        with_joint_field("gear", json!(1e300)),
        "assembly.joints[0].gear: expected a finite, non-zero gear within ±1e9, got 1e300",
    );
    let mut doc = with_joint_type("ball");
    doc["assembly"]["joints"][0]["gear"] = json!(2);
    assert_issue(
        doc,
        "assembly.joints[0].gear: a gear needs a revolute or prismatic joint, not a ball joint",
    );
    let mut doc = with_joint_field("gear", json!(2));
    doc["assembly"]["joints"][0]["actuated"] = json!(false);
    assert_issue(
        doc,
        "assembly.joints[0].gear: a passive joint (\"actuated\": false) has no motor to gear; remove gear or the actuated flag",
    );
    assert_issue(
        with_joint_field("reference", json!(-2e9)),
        "assembly.joints[0].reference: expected a finite position within ±1e9 (deg or mm), got -2e9",
    );
    let mut doc = with_joint_type("fixed");
    doc["assembly"]["joints"][0]["reference"] = json!(1);
    assert_issue(
        doc,
        "assembly.joints[0].reference: a reference position needs a revolute or prismatic joint, not a fixed joint",
    );
    let mut doc = with_joint_field("gear", json!(-120));
    doc["assembly"]["joints"][0]["reference"] = json!(30);
    let a = common::ok(doc);
    assert_eq!((a.joints[0].gear, a.joints[0].reference), (-120.0, 30.0));
}

#[test]
fn site_errors_name_the_site() {
    let mut doc = with_joint_field("damping", json!(0));
    let instance = doc["assembly"]["instances"][1]["name"].clone();
    doc["assembly"]["sites"] = json!([
        {"name": "tip", "instance": instance, "point": {"x": 0, "y": 0, "z": 10}},
        {"name": "tip", "instance": instance, "point": {"x": 0, "y": 0, "z": 1}}
    ]);
    assert_issue(
        doc.clone(),
        "assembly.sites[1].name: \"tip\" names an earlier site too; site names must be unique",
    );
    doc["assembly"]["sites"][1] =
        json!({"name": "toe", "instance": "hand", "point": {"x": 0, "y": 0, "z": 1e9}});
    let e = err(doc.clone()).to_string();
    assert!(
        e.contains("assembly.sites[1].instance: unknown instance \"hand\" (known: ")
            && e.contains(
                "assembly.sites[1].point.z: expected a finite coordinate within ±1e8 mm, got 1e9"
            ),
        "{e}"
    );
    doc["assembly"]["sites"]
        .as_array_mut()
        .expect("sites")
        .pop();
    let a = common::ok(doc);
    assert_eq!(a.sites.len(), 1);
    assert_eq!(
        (a.sites[0].instance, a.sites[0].point),
        (1, [0.0, 0.0, 10.0])
    );
    assert_eq!(a.site_index("tip"), Some(0));
}

#[test]
fn spring_errors_name_the_field() {
    assert_issue(
        with_joint_field("stiffness", json!(-1)),
        "assembly.joints[0].stiffness: expected a stiffness >= 0 in N·m/rad, got -1",
    );
    let mut doc = with_joint_type("ball");
    doc["assembly"]["joints"][0]["stiffness"] = json!(2);
    assert_issue(
        doc,
        "assembly.joints[0].stiffness: a ball joint takes no spring; stiffness applies to revolute and prismatic joints only",
    );
    assert_issue(
        with_joint_field("spring_rest", json!(10)),
        "assembly.joints[0].spring_rest: a spring rest position needs a `stiffness` or a `springdamper`",
    );
    let mut doc = with_joint_field("stiffness", json!(2));
    doc["assembly"]["joints"][0]["spring_rest"] = json!(12345.5);
    let text = doc.to_string().replace("12345.5", "1e999");
    let e = common::err_text(&text);
    assert!(
        e.to_string().contains("spring_rest"),
        "an infinite rest is refused at its field: {e}"
    );
    let a = common::ok({
        let mut doc = with_joint_field("stiffness", json!(2));
        doc["assembly"]["joints"][0]["spring_rest"] = json!(30);
        doc
    });
    assert_eq!(a.joints[0].stiffness, 2.0);
    assert!((a.joints[0].spring_rest - 30f64.to_radians()).abs() < 1e-12);
}

#[test]
fn empty_assembly() {
    let mut doc = base_doc();
    doc["assembly"] = json!({ "instances": [], "joints": [] });
    assert_issue(
        doc,
        "assembly.instances: expected at least one instance (the first one is grounded)",
    );
    let mut doc = base_doc();
    doc["assembly"] = json!({ "instances": [], "joints": [] });
    doc["floating_base"] = json!(true);
    assert_issue(
        doc,
        "assembly.instances: expected at least one instance (the first one is the floating base)",
    );
}

#[test]
fn limits_on_a_joint_without_limits() {
    for (kind, field) in [("ball", "min"), ("cylindrical", "max"), ("fixed", "min")] {
        let mut doc = with_joint_type(kind);
        doc["assembly"]["joints"][0][field] = json!(5);
        if kind == "fixed" {
            doc["assembly"]["joints"][0]["max"] = json!(10);
        }
        assert_issue(
            doc,
            &format!("assembly.joints[0].{field}: a {kind} joint has no limits; min/max apply to revolute and prismatic joints only"),
        );
    }
}

#[test]
fn unknown_material_on_part() {
    let mut doc = base_doc();
    doc["parts"][1]["material"] = json!("steel");
    assert_issue(
        doc,
        r#"parts[1].material: unknown material "steel" (known: none)"#,
    );
}

#[test]
fn unknown_material_on_instance() {
    let mut doc = base_doc();
    doc["materials"] = json!({ "aluminium": {}, "steel": { "density": 7850 } });
    doc["assembly"]["instances"][1]["material"] = json!("steal");
    assert_issue(
        doc,
        r#"assembly.instances[1].material: unknown material "steal" (known: "aluminium", "steel")"#,
    );
}

#[test]
fn bad_material_values() {
    let cases = [
        (
            "density",
            json!(-1),
            "expected a positive density in kg/m³, got -1",
        ),
        (
            "density",
            json!(0),
            "expected a positive density in kg/m³, got 0",
        ),
        (
            "friction",
            json!(-0.1),
            "expected a friction coefficient >= 0, got -0.1",
        ),
        (
            "restitution",
            json!(1.5),
            "expected a restitution in [0, 1], got 1.5",
        ),
        (
            "restitution",
            json!(-0.5),
            "expected a restitution in [0, 1], got -0.5",
        ),
    ];
    for (field, value, message) in cases {
        let mut doc = base_doc();
        doc["materials"] = json!({ "bad": { field: value } });
        assert_issue(doc, &format!("materials.bad.{field}: {message}"));
    }
}

#[test]
fn bad_soft_contacts_name_their_field() {
    let cases = [
        (
            "solref",
            json!([0.02, -1.0]),
            "expected [time constant s > 0, damping ratio > 0] or [-stiffness < 0, -damping <= 0], got [0.02, -1.0]",
        ),
        (
            "solref",
            json!([0.0, 0.0]),
            "expected [time constant s > 0, damping ratio > 0] or [-stiffness < 0, -damping <= 0], got [0.0, 0.0]",
        ),
        (
            "solimp",
            json!([0.9, 1.0, 1.0, 0.5, 2.0]),
            "expected [dmin, dmax in (0, 1), width mm >= 0, midpoint in (0, 1), power >= 1], got [0.9, 1.0, 1.0, 0.5, 2.0]",
        ),
        (
            "solimp",
            json!([0.9, 0.95, 1.0, 0.5, 0.5]),
            "expected [dmin, dmax in (0, 1), width mm >= 0, midpoint in (0, 1), power >= 1], got [0.9, 0.95, 1.0, 0.5, 0.5]",
        ),
        ("solmix", json!(-1.0), "expected a weight >= 0, got -1"),
        ("margin", json!(-2.0), "expected a distance in mm >= 0, got -2"),
        ("gap", json!(-0.5), "expected a distance in mm >= 0, got -0.5"),
        ("impratio", json!(0.0), "expected a ratio > 0, got 0"),
        (
            "condim",
            json!(5),
            "expected 1 (frictionless), 3 (sliding), 4 (and torsional) or 6 (and rolling friction), got 5",
        ),
        (
            "torsional_friction",
            json!(-1.0),
            "expected a distance in mm >= 0, got -1",
        ),
        (
            "rolling_friction",
            json!(-0.1),
            "expected a distance in mm >= 0, got -0.1",
        ),
    ];
    for (field, value, message) in cases {
        let mut doc = base_doc();
        doc["materials"] = json!({ "bad": { "soft_contact": { field: value } } });
        assert_issue(
            doc,
            &format!("materials.bad.soft_contact.{field}: {message}"),
        );
    }
    // A cone is pyramidal or elliptic; anything else is refused by the schema.
    let mut doc = base_doc();
    doc["materials"] = json!({ "bad": { "soft_contact": { "cone": "round" } } });
    let text = doc.to_string();
    let err = gymfleet_assembly::parse(&text).expect_err("refused");
    assert!(err.to_string().contains("unknown variant `round`"), "{err}");
}

#[test]
fn bad_soft_limits_name_their_field() {
    let limited = |kind: &str, soft: Value| {
        let mut doc = with_joint_type(kind);
        let joint = &mut doc["assembly"]["joints"][0];
        joint["min"] = json!(-10);
        joint["max"] = json!(10);
        joint["soft_limit"] = soft;
        doc
    };
    let path = "assembly.joints[0].soft_limit";
    assert_issue(
        limited("revolute", json!({ "solref": [0.02, -1.0] })),
        &format!("{path}.solref: expected [time constant s > 0, damping ratio > 0] or [-stiffness < 0, -damping <= 0], got [0.02, -1.0]"),
    );
    assert_issue(
        limited("revolute", json!({ "solimp": [0.9, 0.95, -1.0, 0.5, 2.0] })),
        &format!("{path}.solimp: expected [dmin, dmax in (0, 1), width deg >= 0, midpoint in (0, 1), power >= 1], got [0.9, 0.95, -1.0, 0.5, 2.0]"),
    );
    assert_issue(
        limited("prismatic", json!({ "solimp": [0.0, 0.95, 1.0, 0.5, 2.0] })),
        &format!("{path}.solimp: expected [dmin, dmax in (0, 1), width mm >= 0, midpoint in (0, 1), power >= 1], got [0.0, 0.95, 1.0, 0.5, 2.0]"),
    );
    assert_issue(
        limited("revolute", json!({ "margin": -1.0 })),
        &format!("{path}.margin: expected a distance in deg >= 0, got -1"),
    );
    // Without limits there is nothing to soften.
    let mut doc = base_doc();
    doc["assembly"]["joints"][0]["soft_limit"] = json!({});
    assert_issue(
        doc,
        &format!(
            "{path}: only a revolute or prismatic joint with min and max has limits to soften"
        ),
    );
}

#[test]
fn negative_damping() {
    assert_issue(
        with_joint_field("damping", json!(-0.5)),
        "assembly.joints[0].damping: expected a damping >= 0, got -0.5",
    );
}

#[test]
fn non_positive_max_effort() {
    for effort in [0, -2] {
        assert_issue(
            with_joint_field("max_effort", json!(effort)),
            &format!("assembly.joints[0].max_effort: expected a positive effort in N·m or N, got {effort}"),
        );
    }
}

#[test]
fn negative_or_misplaced_armature() {
    assert_issue(
        with_joint_field("armature", json!(-1e-6)),
        "assembly.joints[0].armature: expected an armature >= 0 (kg·m² or kg), got -0.000001",
    );
    let mut doc = with_joint_field("armature", json!(0.5));
    doc["assembly"]["joints"][0]["type"] = json!("fixed");
    assert_issue(
        doc,
        "assembly.joints[0].armature: a fixed joint has no DOF to add armature to",
    );
    let armature = common::ok(with_joint_field("armature", json!(0.25))).joints[0].armature;
    assert_eq!(armature, 0.25);
}

#[test]
fn collision_bits_are_32_bit_unsigned_integers() {
    for (value, message) in [
        (json!(-1), "invalid value: integer `-1`, expected u32"),
        (
            json!(4294967296u64),
            "invalid value: integer `4294967296`, expected u32",
        ),
        (
            json!(1.5),
            "invalid type: floating point `1.5`, expected u32",
        ),
    ] {
        let mut doc = base_doc();
        doc["assembly"]["instances"][0]["collision"] = json!({ "group": value });
        common::assert_malformed(
            &common::err(doc),
            "assembly.instances[0].collision.group",
            message,
        );
    }
    let mut doc = base_doc();
    doc["assembly"]["instances"][0]["collision"] = json!({ "mask": 6 });
    assert_eq!(common::ok(doc).instances[0].collision, (1, 6));
    assert_eq!(common::ok(base_doc()).instances[0].collision, (1, 1));
}

#[test]
fn given_mass_properties_are_checked() {
    let with = |inertial: serde_json::Value| {
        let mut doc = base_doc();
        doc["assembly"]["instances"][0]["inertial"] = inertial;
        doc
    };
    assert_issue(
        with(json!({"mass": 0})),
        "assembly.instances[0].inertial.mass: expected a mass in (0, 1e6] kg, got 0",
    );
    assert_issue(
        with(json!({"mass": 1, "center_of_mass": {"x": 1e12, "y": 0, "z": 0}})),
        "assembly.instances[0].inertial.center_of_mass.x: expected a coordinate within ±1e6 mm, got 1000000000000",
    );
    assert_issue(
        with(json!({"mass": 1, "inertia": {"xx": 1, "yy": 1, "zz": -1}})),
        "assembly.instances[0].inertial.inertia: [[1, 0, 0], [0, 1, 0], [0, 0, -1]] kg·m² is not positive definite (every principal moment must be > 0)",
    );
    assert_issue(
        with(json!({"mass": 1, "inertia": {"xx": 1, "yy": 1, "zz": 3}})),
        "assembly.instances[0].inertial.inertia: [[1, 0, 0], [0, 1, 0], [0, 0, 3]] kg·m² is its principal moments break the triangle inequality (each must be at most the sum of the other two): no body has this inertia",
    );
    assert_issue(
        with(json!({"mass": 1, "inertia": {"xx": 1, "yy": 1, "zz": 1, "xy": 2}})),
        "assembly.instances[0].inertial.inertia: [[1, 2, 0], [2, 1, 0], [0, 0, 1]] kg·m² is not positive definite (every principal moment must be > 0)",
    );
    // A thin rod (principal moments 0.5, 0.5, 1e-9) is fine; so is a mass alone.
    let rod = common::ok(with(
        json!({"mass": 1, "inertia": {"xx": 0.5, "yy": 0.5, "zz": 1e-9}}),
    ));
    assert_eq!(rod.instances[0].inertial.expect("given").mass, 1.0);
    let alone = common::ok(with(json!({"mass": 2.5})));
    let given = alone.instances[0].inertial.expect("given");
    assert_eq!((given.mass, given.inertia), (2.5, None));
}

#[test]
fn a_capsule_is_at_least_as_long_as_its_caps() {
    let mut doc = base_doc();
    doc["parts"][0]["primitive"] = json!({ "type": "capsule", "radius": 5, "height": 8 });
    assert_issue(
        doc,
        "parts[0].primitive.height: a capsule's height includes its two caps: expected at least 2 × radius = 10 mm, got 8",
    );
    let mut doc = base_doc();
    doc["parts"][0]["primitive"] = json!({ "type": "capsule", "radius": 5, "height": 30 });
    let shape = common::ok(doc).instances[0].shape.clone();
    assert_eq!(
        shape,
        gymfleet_assembly::Shape::Capsule {
            radius: 0.005,
            height: 0.030
        }
    );
    let pi = std::f64::consts::PI;
    let volume = pi * 0.005f64.powi(2) * 0.020 + 4.0 / 3.0 * pi * 0.005f64.powi(3);
    assert!((shape.volume() - volume).abs() < 1e-15);
    assert_eq!(shape.centroid(), [0.0, 0.0, 0.015]);
}

#[test]
fn mass_overflow_is_an_error() {
    let mut doc = base_doc();
    doc["parts"][0]["primitive"]["size"] = json!({ "x": 1e200, "y": 1e200, "z": 5 });
    assert_issue(
        doc,
        "assembly.instances[0]: expected a finite, positive mass (volume × density), got inf kg; check the part's size and the material's density",
    );
}

#[test]
fn huge_finite_axis_is_normalised() {
    let doc = with_joint_field("axis", json!({ "x": 0, "y": 1e300, "z": 1e300 }));
    let axis = common::ok(doc).joints[0].axis;
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!(
        (axis[1] - h).abs() < 1e-12 && (axis[2] - h).abs() < 1e-12,
        "{axis:?}"
    );
}

#[test]
fn all_independent_errors_are_reported_in_document_order() {
    let mut doc = base_doc();
    doc["parts"][0]["primitive"]["size"]["z"] = json!(0);
    doc["assembly"]["instances"][1]["material"] = json!("steel");
    doc["assembly"]["joints"][0]["axis"] = json!({ "x": 0, "y": 0, "z": 0 });
    doc["assembly"]["joints"][0]["damping"] = json!(-1);
    let ghost = revolute("arm", "ghost");
    doc["assembly"]["joints"]
        .as_array_mut()
        .unwrap()
        .push(ghost);

    let expected = [
        "parts[0].primitive.size.z: expected a positive length in mm, got 0",
        r#"assembly.instances[1].material: unknown material "steel" (known: none)"#,
        "assembly.joints[0].axis: expected a non-zero finite direction, got {x: 0, y: 0, z: 0}",
        "assembly.joints[0].damping: expected a damping >= 0, got -1",
        r#"assembly.joints[1].child: unknown instance "ghost" (known: "arm", "base")"#,
    ];
    let e = err(doc);
    assert_eq!(e.issues().len(), expected.len(), "{e}");
    let got: Vec<String> = e.issues().iter().map(ToString::to_string).collect();
    assert_eq!(got, expected);
    assert_eq!(e.to_string(), expected.join("; "));
    assert_eq!(e.path(), "parts[0].primitive.size.z");
}

#[test]
fn simulation_settings_are_checked_and_default_to_z_up_gravity() {
    let a = common::ok(base_doc());
    assert_eq!(
        (a.gravity, a.dt),
        (gymfleet_assembly::DEFAULT_GRAVITY, None)
    );
    let mut doc = base_doc();
    doc["simulation"] = json!({"gravity": {"x": 0, "y": -9.81, "z": 0}, "dt": 0.002});
    let a = common::ok(doc);
    assert_eq!((a.gravity, a.dt), ([0.0, -9.81, 0.0], Some(0.002)));
    let mut doc = base_doc();
    doc["simulation"] = json!({"gravity": {"x": 0, "y": 0, "z": -2000}});
    assert_issue(
        doc,
        "simulation.gravity.z: expected a component within ±1000 m/s², got -2000",
    );
    let mut doc = base_doc();
    doc["simulation"] = json!({"dt": 0});
    assert_issue(
        doc,
        "simulation.dt: expected an env step in (0, 1] s, got 0",
    );
    let mut doc = base_doc();
    doc["simulation"] = json!({"timestep": 0.01});
    let message = common::err(doc).to_string();
    assert!(
        message
            .contains("simulation.timestep: unknown field `timestep`, expected one of `gravity`, `dt`, `fluid`"),
        "{message}"
    );
}

#[test]
fn limits_must_hold_the_documents_pose() {
    let doc = with_joint_field("min", json!(10));
    assert_issue(
        doc,
        "assembly.joints[0].min: the joint starts at 0 deg (its `initial`; positions are measured from the document's pose), outside its limits [10, inf]",
    );
}

#[test]
fn an_initial_position_lies_within_the_limits() {
    let mut doc = with_joint_field("min", json!(10));
    doc["assembly"]["joints"][0]["max"] = json!(50);
    doc["assembly"]["joints"][0]["initial"] = json!(30);
    let a = common::ok(doc.clone());
    assert!((a.joints[0].initial - 30f64.to_radians()).abs() < 1e-12);
    doc["assembly"]["joints"][0]["initial"] = json!(60);
    assert_issue(
        doc,
        "assembly.joints[0].initial: the joint starts at 60 deg (its `initial`; positions are measured from the document's pose), outside its limits [10, 50]",
    );
    let mut ball = with_joint_type("ball");
    ball["assembly"]["joints"][0]["initial"] = json!(5);
    assert_issue(
        ball,
        "assembly.joints[0].initial: a ball joint has no initial position; initial applies to revolute and prismatic joints only",
    );
}

/// A heightfield is a ground as a plane is: never the floating base.
#[test]
fn heightfield_as_floating_base() {
    let mut doc = base_doc();
    doc["parts"][0]["primitive"] = json!({"type": "heightfield", "rows": 2, "columns": 2,
                                          "size": {"x": 10, "y": 10, "z": 1}});
    doc["floating_base"] = json!(true);
    assert_issue(
        doc,
        r#"assembly.instances[0].part: part "Base" is a heightfield (terrain, a ground), which cannot be the floating base (the first instance); list the robot's base first"#,
    );
}

#[test]
fn springdamper_values_are_positive() {
    let mut doc = base_doc();
    doc["assembly"]["joints"][0]["springdamper"] = json!([0.1, 0]);
    assert_issue(
        doc,
        "assembly.joints[0].springdamper: expected [timeconst, dampratio], both > 0, got [0.1, 0]",
    );
    let mut doc = base_doc();
    doc["assembly"]["joints"][0]["spring_rest"] = json!(10);
    assert_issue(
        doc,
        "assembly.joints[0].spring_rest: a spring rest position needs a `stiffness` or a `springdamper`",
    );
}
