//! URDF descriptions nobody here wrote (example-robot-data's UR5 and Panda, with their STL
//! meshes) convert into documents that parse, build and hold still; unsupported
//! constructs are errors naming the element and its line.

use std::path::Path;

use gymfleet_env::{ActionType, EnvConfig, RobotEnv};
use gymfleet_import::{to_json, urdf_to_document, Assets, Format, ImportError};

const UR5: &str = include_str!("data/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf");
const PANDA: &str =
    include_str!("data/example-robot-data/robots/panda_description/urdf/panda.urdf");

/// The test data folder as an assets root: `example-robot-data/robots/…` inside it.
fn assets() -> Assets {
    Assets::from_dir(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")).expect("reads")
}

fn ur5_json() -> (String, Vec<String>) {
    to_json(UR5, Format::Urdf, Some(&assets())).expect("converts")
}

fn ur5_env() -> RobotEnv {
    let (text, _) = ur5_json();
    RobotEnv::from_json(&text, EnvConfig::with_end_effectors(["ee_link"]))
        .unwrap_or_else(|e| panic!("the converted UR5 builds: {e}"))
}

#[test]
fn ur5_has_six_actuated_joints_with_the_files_limits_and_efforts() {
    let env = ur5_env();
    let spec = env.spec();
    let names: Vec<&str> = spec.dofs.iter().map(|d| d.joint_name.as_str()).collect();
    assert_eq!(
        names,
        [
            "shoulder_pan_joint",
            "shoulder_lift_joint",
            "elbow_joint",
            "wrist_1_joint",
            "wrist_2_joint",
            "wrist_3_joint"
        ]
    );
    assert_eq!(spec.action_dim, 6);
    let limits: Vec<[f64; 2]> = spec
        .dofs
        .iter()
        .map(|d| d.limits.expect("limited"))
        .collect();
    for (k, [lo, hi]) in limits.iter().enumerate() {
        let expected = if k == 2 { 180.0 } else { 360.0 };
        assert!(
            (hi - expected).abs() < 1e-6 && (lo + expected).abs() < 1e-6,
            "{k}: {lo} {hi}"
        );
    }
    let efforts: Vec<Option<f64>> = spec.dofs.iter().map(|d| d.max_effort).collect();
    assert_eq!(
        efforts,
        [150.0, 150.0, 150.0, 28.0, 28.0, 28.0].map(Some).to_vec()
    );
}

#[test]
fn ur5_masses_are_the_files_and_its_shapes_are_mesh_hulls() {
    let (text, warnings) = ur5_json();
    let assembly = gymfleet_assembly::parse(&text).expect("parses");
    let mass = |name: &str| {
        let inst = &assembly.instances[assembly.instance_index(name).expect(name)];
        inst.inertial.expect("given").mass
    };
    for (link, kg) in [
        ("base_link", 4.0),
        ("shoulder_link", 3.7),
        ("upper_arm_link", 8.393),
        ("forearm_link", 2.275),
        ("wrist_1_link", 1.219),
        ("wrist_2_link", 1.219),
        ("wrist_3_link", 0.1879),
    ] {
        assert_eq!(mass(link), kg, "{link}");
    }
    let upper = &assembly.instances[assembly.instance_index("upper_arm_link").unwrap()];
    let gymfleet_assembly::Shape::Convex(parts) = &upper.shape else {
        panic!("a mesh hull, got {:?}", upper.shape)
    };
    assert_eq!(parts.pieces.len(), 1);
    // The upper arm's collision mesh spans its 425 mm link (and a little more).
    let z: Vec<f64> = parts.pieces[0].vertices.iter().map(|v| v[2]).collect();
    let span =
        z.iter().cloned().fold(f64::MIN, f64::max) - z.iter().cloned().fold(f64::MAX, f64::min);
    assert!(
        (0.42..0.6).contains(&span),
        "upper arm hull spans {span} m along its z"
    );
    for expected in [
        "<visual> ignored",
        "<transmission> ignored",
        "velocity ignored",
        "mass 0",
    ] {
        assert!(
            warnings.iter().any(|w| w.contains(expected)),
            "no {expected:?} in {warnings:#?}"
        );
    }
}

#[test]
fn ur5_holds_still_under_pd_at_its_initial_pose() {
    let mut env = ur5_env();
    let steps = (1.0 / env.spec().dt).round() as usize;
    for _ in 0..steps {
        env.step(ActionType::Position, &[0.0; 6]).expect("steps");
    }
    let obs = env.observe();
    for (k, q) in obs.joint_positions.iter().enumerate() {
        assert!(q.abs() < 1.0, "joint {k} sagged to {q} deg");
    }
    for (k, v) in obs.joint_velocities.iter().enumerate() {
        assert!(v.abs() < 1.0, "joint {k} still moves at {v} deg/s");
    }
}

#[test]
fn panda_mimic_finger_is_refused_naming_the_line() {
    let err = urdf_to_document(PANDA).expect_err("a mimic joint");
    let ImportError::Unsupported {
        element,
        line,
        reason,
    } = &err
    else {
        panic!("{err}")
    };
    assert_eq!(element, "mimic");
    assert_eq!(*line, 348);
    assert!(
        reason.contains("panda_finger_joint2") && reason.contains("mimic"),
        "{reason}"
    );
}

fn urdf_error(xml: &str) -> String {
    urdf_to_document(xml).expect_err("refused").to_string()
}

fn robot(inner: &str) -> String {
    format!("<robot name=\"r\">\n{inner}\n</robot>")
}

const LINK: &str = r#"<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>"#;

fn link(name: &str) -> String {
    format!(
        r#"<link name="{name}">{LINK}<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>"#
    )
}

fn revolute(name: &str, parent: &str, child: &str) -> String {
    format!(
        r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/><origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="1"/></joint>"#
    )
}

#[test]
fn bad_descriptions_name_their_element_and_line() {
    let cases: Vec<(String, &str)> = vec![
        (
            robot(&format!("{}\n{}\n{}\n{}", link("a"), link("b"), revolute("j1", "a", "b"), revolute("j2", "b", "a"))),
            "every link is some joint's child: the joints form a cycle",
        ),
        (
            robot(&format!("{}\n{}\n{}", link("a"), link("b"), link("c"))),
            "3 links are no joint's child",
        ),
        (
            robot(&format!("{}\n{}\n{}\n{}\n{}", link("a"), link("b"), link("c"), revolute("j1", "a", "c"), revolute("j2", "b", "c"))),
            "line 6: <joint>: link \"c\" is already the child of joint \"j1\" (line 5): URDF is a tree",
        ),
        (
            robot(&format!("{}\n{}", link("a"), revolute("j1", "a", "ghost"))),
            "line 3: <child link=…>: no link is named \"ghost\"",
        ),
        (
            robot(r#"<link name="a"><inertial><mass value="2"/><inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>"#),
            "<inertia>: a link of 2 kg with zero inertia",
        ),
        (
            robot(&format!("{}\n{}\n{}", link("a"), link("b"), revolute("j1", "a", "b").replace("revolute", "floating"))),
            "line 2: <link>: the root link \"a\" holds a floating joint, so it is the world: it may have no <collision> or <inertial>",
        ),
        (
            robot(&format!("<link name=\"w\"/>\n{}\n{}\n{}\n{}", link("a"), link("b"), revolute("j1", "w", "a"), revolute("j2", "a", "b").replace("revolute", "floating"))),
            "line 6: <joint>: a floating joint must hang the robot from the root link, the world (here \"w\")",
        ),
        (
            robot(&format!("<link name=\"w\"/>\n{}\n{}\n{}\n{}", link("a"), link("b"), revolute("j1", "w", "a").replace("revolute", "floating"), revolute("j2", "w", "b").replace("revolute", "floating"))),
            "line 6: <joint>: a second floating joint: one floating base is supported",
        ),
        (
            robot(&format!("<link name=\"w\"/>\n{}\n{}\n{}\n{}", link("a"), link("b"), revolute("j1", "w", "a").replace("revolute", "floating"), revolute("j2", "w", "b"))),
            "line 2: <link>: the world link \"w\" holds a floating joint and other joints: nothing is fixed to the world beside a floating base",
        ),
        (
            robot(&format!("{}\n{}\n{}", link("a"), link("b"), revolute("j1", "a", "b").replace(r#"<limit lower="-1" upper="1" effort="5" velocity="1"/>"#, ""))),
            "a revolute joint needs <limit lower upper effort velocity>",
        ),
        (
            robot(&format!("{}\n{}\n{}", link("a"), link("b"), revolute("j1", "a", "b").replace("</joint>", r#"<dynamics friction="-0.3"/></joint>"#))),
            "<dynamics friction=…>: expected friction ≥ 0, got -0.3",
        ),
        (
            robot(&link("a").replace(r#"size="0.1 0.1 0.1""#, r#"size="0.1 0.1""#)),
            "<box size=…>: expected 3 numbers, got 2",
        ),
        (
            robot(&link("a").replace(r#"<box size="0.1 0.1 0.1"/>"#, r#"<cone radius="1"/>"#)),
            "<cone>: <cone> geometry is not supported",
        ),
        (
            robot(&format!("{}\n{}", link("a"), link("a"))),
            "line 3: <link name=…>: a second link named \"a\"",
        ),
        (
            robot(r#"<link name="a"><inertial><mass value="2"/><inertia ixx="0.1" iyy="0.1" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>"#),
            "<inertia>: the inertia of a link of 2 kg is not positive definite",
        ),

    ];
    for (xml, expected) in cases {
        let message = urdf_error(&xml);
        assert!(
            message.contains(expected),
            "expected {expected:?} in {message:?} for\n{xml}"
        );
    }
}

#[test]
fn a_continuous_joint_is_unlimited_and_a_prismatic_one_is_in_mm() {
    let xml = robot(&format!(
        "{}\n{}\n{}\n{}\n{}",
        link("a"),
        link("b"),
        link("c"),
        revolute("spin", "a", "b").replace("revolute", "continuous"),
        revolute("slide", "b", "c").replace("revolute", "prismatic")
    ));
    let converted = urdf_to_document(&xml).expect("converts");
    let env =
        RobotEnv::from_json(&converted.document.to_string(), EnvConfig::default()).expect("builds");
    let spec = env.spec();
    assert_eq!(spec.dofs[0].limits, None);
    assert_eq!(spec.dofs[1].limits, Some([-1000.0, 1000.0]));
    // The anchors compose: b's frame is 200 mm above a's, c's 200 mm above b's.
    let joints = converted.document["assembly"]["joints"]
        .as_array()
        .unwrap()
        .clone();
    assert_eq!(joints[1]["anchor"]["z"], 400.0);
}

/// Kinova's j2s6s200 joint 2 and Panda's joint 4 have limits that exclude the zero pose:
/// the joint starts at its nearest limit (where MuJoCo's limit would push it).
#[test]
fn a_zero_pose_outside_the_limits_starts_at_the_nearest_limit() {
    let xml = robot(&format!(
        "{}\n{}\n{}",
        link("a"),
        link("b"),
        revolute("j1", "a", "b")
            .replace(r#"lower="-1""#, r#"lower="0.82""#)
            .replace(r#"upper="1""#, r#"upper="5.46""#)
    ));
    let converted = urdf_to_document(&xml).expect("converts");
    assert!(
        converted
            .warnings
            .iter()
            .any(|w| w.contains("line 4: <limit> joint \"j1\" starts at 46.98")),
        "{:?}",
        converted.warnings
    );
    let mut env =
        RobotEnv::from_json(&converted.document.to_string(), EnvConfig::default()).expect("builds");
    let q = env.reset(None).joint_positions[0];
    assert!(
        (f64::from(q) - 0.82f64.to_degrees()).abs() < 1e-3,
        "starts at {q}"
    );
}

const KINOVA: &str =
    include_str!("data/example-robot-data/robots/kinova_description/robots/kinova.urdf");

/// Kinova's Jaco 2 (j2s6s200): COLLADA meshes, continuous joints, fixed fingers, and a
/// zero pose outside two joints' limits: it starts at their nearest limits and holds there.
#[test]
fn kinova_with_collada_meshes_starts_at_its_limits_and_holds_still() {
    let (text, warnings) = to_json(KINOVA, Format::Urdf, Some(&assets())).expect("converts");
    for expected in [
        "\"j2s6s200_joint_2\" starts at 47",
        "\"j2s6s200_joint_3\" starts at 19",
    ] {
        assert!(
            warnings.iter().any(|w| w.contains(expected)),
            "no {expected:?} in {warnings:#?}"
        );
    }
    let assembly = gymfleet_assembly::parse(&text).expect("parses");
    // The arm link's hull (arm.dae, in metres by its <unit>) spans its 410 mm.
    let arm = &assembly.instances[assembly.instance_index("j2s6s200_link_2").expect("link 2")];
    let gymfleet_assembly::Shape::Convex(parts) = &arm.shape else {
        panic!("a mesh hull, got {:?}", arm.shape)
    };
    let y: Vec<f64> = parts.pieces[0].vertices.iter().map(|v| v[1]).collect();
    let span =
        y.iter().cloned().fold(f64::MIN, f64::max) - y.iter().cloned().fold(f64::MAX, f64::min);
    assert!((0.4..0.5).contains(&span), "link 2's hull spans {span} m");
    assert_eq!(arm.inertial.expect("given").mass, 0.99);

    let mut env = RobotEnv::from_json(&text, EnvConfig::default()).expect("builds");
    let spec = env.spec();
    assert_eq!(spec.action_dim, 6);
    let limited: Vec<bool> = spec.dofs.iter().map(|d| d.limits.is_some()).collect();
    assert_eq!(
        limited,
        [false, true, true, false, true, false],
        "continuous joints 1, 4, 6"
    );
    let start = env.reset(None).joint_positions;
    let expected = [0.0, 47.0, 19.0, 0.0, 30.0, 0.0];
    for (q, e) in start.iter().zip(expected) {
        assert!((q - e).abs() < 1e-3, "starts at {start:?}");
    }
    for _ in 0..240 {
        env.step(ActionType::Position, &start).expect("steps");
    }
    let q = env.observe().joint_positions;
    for (k, (q, s)) in q.iter().zip(&start).enumerate() {
        assert!((q - s).abs() < 1.0, "joint {k} drifted from {s} to {q} deg");
    }
}

/// PyBullet's `<contact>` extension (Solo's and other legged robots' feet) sets the
/// link's friction and restitution; its solver tuning is ignored with a warning.
#[test]
fn a_pybullet_contact_sets_the_links_friction() {
    let xml = robot(&format!(
        "{}\n{}\n{}",
        link("a"),
        link("foot").replace(
            "</link>",
            r#"<contact><lateral_friction value="1.2"/><restitution value="0.1"/><stiffness value="30000"/></contact></link>"#
        ),
        revolute("j1", "a", "foot")
    ));
    let converted = urdf_to_document(&xml).expect("converts");
    let assembly = gymfleet_assembly::parse(&converted.document.to_string()).expect("parses");
    let foot = &assembly.instances[assembly.instance_index("foot").expect("foot")];
    assert_eq!(
        (foot.material.friction, foot.material.restitution),
        (1.2, 0.1)
    );
    let a = &assembly.instances[assembly.instance_index("a").expect("a")];
    assert_eq!(a.material.friction, gymfleet_assembly::DEFAULT_FRICTION);
    assert!(
        converted
            .warnings
            .iter()
            .any(|w| w.contains("<stiffness> ignored")),
        "{:?}",
        converted.warnings
    );
}

/// A description file finds its meshes in its folder or the folders above (the load
/// client's `--model x.urdf`): the UR5's `package://` paths resolve from its package.
#[test]
fn a_urdf_file_finds_its_meshes_above_it() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf");
    let (from_file, warnings) = gymfleet_import::convert_file(&path).expect("converts");
    let (expected, expected_warnings) = ur5_json();
    assert_eq!(warnings, expected_warnings);
    // The same document (as JSON values: the file's route writes it out twice).
    let (a, b): (serde_json::Value, serde_json::Value) = (
        serde_json::from_str(&from_file).unwrap(),
        serde_json::from_str(&expected).unwrap(),
    );
    assert_eq!(a, b, "the same document as with explicit assets");
}

/// A floating joint from an empty world link makes its child the floating base: the first
/// instance, free, observed as `base_pose`/`base_velocity`; the world link is dropped.
#[test]
fn a_floating_joint_from_the_world_makes_a_floating_base() {
    let xml = robot(&format!(
        "<link name=\"world\"/>\n{}\n{}\n{}\n{}",
        link("base"),
        link("arm"),
        revolute("root", "world", "base")
            .replace("revolute", "floating")
            .replace(
                r#"<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="1"/>"#,
                ""
            ),
        revolute("elbow", "base", "arm")
    ));
    let converted = urdf_to_document(&xml).expect("converts");
    let doc = &converted.document;
    assert_eq!(doc["floating_base"], true);
    let names: Vec<&str> = doc["assembly"]["instances"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["base", "arm"]);
    let mut env = RobotEnv::from_json(&doc.to_string(), EnvConfig::default()).expect("builds");
    assert!(env.spec().floating_base);
    assert_eq!(env.spec().action_dim, 1);
    // The base's box centre is where the floating joint's origin puts the link: 0.2 m up.
    let start = env.observe();
    assert_eq!(&start.base_pose[..3], &[0.0, 0.0, 200.0]);
    let mut o = start;
    for _ in 0..24 {
        o = env
            .step(ActionType::Torque, &[0.0])
            .expect("valid")
            .observation;
    }
    let vz = f64::from(o.base_velocity[2]);
    assert!(
        (vz + 981.0).abs() < 0.5,
        "falls freely: {vz} mm/s after 0.1 s"
    );
}

/// ROS's `<self_filter>` in a link (ANYmal's description) has no effect on the dynamics:
/// ignored with a warning naming its line.
#[test]
fn a_self_filter_is_ignored_with_a_warning() {
    let xml = robot(&link("a").replace(
        "</link>",
        r#"<self_filter><sphere radius="0.1"/></self_filter></link>"#,
    ));
    let converted = urdf_to_document(&xml).expect("converts");
    assert!(
        converted
            .warnings
            .iter()
            .any(|w| w.contains("line 2: <self_filter> ignored (a ROS sensor-filtering setting")),
        "{:?}",
        converted.warnings
    );
}

/// A near-massless frame link with a placeholder inertia (Unitree's B1, IIT's HyQ: 1e-6
/// everywhere) keeps its mass with its shape's inertia, with a warning; a real link with a
/// non-physical inertia is still refused at its line.
#[test]
fn placeholder_inertias_on_frame_links_are_replaced_with_a_warning() {
    let placeholder = r#"<link name="b"><inertial><mass value="1e-6"/><inertia ixx="1e-6" ixy="1e-6" ixz="1e-6" iyy="1e-6" iyz="1e-6" izz="1e-6"/></inertial><collision><geometry><box size="0.01 0.01 0.01"/></geometry></collision></link>"#;
    let xml = robot(&format!(
        "{}\n{placeholder}\n{}",
        link("a"),
        revolute("j", "a", "b")
    ));
    let converted = urdf_to_document(&xml).expect("converts");
    assert!(
        converted
            .warnings
            .iter()
            .any(|w| w.contains("line 3: <inertia>")
                && w.contains("a link this light keeps its mass with its shape's inertia")),
        "{:?}",
        converted.warnings
    );
    let b = &converted.document["assembly"]["instances"][1];
    assert_eq!(b["inertial"], serde_json::json!({"mass": 1e-6}));
    RobotEnv::from_json(&converted.document.to_string(), EnvConfig::default()).expect("builds");
    let heavy = placeholder.replace(r#"<mass value="1e-6"/>"#, r#"<mass value="0.5"/>"#);
    let xml = robot(&format!(
        "{}\n{heavy}\n{}",
        link("a"),
        revolute("j", "a", "b")
    ));
    assert!(
        urdf_error(&xml).contains("line 3: <inertia>: the inertia of a link of 0.5 kg is"),
        "{}",
        urdf_error(&xml)
    );
}

/// `<dynamics friction>` is the joint's dry friction (z1, xArm7, TALOS, TIAGo carry it).
#[test]
fn dynamics_friction_is_the_joints_friction() {
    let joint = revolute("j", "a", "b").replace(
        "</joint>",
        r#"<dynamics damping="0.1" friction="0.3"/></joint>"#,
    );
    let xml = robot(&format!("{}\n{}\n{joint}", link("a"), link("b")));
    let converted = urdf_to_document(&xml).expect("converts");
    let j = &converted.document["assembly"]["joints"][0];
    assert_eq!(j["friction"], 0.3);
    assert_eq!(j["damping"], 0.1);
    RobotEnv::from_json(&converted.document.to_string(), EnvConfig::default()).expect("builds");
}
