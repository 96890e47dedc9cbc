//! Scenes (issue Z1): static geometry (`fixed`), free bodies, mocap bodies, contact rules
//! and ellipsoids in the assembly JSON, each refused with its JSON path when misused.

mod common;

use common::{assert_issue, base_doc, blocks_doc, ok, revolute};
use gymfleet_assembly::Shape;
use serde_json::json;

/// A table (fixed), a gripper on a hinge of the ground, two objects, a mocap handle.
fn table_scene() -> serde_json::Value {
    let mut doc = blocks_doc(&["ground", "table", "gripper", "cup", "ball", "handle"]);
    let i = &mut doc["assembly"]["instances"];
    i[1]["fixed"] = json!(true);
    i[5]["mocap"] = json!(true);
    i[3]["body_frame"] = json!({"position": {"x": 0.5, "y": 0.5, "z": 0.5}});
    doc["assembly"]["joints"] = json!([
        revolute("ground", "gripper"),
        {"type": "fixed", "name": "grip", "parent": "handle", "child": "gripper", "actuated": false}
    ]);
    doc["assembly"]["contacts"] = json!({
        "exclude": [{"a": "table", "b": "gripper"}],
        "pairs": [{"a": "cup", "b": "ball", "friction": 0.2}, {"a": "cup", "b": "table", "condim": 1}]
    });
    doc
}

#[test]
fn a_scene_has_static_geometry_free_bodies_mocap_bodies_and_contact_rules() {
    let a = ok(table_scene());
    let grounded: Vec<bool> = a.instances.iter().map(|i| i.grounded).collect();
    assert_eq!(grounded, [true, true, false, false, false, false]);
    assert_eq!(a.free_bodies(), [3, 4], "cup and ball");
    assert_eq!(a.mocap_bodies(), [5]);
    let frame = a.instances[3].body_frame.expect("the cup's frame");
    assert_eq!(frame.position, [0.0005, 0.0005, 0.0005]);
    assert!(
        a.joints[1].closes_loop,
        "the weld to the handle is a constraint"
    );
    assert_eq!(a.contacts.exclude, [(1, 2)]);
    assert_eq!(a.contacts.pairs.len(), 2);
    assert_eq!(a.contacts.pairs[0].friction, Some(0.2));
    assert_eq!(
        a.contacts.pairs[1].friction,
        Some(0.0),
        "condim 1 is frictionless"
    );
}

#[test]
fn fixed_and_mocap_instances_are_never_joint_children() {
    let mut doc = table_scene();
    doc["assembly"]["joints"][0] = revolute("gripper", "table");
    assert_issue(
        doc,
        r#"assembly.joints[0].child: instance "table" is fixed to the world ("fixed": true) and cannot be a joint child; swap parent and child"#,
    );
    let mut doc = table_scene();
    doc["assembly"]["joints"][1] = json!({"type": "fixed", "parent": "gripper", "child": "handle"});
    assert_issue(
        doc,
        r#"assembly.joints[1].child: instance "handle" is a mocap body, which only its pose targets move, and cannot be a joint child; swap parent and child"#,
    );
}

#[test]
fn nothing_moving_hangs_from_a_mocap_body_and_nothing_joins_two_held_instances() {
    let mut doc = table_scene();
    doc["assembly"]["joints"][1] = revolute("handle", "cup");
    assert_issue(
        doc,
        r#"assembly.joints[1].observed: instance "handle" is a mocap body, which nothing moving hangs from: a joint from it is a constraint that pulls "cup" along ("observed": false), or a fixed joint that makes "cup" part of it"#,
    );
    let mut doc = table_scene();
    doc["assembly"]["joints"][1] = json!({"type": "fixed", "parent": "ground", "child": "table"});
    // The child rule speaks first: a fixed instance is never a child.
    assert_issue(
        doc,
        r#"assembly.joints[1].child: instance "table" is fixed to the world ("fixed": true) and cannot be a joint child; swap parent and child"#,
    );
    let mut doc = table_scene();
    doc["assembly"]["joints"][1] = json!({"type": "fixed", "parent": "handle", "child": "ground"});
    assert_issue(
        doc,
        r#"assembly.joints[1].child: joint "handle" -> "ground" joins two instances the world holds where they are (grounded, fixed or mocap): it would hold nothing; remove it"#,
    );
}

