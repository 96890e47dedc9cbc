//! Gymnasium's locomotion models (the Ant, HalfCheetah) convert, stand and settle as
//! MuJoCo's do; free joints, springs and total masses convert or name their line.

mod common;

use common::{bare, env, error};
use gymfleet_env::{ActionType, EnvConfig, RobotEnv};
use gymfleet_import::mjcf_to_document;

const ANT: &str = include_str!("data/ant.xml");

/// Gymnasium's Ant: a free joint makes its torso the floating base (the first instance),
/// its eight motors drive the hips and ankles, and, dropped from 0.75 m with its ankles
/// at their stops, it lands on its legs and stays there. MuJoCo 3 (this description from
/// the same pose, 60 s) rests its torso's centre at 382.5 mm with its ankles on the
/// stops, the capsules held 10 mm off the floor by the description's contact `margin`,
/// which gymfleet does not model (it warns).
#[test]
fn ant_has_a_floating_torso_and_eight_driven_joints() {
    let converted = mjcf_to_document(ANT).expect("converts");
    let doc = &converted.document;
    assert_eq!(doc["floating_base"], true);
    assert_eq!(doc["assembly"]["instances"][0]["name"], "torso_geom");
    assert!(
        converted.warnings.iter().all(|w| !w.contains("free joint")),
        "the free joint's damping and armature are 0: {:?}",
        converted.warnings
    );
    let (mut env, _) = env(ANT, &["torso_geom"]);
    let spec = env.spec();
    assert!(spec.floating_base);
    assert_eq!(spec.action_dim, 8);
    assert_eq!(spec.num_dofs, 8);
    assert_eq!(spec.observation_dim, 2 * 8 + 13 + 7);
    let names: Vec<&str> = spec.dofs.iter().map(|d| d.joint_name.as_str()).collect();
    assert_eq!(
        names,
        ["hip_1", "ankle_1", "hip_2", "ankle_2", "hip_3", "ankle_3", "hip_4", "ankle_4"]
    );
    // Its motors are not in the joints' order (hip_4 and ankle_4 come first): they are
    // actuators, and the actions are MuJoCo's ctrl in actuator order (issue Z1b).
    let targets: Vec<&str> = spec.actuators.iter().map(|a| a.target.as_str()).collect();
    assert_eq!(
        targets,
        ["hip_4", "ankle_4", "hip_1", "ankle_1", "hip_2", "ankle_2", "hip_3", "ankle_3"]
    );
    assert!(spec
        .actuators
        .iter()
        .all(|a| a.ctrl_range == Some([-1.0, 1.0])));
    assert!(spec
        .dofs
        .iter()
        .all(|d| !d.actuated && d.max_effort.is_none()));
    let gears: Vec<&serde_json::Value> = doc["assembly"]["actuators"]
        .as_array()
        .expect("actuators")
        .iter()
        .map(|a| &a["gear"])
        .collect();
    assert!(gears.iter().all(|g| **g == 150.0), "{gears:?}");
    let start = env.observe();
    assert!(
        (start.base_pose[2] - 750.0).abs() < 1e-3,
        "{:?}",
        start.base_pose
    );
    let mut run = |steps: usize| {
        let mut o = None;
        for _ in 0..steps {
            o = Some(
                env.step(ActionType::Torque, &[0.0; 8])
                    .expect("valid")
                    .observation,
            );
        }
        o.expect("stepped")
    };
    let landed = run(480);
    let later = run(120);
    let z = f64::from(landed.base_pose[2]);
    assert!(
        (z - 382.5).abs() < 25.0,
        "the torso's centre rests at {z} mm"
    );
    let moved = (0..3)
        .map(|k| f64::from(later.base_pose[k] - landed.base_pose[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(moved < 0.5, "the torso still moves: {moved} mm in 0.5 s");
    let sideways = f64::from(later.base_pose[0]).hypot(f64::from(later.base_pose[1]));
    assert!(sideways < 20.0, "it slid {sideways} mm sideways");
    // The limits are MuJoCo's soft ones (vendored patch 44): a loaded ankle rests a little
    // past its range, 29.99764° against 30° in MuJoCo 3 (`mj_step` from the same model).
    for (k, &angle) in later.joint_positions.iter().enumerate() {
        let [lo, hi] = spec_limits(&env, k);
        assert!(
            angle >= lo as f32 - 1e-2 && angle <= hi as f32 + 1e-2,
            "joint {k}: {angle}°"
        );
    }
}

fn spec_limits(env: &RobotEnv, dof: usize) -> [f64; 2] {
    env.spec().dofs[dof]
        .limits
        .expect("every Ant joint is limited")
}

#[test]
fn free_joints_outside_top_level_bodies_or_beside_other_joints_are_refused() {
    let nested = bare(
        r#"<body name="a"><geom size="0.1"/><body name="b"><freejoint/><geom size="0.1"/></body></body>"#,
    );
    assert_eq!(
        error(&nested),
        "line 3: <freejoint>: a free joint belongs to a top-level body (a child of <worldbody>)"
    );
    let beside =
        bare(r#"<body name="a"><freejoint/><joint type="hinge"/><geom size="0.1"/></body>"#);
    assert_eq!(
        error(&beside),
        "line 3: <freejoint>: a free joint must be its body's only joint"
    );
}

/// A free body with nothing jointed below it is an object, not a floating base: the
/// world's geoms (a table) are fixed, what hangs from the world hangs from them, and the
/// object is a free body of its own.
#[test]
fn a_free_object_beside_static_geometry_is_a_free_body() {
    let table = bare(
        r#"<geom name="table" type="box" size="1 1 0.1"/><body name="a" pos="0 0 0.5"><freejoint/><geom size="0.1"/></body><body name="door"><joint type="hinge"/><geom size="0.1"/></body>"#,
    );
    let converted = mjcf_to_document(&table).expect("converts");
    let doc = &converted.document;
    assert!(doc.get("floating_base").is_none(), "{doc}");
    let instances = doc["assembly"]["instances"].as_array().unwrap();
    assert_eq!(instances[0]["name"], "table");
    assert_eq!(instances[0]["fixed"], true);
    let door = doc["assembly"]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["type"] == "revolute")
        .expect("the door's hinge");
    assert_eq!(door["parent"], "table");
    let env = RobotEnv::from_json(&doc.to_string(), EnvConfig::default()).expect("builds");
    assert_eq!(env.spec().free_bodies, ["a"]);
}

const HALF_CHEETAH: &str = include_str!("data/half_cheetah.xml");

/// Gymnasium's HalfCheetah: `settotalmass` scales its bodies to 14 kg, its joints carry
/// springs (`stiffness`), its root is three passive joints to the world (x, z slides, a
/// pitch hinge). With frictionless contacts and left alone for 5 s it settles into the pose
/// MuJoCo settles it into (MuJoCo 4.0.0, the same file with `friction="0 0 0"`, 500 steps of
/// 0.01 s: root z −128.51 mm, pitch 2.979°, joints [1.959, 3.888, −0.798, −3.378, −8.020,
/// −7.507]°): springs, gravity and the contacts' normal forces balance the same way. Root x
/// is not compared: with nothing to hold it, it drifts on both sides.
///
/// Why frictionless: MuJoCo's regularized friction lets loaded feet creep, so with the
/// file's friction (0.4) its cheetah still ends in the frictionless pose (the same joint
/// angles to 0.002°, z −132.4 mm); gymfleet's Coulomb friction holds the feet where they
/// land, and the legs stay loaded (bthigh −1.39° against 1.96°, the torso 29 mm higher).
/// Until vendored Rapier patch 21 our friction was a tenth of Coulomb's on this planar
/// root, and the feet slid into MuJoCo's pose with the friction on.
#[test]
fn half_cheetah_settles_into_mujocos_pose() {
    let converted = mjcf_to_document(HALF_CHEETAH).expect("converts");
    let text = converted.document.to_string();
    let assembly = gymfleet_assembly::parse(&text).expect("valid");
    let total: f64 = assembly
        .instances
        .iter()
        .filter(|i| !i.grounded)
        .map(|i| {
            i.inertial
                .map_or(i.shape.volume() * i.material.density, |g| g.mass)
        })
        .sum();
    // The two 1 mg helpers between the root's three joints are not bodies of MuJoCo's.
    assert!((total - 14.0 - 2e-6).abs() < 1e-9, "total mass {total} kg");
    let frictionless = HALF_CHEETAH.replace("friction=\".4 .1 .1\"", "friction=\"0 0 0\"");
    let (mut env, _) = env(&frictionless, &[]);
    let spec = env.spec().clone();
    assert_eq!(spec.action_dim, 6);
    assert_eq!(spec.num_dofs, 9);
    let mut o = env.observe();
    for _ in 0..500 {
        o = env
            .step(ActionType::Torque, &[0.0; 6])
            .expect("valid")
            .observation;
    }
    let q = &o.joint_positions;
    let mujoco = [1.959, 3.888, -0.798, -3.378, -8.020, -7.507];
    for (k, expected) in mujoco.iter().enumerate() {
        let ours = f64::from(q[3 + k]);
        assert!(
            (ours - expected).abs() < 0.01,
            "{}: {ours}° against MuJoCo's {expected}°",
            spec.dofs[3 + k].joint_name
        );
    }
    // With MuJoCo's contacts (vendored patch 43; frictionless, its pyramid is rigid) the
    // pitch settles 0.011° above MuJoCo's (2.975° to 2.986° after 20 s), 0.01° with Rapier's.
    assert!((f64::from(q[2]) - 2.979).abs() < 0.02, "pitch {}°", q[2]);
    assert!((f64::from(q[1]) + 128.51).abs() < 2.0, "root z {} mm", q[1]);
}

/// Joint springs: `stiffness` and `springref` (less `ref`, as positions are) become the
/// joint's `stiffness` and `spring_rest`; bad values name their attribute and line.
#[test]
fn springs_and_total_mass_convert_or_name_their_line() {
    let xml = "<mujoco>\n<compiler angle=\"radian\"/>\n<worldbody>\n<body><joint name=\"j\" type=\"hinge\" stiffness=\"2\" springref=\"0.3\" ref=\"0.1\" range=\"-1 1\"/><geom size=\".1\"/></body>\n<body><joint name=\"s\" type=\"slide\" stiffness=\"5\" frictionloss=\"0.4\"/><geom size=\".1\"/></body>\n</worldbody>\n</mujoco>";
    let converted = mjcf_to_document(xml).expect("converts");
    let joints = converted.document["assembly"]["joints"].as_array().unwrap();
    let hinge = joints.iter().find(|j| j["name"] == "j").unwrap();
    assert_eq!(hinge["stiffness"], 2.0);
    let rest = hinge["spring_rest"].as_f64().unwrap();
    assert!((rest - 0.2f64.to_degrees()).abs() < 1e-9, "{rest}");
    let slide = joints.iter().find(|j| j["name"] == "s").unwrap();
    assert_eq!(slide["stiffness"], 5.0);
    assert!(slide.get("spring_rest").is_none());
    assert_eq!(
        slide["friction"], 0.4,
        "frictionloss is the joint's friction"
    );
    assert!(hinge.get("friction").is_none());
    assert_eq!(
        error(&bare(
            r#"<body><joint frictionloss="-1"/><geom size="0.1"/></body>"#
        )),
        "line 3: <joint frictionloss=…>: expected a friction >= 0, got -1"
    );
    assert_eq!(
        error("<mujoco>\n<compiler settotalmass=\"heavy\"/>\n<worldbody/>\n</mujoco>"),
        "line 2: <compiler settotalmass=…>: expected a number, got \"heavy\""
    );
    assert_eq!(
        error(&bare(
            r#"<body><joint stiffness="-1"/><geom size="0.1"/></body>"#
        )),
        "line 3: <joint stiffness=…>: expected a stiffness >= 0, got -1"
    );
    assert_eq!(
        error(&bare(
            r#"<body><joint type="ball" stiffness="1"/><geom size="0.1"/></body>"#
        )),
        "line 3: <joint>: stiffness on a ball joint (a rotational spring) is not supported yet"
    );
}

/// What a free joint carries that its six DOFs cannot take (damping, armature) is warned
/// about. Free bodies with nothing jointed below them are objects: each observed as its
/// own pose and velocity, none of them the floating base.
#[test]
fn free_joint_extras_are_warned_about_and_every_free_body_is_observed() {
    let xml = bare(
        r#"<geom type="plane" size="1 1 0.1"/><body name="a"><joint type="free" damping="2" armature="0.1"/><geom size="0.1"/></body><body name="b" pos="1 0 0"><freejoint/><geom size="0.1"/></body>"#,
    );
    let converted = mjcf_to_document(&xml).expect("converts");
    let w = &converted.warnings;
    assert!(
        w.iter()
            .any(|m| m.contains("damping on a free joint ignored (its six DOFs take none)")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|m| m.contains("armature on a free joint ignored")),
        "{w:?}"
    );
    assert!(converted.document.get("floating_base").is_none());
    let env =
        RobotEnv::from_json(&converted.document.to_string(), EnvConfig::default()).expect("builds");
    assert_eq!(env.spec().free_bodies, ["a", "b"]);
    let layout: Vec<(&str, usize)> = env
        .spec()
        .observation_layout
        .iter()
        .map(|s| (s.name, s.size))
        .collect();
    assert_eq!(
        layout,
        [
            ("joint_positions", 0),
            ("joint_velocities", 0),
            ("free_body_poses", 14),
            ("free_body_velocities", 12),
            ("end_effector_poses", 0)
        ]
    );
}
