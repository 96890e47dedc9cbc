//! MJCF scenes (issue Z1): flags honoured and options warned about, `mass="0"`, zero
//! inertias, `<skin>`, several `<worldbody>`s, includes and meshes from the model's folder,
//! `<contact>`, mocap bodies, ellipsoids and `inertiagrouprange`.

mod common;

use common::error;
use gymfleet_import::{asset_path, mjcf_to_document, to_json_in, Assets, Format};
use serde_json::Value;

fn converted(xml: &str) -> (Value, Vec<String>) {
    let c = mjcf_to_document(xml).expect("converts");
    (c.document, c.warnings)
}

fn instances(doc: &Value) -> &Vec<Value> {
    doc["assembly"]["instances"].as_array().expect("instances")
}

fn instance<'a>(doc: &'a Value, name: &str) -> &'a Value {
    instances(doc)
        .iter()
        .find(|i| i["name"] == name)
        .unwrap_or_else(|| panic!("no instance {name}: {doc}"))
}

const ARM: &str = r#"<worldbody>
  <geom name="floor" type="plane" size="1 1 0.1"/>
  <body name="arm" pos="0 0 1"><joint name="j" type="hinge" range="-30 30"/><geom name="link" size="0.1"/></body>
</worldbody>"#;

fn with_option(flags: &str) -> String {
    format!("<mujoco><option><flag {flags}/></option>{ARM}</mujoco>")
}