#[test]
fn a_floating_base_is_neither_fixed_nor_a_mocap_body() {
    let mut doc = base_doc();
    doc["floating_base"] = json!(true);
    doc["assembly"]["instances"][0]["mocap"] = json!(true);
    let e = common::err(doc).to_string();
    assert!(
        e.starts_with("assembly.instances[0].mocap: the floating base (the first instance) moves freely: it cannot be fixed or a mocap body; list it elsewhere, or remove floating_base"),
        "{e}"
    );
    let mut doc = table_scene();
    doc["assembly"]["instances"][5]["fixed"] = json!(true);
    assert_issue(
        doc,
        "assembly.instances[5].mocap: an instance is fixed or a mocap body (moved by its targets), not both",
    );
}

#[test]
fn contact_rules_name_instances_and_say_what_they_accept() {
    let mut doc = table_scene();
    doc["assembly"]["contacts"]["exclude"][0]["b"] = json!("griper");
    let e = common::err(doc).to_string();
    assert!(
        e.starts_with(r#"assembly.contacts.exclude[0].b: unknown instance "griper" (known: "#),
        "{e}"
    );
    let mut doc = table_scene();
    doc["assembly"]["contacts"]["pairs"][1]["condim"] = json!(4);
    assert_issue(
        doc,
        "assembly.contacts.pairs[1].condim: expected 1 (frictionless) or 3 (sliding friction), got 4; torsional and rolling friction (4, 6) are not simulated",
    );
    let mut doc = table_scene();
    doc["assembly"]["contacts"]["pairs"][0]["friction"] = json!(-1.0);
    assert_issue(
        doc,
        "assembly.contacts.pairs[0].friction: expected a friction coefficient in [0, 1000], got -1",
    );
    let mut doc = table_scene();
    doc["assembly"]["contacts"]["exclude"][0]["b"] = json!("table");
    assert_issue(
        doc,
        r#"assembly.contacts.exclude[0].b: names instance "table" again: an instance never collides with itself"#,
    );
}

#[test]
fn an_ellipsoid_has_its_exact_volume_and_positive_radii() {
    let mut doc = blocks_doc(&["ground", "egg"]);
    doc["parts"] = json!([
        {"name": "Block", "primitive": {"type": "cube", "size": {"x": 1, "y": 1, "z": 1}}},
        {"name": "Egg", "primitive": {"type": "ellipsoid", "radii": {"x": 30, "y": 20, "z": 10}}}
    ]);
    doc["assembly"]["instances"][1]["part"] = json!("Egg");
    let a = ok(doc.clone());
    let Shape::Ellipsoid { radii, ref hull } = a.instances[1].shape else {
        panic!("not an ellipsoid: {:?}", a.instances[1].shape)
    };
    assert_eq!(radii, [0.03, 0.02, 0.01]);
    let exact = 4.0 / 3.0 * std::f64::consts::PI * 0.03 * 0.02 * 0.01;
    assert!(
        (hull.volume() / exact - 1.0).abs() < 1e-4,
        "{}",
        hull.volume() / exact
    );
    // Every vertex within 1 % outside the surface (the grid, scaled to the volume).
    for v in &hull.pieces[0].vertices {
        let q = (v[0] / 0.03).powi(2) + (v[1] / 0.02).powi(2) + (v[2] / 0.01).powi(2);
        assert!((1.0..1.01).contains(&q.sqrt()), "{v:?} at {}", q.sqrt());
    }
    doc["parts"][1]["primitive"]["radii"]["y"] = json!(0);
    assert_issue(
        doc,
        "parts[1].primitive.radii.y: expected a positive length in mm, got 0",
    );
}

#[test]
fn a_sites_axes_and_a_body_frame_must_be_finite() {
    let mut doc = table_scene();
    doc["assembly"]["sites"] = json!([{"name": "s", "instance": "cup", "point": {"x": 0, "y": 0, "z": 0},
                                       "rotation": {"x": 0, "y": 1e9, "z": 0}}]);
    assert_issue(
        doc,
        "assembly.sites[0].rotation.y: expected a finite angle within ±1e6 degrees, got 1e9",
    );
}