#[test]
fn flags_that_switch_physics_off_are_honoured() {
    let (doc, _) = converted(&with_option(r#"contact="disable""#));
    assert!(instances(&doc)
        .iter()
        .all(|i| i["collision"]["group"] == 0 && i["collision"]["mask"] == 0));
    let (doc, _) = converted(&with_option(r#"gravity="disable""#));
    assert_eq!(
        doc["simulation"]["gravity"],
        serde_json::json!({"x": 0.0, "y": 0.0, "z": 0.0})
    );
    let (doc, _) = converted(&with_option(r#"limit="disable""#));
    let joint = &doc["assembly"]["joints"][0];
    assert!(
        joint.get("min").is_none() && joint.get("max").is_none(),
        "{joint}"
    );
    let (doc, _) = converted(&with_option(r#"constraint="disable""#));
    assert!(doc["assembly"]["joints"][0].get("min").is_none());
    assert_eq!(instance(&doc, "link")["collision"]["mask"], 0);
    // Defaults and settings without effect are warned about, never silent.
    let (_, warnings) = converted(&with_option(r#"energy="enable" frictionloss="disable""#));
    assert!(
        warnings.iter().any(|w| w
            .contains("energy=\"enable\" ignored (no effect on the motion gymfleet simulates)")),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().any(|w| w.contains(
            "frictionloss=\"disable\" ignored: joints' and tendons' dry friction still acts"
        )),
        "{warnings:?}"
    );
    let (_, warnings) = converted(&format!(
        r#"<mujoco><option cone="elliptic" impratio="10" noslip_iterations="20"/>{ARM}</mujoco>"#
    ));
    for expected in [
        "cone=\"elliptic\" sizes how soft the contacts are, along the normal and in friction, as MuJoCo's; the pyramid is MuJoCo's four facets at condim 3",
        "impratio=\"10\" sizes how soft the contacts are",
        "noslip_iterations=\"20\" ignored: there is no noslip pass",
    ] {
        assert!(
            warnings.iter().any(|w| w.contains(expected)),
            "{expected}: {warnings:?}"
        );
    }
    assert_eq!(
        error(&with_option(r#"contact="off""#)),
        "line 1: <flag contact=…>: expected enable or disable, got \"off\""
    );
}

#[test]
fn equality_switched_off_leaves_the_constraints_out() {
    let xml = r#"<mujoco><option><flag equality="disable"/></option><worldbody>
      <body name="a" pos="0 0 1"><joint type="hinge"/><geom size="0.1"/></body>
      <body name="b" pos="1 0 1"><joint type="hinge"/><geom size="0.1"/></body>
    </worldbody><equality><connect body1="a" body2="b" anchor="0.5 0 0"/></equality></mujoco>"#;
    let (doc, warnings) = converted(xml);
    assert!(doc["assembly"]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .all(|j| j["type"] != "ball"));
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("left out: <option><flag> switches equality constraints off")),
        "{warnings:?}"
    );
}

#[test]
fn a_massless_geom_weighs_a_helpers_milligram_and_a_zero_inertia_a_small_ball() {
    let xml = r#"<mujoco><worldbody><body name="b" pos="0 0 1"><joint type="hinge"/>
      <geom name="deco" size="0.1" mass="0"/><geom name="load" size="0.1" mass="2"/>
      <body name="camera" pos="0 0 0.2"><inertial pos="0 0 0" mass="0" diaginertia="0 0 0"/></body>
    </body></worldbody></mujoco>"#;
    let (doc, _) = converted(xml);
    assert_eq!(instance(&doc, "deco")["inertial"]["mass"], 1e-6);
    assert_eq!(instance(&doc, "load")["inertial"]["mass"], 2.0);
    let camera = &instance(&doc, "camera")["inertial"];
    assert_eq!(camera["mass"], 1e-6);
    let xx = camera["inertia"]["xx"].as_f64().unwrap();
    assert!((xx / (0.4 * 1e-6 * 1e-6) - 1.0).abs() < 1e-9, "{xx}");
    assert_eq!(
        error(
            r#"<mujoco><worldbody><body><joint/><geom size="0.1" mass="-1"/></body></worldbody></mujoco>"#
        ),
        "line 1: <geom mass=…>: expected a mass >= 0, got -1"
    );
}

#[test]
fn appearance_is_warned_about_and_every_worldbody_is_read() {
    let xml = r#"<mujoco><asset><skin file="dog.skn"/></asset>
      <worldbody><geom name="floor" type="plane" size="1 1 0.1"/></worldbody>
      <worldbody><body name="b" pos="0 0 1"><freejoint/><geom size="0.1"/></body></worldbody>
    </mujoco>"#;
    let (doc, warnings) = converted(xml);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("<skin> ignored (appearance only)")),
        "{warnings:?}"
    );
    let names: Vec<&str> = instances(&doc)
        .iter()
        .map(|i| i["name"].as_str().unwrap())
        .collect();
    assert_eq!(names[0], "floor");
    assert!(names.contains(&"b"), "{names:?}");
}

#[test]
fn contact_rules_become_the_documents() {
    let xml = r#"<mujoco><worldbody>
      <geom name="floor" type="plane" size="1 1 0.1"/>
      <body name="a" pos="0 0 1"><joint type="hinge"/><geom name="ga" size="0.1" contype="0" conaffinity="0"/>
        <body name="b" pos="0 0 0.5"><joint type="hinge"/><geom name="gb" size="0.1"/><geom name="gb2" size="0.05"/></body>
      </body>
    </worldbody><contact>
      <exclude body1="world" body2="b"/>
      <pair geom1="ga" geom2="floor" condim="1"/>
      <pair geom1="gb" geom2="floor" friction="0.3 0.3 0.005 0.0001 0.0001" condim="6"/>
    </contact></mujoco>"#;
    let (doc, warnings) = converted(xml);
    let contacts = &doc["assembly"]["contacts"];
    let excluded: Vec<(&str, &str)> = contacts["exclude"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| (e["a"].as_str().unwrap(), e["b"].as_str().unwrap()))
        .collect();
    assert_eq!(excluded, [("floor", "gb"), ("floor", "gb2")]);
    assert_eq!(contacts["pairs"][0]["condim"], 1);
    assert!(contacts["pairs"][0].get("friction").is_none());
    assert_eq!(contacts["pairs"][1]["friction"], 0.3);
    assert!(
        warnings.iter().any(|w| w.contains(
            "condim=\"6\" collides as 3: torsional and rolling friction are not simulated"
        )),
        "{warnings:?}"
    );
    assert_eq!(
        error(r#"<mujoco><worldbody><geom name="f" type="plane" size="1 1 1"/></worldbody><contact><pair geom1="f" geom2="g"/></contact></mujoco>"#),
        "line 1: <pair geom2=…>: no geom is named \"g\" (or it was dropped: a massless geom that collides with nothing)"
    );
    assert_eq!(
        error(
            r#"<mujoco><worldbody/><contact><exclude body1="world" body2="x"/></contact></mujoco>"#
        ),
        "line 1: <exclude body2=…>: no body is named \"x\""
    );
}

#[test]
fn a_geoms_condim_and_friction_triplet_become_its_soft_contact() {
    let xml = r#"<mujoco><default><geom condim="4"/></default><worldbody>
      <geom name="floor" type="plane" size="1 1 0.1" condim="1"/>
      <body name="a" pos="0 0 1"><freejoint/><geom name="ga" size="0.1" friction="0.8 0.002 0.0005" condim="6"/></body>
      <body name="b" pos="1 0 1"><freejoint/><geom name="gb" size="0.1"/></body>
    </worldbody></mujoco>"#;
    let (doc, warnings) = converted(xml);
    let soft = |name: &str| doc["materials"][name]["soft_contact"].clone();
    assert_eq!(soft("floor")["condim"], 1);
    assert_eq!(soft("ga")["condim"], 6);
    // Metres to mm.
    assert!((soft("ga")["torsional_friction"].as_f64().unwrap() - 2.0).abs() < 1e-9);
    assert!((soft("ga")["rolling_friction"].as_f64().unwrap() - 0.5).abs() < 1e-9);
    // The class's condim; without a triplet, the document's defaults (MuJoCo's).
    assert_eq!(soft("gb")["condim"], 4);
    assert!(soft("gb").get("torsional_friction").is_none());
    assert!(
        !warnings.iter().any(|w| w.contains("condim")),
        "{warnings:?}"
    );
    let bad = |attrs: &str| {
        error(&format!(
            r#"<mujoco><worldbody><geom name="f" type="plane" size="1 1 1" {attrs}/></worldbody></mujoco>"#
        ))
    };
    assert_eq!(
        bad(r#"condim="5""#),
        "line 1: <geom condim=…>: expected 1, 3, 4 or 6, got 5"
    );
    assert_eq!(
        bad(r#"friction="1 -0.1 0""#),
        "line 1: <geom friction=…>: expected a torsional coefficient >= 0, got -0.1"
    );
}

#[test]
fn a_mocap_body_is_a_kinematic_instance_named_after_it() {
    let xml = r#"<mujoco><worldbody>
      <geom name="floor" type="plane" size="1 1 0.1"/>
      <body name="hand" mocap="true" pos="0.1 0.2 0.3" euler="0 0 90"><geom type="box" size="0.01 0.01 0.01" contype="0" conaffinity="0"/></body>
      <body name="arm" pos="0 0 1"><joint type="hinge"/><geom size="0.1"/></body>
    </worldbody><equality><weld body1="hand" body2="arm"/></equality></mujoco>"#;
    let (doc, _) = converted(xml);
    let hand = instance(&doc, "hand");
    assert_eq!(hand["mocap"], true);
    assert_eq!(
        hand["position"],
        serde_json::json!({"x": 100.0, "y": 200.0, "z": 300.0})
    );
    let weld = doc["assembly"]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["type"] == "fixed" && j["child"] == "arm_geom")
        .expect("the weld to the arm");
    assert_eq!(weld["parent"], "hand");
    assert_eq!(
        error(
            r#"<mujoco><worldbody><body><geom size="0.1"/><body mocap="true"><geom size="0.1"/></body></body></worldbody></mujoco>"#
        ),
        "line 1: <body mocap=…>: a mocap body is a child of <worldbody> (MuJoCo's rule)"
    );
    assert_eq!(
        error(
            r#"<mujoco><worldbody><body mocap="true"><joint/><geom size="0.1"/></body></worldbody></mujoco>"#
        ),
        "line 1: <joint type=…>: a mocap body has no joints: its pose targets move it"
    );
}

#[test]
fn an_ellipsoid_geom_is_an_ellipsoid_and_inertiagrouprange_weighs_only_its_groups() {
    let xml = r#"<mujoco><compiler inertiagrouprange="0 2"/><worldbody><body name="egg" pos="0 0 1"><freejoint/>
      <geom name="shell" type="ellipsoid" size="0.03 0.02 0.01"/>
      <geom name="visual" size="0.05" group="3"/>
    </body></worldbody></mujoco>"#;
    let (doc, _) = converted(xml);
    let part = doc["parts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "shell")
        .expect("the shell's part");
    assert_eq!(part["primitive"]["type"], "ellipsoid");
    assert_eq!(
        part["primitive"]["radii"],
        serde_json::json!({"x": 30.0, "y": 20.0, "z": 10.0})
    );
    assert_eq!(instance(&doc, "visual")["inertial"]["mass"], 1e-6);
    assert!(instance(&doc, "shell").get("inertial").is_none());
    assert_eq!(
        error(r#"<mujoco><compiler inertiagrouprange="3"/><worldbody/></mujoco>"#),
        "line 1: <compiler inertiagrouprange=…>: expected two integers, lowest first, got \"3\""
    );
}

#[test]
fn includes_and_meshes_resolve_from_the_models_folder() {
    assert_eq!(
        asset_path("scenes", "../meshes/a.stl").unwrap(),
        "meshes/a.stl"
    );
    assert_eq!(asset_path("a/b", "./c/../d.xml").unwrap(), "a/b/d.xml");
    assert_eq!(
        asset_path("scenes", "../../x.xml").unwrap_err(),
        "\"../../x.xml\" climbs above the assets' root from the model's folder \"scenes\": send the folder that holds it as the assets, and the model's path in it as document_path (Python: make(path, assets=folder) does this when path is inside folder)"
    );
    // scenes/main.xml includes parts/arm.xml (which includes ../shared/floor.xml: includes
    // resolve from the main file's folder, as MuJoCo resolves them).
    let main = r#"<mujoco><include file="parts/arm.xml"/></mujoco>"#;
    let arm = r#"<mujoco><include file="../shared/floor.xml"/><worldbody><body name="arm" pos="0 0 1"><joint type="hinge"/><geom size="0.1"/></body></worldbody></mujoco>"#;
    let floor = r#"<mujoco><worldbody><geom name="floor" type="plane" size="1 1 0.1"/></worldbody></mujoco>"#;
    let assets = Assets::from_files([
        ("scenes/parts/arm.xml".to_string(), arm.as_bytes().to_vec()),
        ("shared/floor.xml".to_string(), floor.as_bytes().to_vec()),
    ]);
    let (json, _) = to_json_in(main, Format::Mjcf, Some(&assets), "scenes").expect("converts");
    let doc: Value = serde_json::from_str(&json).unwrap();
    let names: Vec<&str> = instances(&doc)
        .iter()
        .map(|i| i["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["floor", "arm_geom"]);
}
