//! MJCF descriptions nobody here wrote (Gymnasium's Reacher and InvertedPendulum) convert
//! into documents that parse, build and move as MuJoCo's models do; unsupported
//! constructs are errors naming the element and its line.

mod common;

use common::{env, error, model};
use gymfleet_env::{ActionType, EnvConfig, RobotEnv};
use gymfleet_import::{mjcf_to_document, ImportError};

const REACHER: &str = include_str!("data/reacher.xml");
const INVERTED_PENDULUM: &str = include_str!("data/inverted_pendulum.xml");

#[test]
fn reacher_has_two_driven_joints_and_two_passive_target_slides() {
    let (env, warnings) = env(REACHER, &["fingertip"]);
    let spec = env.spec();
    let names: Vec<&str> = spec.dofs.iter().map(|d| d.joint_name.as_str()).collect();
    assert_eq!(names, ["joint0", "joint1", "target_x", "target_y"]);
    assert_eq!(spec.action_dim, 2, "only the motors' joints take actions");
    let limits: Vec<Option<[f64; 2]>> = spec.dofs.iter().map(|d| d.limits).collect();
    assert_eq!(limits[0], None, "joint0 is limited=\"false\"");
    let [lo, hi] = limits[1].expect("joint1 is limited");
    assert!(
        (hi - 3.0f64.to_degrees()).abs() < 1e-9 && (lo + hi).abs() < 1e-9,
        "{lo} {hi}"
    );
    // ±0.27 m of MuJoCo's qpos, whose value at the model's pose is ref = ±0.1 m.
    let [lo, hi] = limits[2].expect("target_x is limited");
    assert!(
        (lo + 370.0).abs() < 1e-9 && (hi - 170.0).abs() < 1e-9,
        "{lo} {hi}"
    );
    let [lo, hi] = limits[3].expect("target_y is limited");
    assert!(
        (lo + 170.0).abs() < 1e-9 && (hi - 370.0).abs() < 1e-9,
        "{lo} {hi}"
    );
    // gear 200 × ctrlrange ±1; actions are MuJoCo's ctrl (the effort is gear × ctrl).
    assert_eq!(spec.dofs[0].max_effort, Some(200.0));
    assert_eq!(spec.dofs[0].gear, 200.0);
    // The target slides report MuJoCo's qpos: ref (±0.1 m) at the model's pose.
    assert_eq!(spec.dofs[2].reference, 100.0);
    assert_eq!(spec.dofs[3].reference, -100.0);
    assert_eq!(spec.dofs[2].gear, 1.0);
    // MuJoCo's timestep is an env step unless the request asks for another `dt`.
    assert_eq!(spec.dt, 0.01);
    let expected = "plane that collides with nothing";
    assert!(
        warnings.iter().any(|w| w.contains(expected)),
        "no warning {expected:?} in {warnings:#?}"
    );
    // Neither the gear nor ref is a warning any more: both are kept.
    assert!(
        !warnings
            .iter()
            .any(|w| w.contains("gear") || w.contains("ref")),
        "{warnings:#?}"
    );
}

#[test]
fn reacher_masses_are_mujocos_from_the_geoms() {
    let converted = mjcf_to_document(REACHER).expect("converts");
    let assembly = gymfleet_assembly::parse(&converted.document.to_string()).expect("parses");
    let mass = |name: &str| {
        let i = assembly.instance_index(name).expect(name);
        let inst = &assembly.instances[i];
        inst.shape.volume() * inst.material.density
    };
    // A capsule of radius 1 cm and 10 cm between its caps' centres, water-dense.
    let pi = std::f64::consts::PI;
    let link = 1000.0 * (pi * 0.01f64.powi(2) * 0.1 + 4.0 / 3.0 * pi * 0.01f64.powi(3));
    for name in ["link0", "link1"] {
        assert!(
            (mass(name) - link).abs() < 1e-12,
            "{name}: {} kg against {link}",
            mass(name)
        );
    }
    let tip = 1000.0 * 4.0 / 3.0 * pi * 0.01f64.powi(3);
    assert!((mass("fingertip") - tip).abs() < 1e-12);
}

/// Reacher's dynamics are its armature (1 kg·m²) and damping (1 N·m·s/rad), against links
/// of a few grams: under a constant torque τ the shoulder's speed follows
/// `τ/b·(1 − e^(−b·t/J))` with `J` the armature plus the links' own inertia. Within 2 %.
#[test]
fn reacher_shoulder_spins_up_through_its_armature_and_damping() {
    let (mut env, _) = env(REACHER, &["fingertip"]);
    let (tau, b, dt) = (0.05, 1.0, env.spec().dt);
    // The action is MuJoCo's ctrl: the torque is gear (200) × ctrl.
    let gear = env.spec().dofs[0].gear;
    // The links' inertia about the shoulder (link0, link1 and the tip, straight out):
    // small beside the armature; MuJoCo's body_inertia gives about 1.2e-3 kg·m² in all.
    let j = 1.0 + 1.2e-3;
    let mut speed = 0.0;
    let steps = (0.5 / dt).round() as usize;
    for _ in 0..steps {
        let obs = env
            .step(ActionType::Torque, &[(tau / gear) as f32, 0.0])
            .expect("steps")
            .observation;
        speed = f64::from(obs.joint_velocities[0]).to_radians();
    }
    let t = steps as f64 * dt;
    let analytic = tau / b * (1.0 - (-b * t / j).exp());
    assert!(
        (speed - analytic).abs() / analytic < 0.02,
        "shoulder at {speed} rad/s after {t} s; analytic {analytic}"
    );
}

#[test]
fn reacher_holds_still_under_pd_at_its_initial_pose() {
    let (mut env, _) = env(REACHER, &["fingertip"]);
    for _ in 0..240 {
        env.step(ActionType::Position, &[0.0, 0.0]).expect("steps");
    }
    let obs = env.observe();
    // Positions are MuJoCo's qpos: the target slides start at their ref (±100 mm).
    for (k, (q, dof)) in obs.joint_positions.iter().zip(&env.spec().dofs).enumerate() {
        let moved = f64::from(*q) - dof.reference;
        assert!(
            moved.abs() < 1e-3,
            "joint {k} moved to {q} from {}",
            dof.reference
        );
    }
}

#[test]
fn inverted_pendulum_has_a_driven_cart_and_a_passive_pole() {
    let (mut env, _) = env(INVERTED_PENDULUM, &["cpole"]);
    let spec = env.spec().clone();
    let names: Vec<&str> = spec.dofs.iter().map(|d| d.joint_name.as_str()).collect();
    assert_eq!(names, ["slider", "hinge"]);
    assert_eq!(spec.action_dim, 1);
    assert_eq!(
        spec.dofs[0].max_effort,
        Some(300.0),
        "gear 100 × ctrlrange ±3"
    );
    assert_eq!(spec.dofs[0].limits, Some([-1000.0, 1000.0]));
    assert_eq!(
        spec.dofs[1].limits,
        Some([-90.0, 90.0]),
        "degrees: the default angle unit"
    );
    // The pole starts nearly upright (its top 1 mm off the hinge's vertical: 0.095°) and
    // falls to the side it leans to, +x, i.e. positive about +y, growing about as
    // cosh(ω·t) with ω ≈ 5 /s: about 0.5° at 0.5 s, several degrees at 1 s.
    let mut angles = Vec::new();
    for _ in 0..240 {
        angles.push(
            env.step(ActionType::Torque, &[0.0])
                .expect("steps")
                .observation
                .joint_positions[1],
        );
    }
    // It falls steadily until its stop at 90°, which is MuJoCo's soft limit (solref 0.02
    // s, vendored patch 44): the pole presses a few degrees into it, springs back, and
    // rests just past it, where the limit's spring carries its weight.
    let stop = angles
        .iter()
        .position(|&a| a >= 90.0)
        .expect("reaches its stop");
    assert!(
        angles[..=stop].windows(2).all(|w| w[1] >= w[0]),
        "the pole falls steadily: {angles:?}"
    );
    let peak = angles.iter().copied().fold(0.0f32, f32::max);
    assert!(peak < 100.0, "it pressed {peak}° into its stop");
    assert!(
        (angles[239] - 90.0).abs() < 0.5,
        "it rests at {}°",
        angles[239]
    );
    assert!(
        angles[119] > 0.2 && angles[239] > 2.0,
        "at 0.5 s {}°, at 1 s {}°",
        angles[119],
        angles[239]
    );
}

const BODY: &str = r#"<body name="b"><geom type="sphere" size=".1"/><joint type="hinge"/></body>"#;

#[test]
fn unsupported_constructs_name_their_element_and_line() {
    assert_eq!(
        error(&model(
            r#"<body><joint type="hinge"/><geom type="plane" size="1 1 1"/></body>"#
        )),
        "line 4: <geom>: a plane (a half-space) belongs to the world or to a body without joints"
    );
    assert_eq!(
        error("<mujoco>\n<asset><hfield file=\"terrain.png\"/></asset>\n<worldbody/>\n</mujoco>"),
        "line 2: <hfield size=…>: missing"
    );
    assert_eq!(
        error(&model(
            r#"<body><joint type="hinge"/><geom type="hfield" hfield="h"/></body>"#
        )),
        "line 4: <geom>: a heightfield (terrain) belongs to the world or to a body without joints"
    );
    assert_eq!(
        error("<mujoco>\n<asset><hfield name=\"h\" nrow=\"2\" ncol=\"2\" size=\"1 1 1 0\" elevation=\"1 2 3\"/></asset>\n<worldbody/>\n</mujoco>"),
        "line 2: <hfield elevation=…>: expected nrow × ncol = 4 numbers, got 3"
    );
    assert_eq!(
        error("<mujoco>\n<worldbody>\n<geom type=\"hfield\" hfield=\"nothing\"/></worldbody>\n</mujoco>"),
        "line 3: <geom hfield=…>: no <hfield> is named \"nothing\""
    );
    assert_eq!(
        error(&model(
            r#"<body><joint type="ball" range="0 30"/><geom size=".1"/></body>"#
        )),
        "line 4: <joint>: a ball joint's range (a cone) is not supported yet"
    );
    assert_eq!(
        error(&model(
            r#"<body><joint type="ball" springdamper="0.1 1"/><geom size=".1"/></body>"#
        )),
        "line 4: <joint>: springdamper on a ball joint (a rotational spring) is not supported yet"
    );
    assert_eq!(
        error(&model(
            r#"<body><joint springdamper="0.1 -1"/><geom size=".1"/></body>"#
        )),
        "line 4: <joint springdamper=…>: expected a time constant and a damping ratio, both > 0, got 0.1 -1"
    );
    let converted = mjcf_to_document(&model(
        r#"<body><joint name="tail" springdamper="0.1 1" springref="0.2"/><geom size=".1"/></body>"#,
    ))
    .expect("converts");
    let joint = converted.document["assembly"]["joints"]
        .as_array()
        .expect("joints")
        .iter()
        .find(|j| j["name"] == "tail")
        .expect("the joint")
        .clone();
    assert_eq!(joint["springdamper"], serde_json::json!([0.1, 1.0]));
    assert!(joint.get("stiffness").is_none(), "{joint}");
    assert!(joint["spring_rest"].as_f64().is_some(), "{joint}");
    assert_eq!(
        error(&model(r#"<composite type="grid"/>"#)),
        "line 4: <composite>: <composite> in <worldbody> is not supported yet"
    );
    assert_eq!(
        error(&format!(
            "<mujoco>\n<worldbody>\n{BODY}\n</worldbody>\n<actuator>\n<muscle joint=\"j\"/>\n</actuator>\n</mujoco>"
        )),
        "line 6: <muscle>: muscle actuators are not supported yet (MuJoCo's muscle model: its length–force and velocity curves)"
    );
    assert_eq!(
        error(&format!(
            "<mujoco>\n<worldbody>\n{BODY}\n</worldbody>\n<actuator>\n<general joint=\"j\" gaintype=\"user\"/>\n</actuator>\n</mujoco>"
        )),
        "line 6: <general>: gaintype \"user\" is not supported (supported: fixed, affine)"
    );
    assert_eq!(
        error(&format!(
            "<mujoco>\n<worldbody>\n{BODY}\n</worldbody>\n<actuator>\n<position joint=\"j\" inheritrange=\"1\"/>\n</actuator>\n</mujoco>"
        )),
        "line 6: <position inheritrange=…>: \"1\": inheritrange is not supported yet; give ctrlrange"
    );
    assert_eq!(
        error(&format!(
            "<mujoco>\n<worldbody>\n{BODY}\n</worldbody>\n<actuator>\n<position joint=\"j\" kv=\"1\" dampratio=\"1\"/>\n</actuator>\n</mujoco>"
        )),
        "line 6: <position dampratio=…>: kv and dampratio cannot both be defined"
    );
    assert_eq!(
        error(&format!(
            "<mujoco>\n<worldbody>\n{BODY}\n</worldbody>\n<actuator>\n<general joint=\"b_joint\" ctrlrange=\"1 -1\"/>\n</actuator>\n</mujoco>"
        )),
        "line 6: <general ctrlrange=…>: expected min < max for a limited range, got [1, -1]"
    );
    assert_eq!(
        error(&format!(
            "<mujoco>\n<worldbody>\n{BODY}\n</worldbody>\n<actuator>\n<motor joint=\"elbow\"/>\n</actuator>\n</mujoco>"
        )),
        "line 6: <motor joint=…>: no hinge, slide or ball joint is named \"elbow\""
    );
    assert_eq!(
        error(&model(r#"<body pos="0 0 x"><geom size=".1"/></body>"#)),
        "line 4: <body pos=…>: expected finite numbers, got \"0 0 x\""
    );
    assert_eq!(
        error(&model(
            r#"<body><geom type="capsule" fromto="0 0 0 0 0 0" size=".1"/></body>"#
        )),
        "line 4: <geom fromto=…>: the two ends are the same point"
    );
    assert!(matches!(
        mjcf_to_document("<mujoco><worldbody>"),
        Err(ImportError::Xml(_))
    ));
}

#[test]
fn several_joints_in_one_body_chain_through_helpers_and_defaults_apply() {
    let xml = r#"<mujoco>
      <default>
        <joint damping="0.5"/>
        <default class="stiff"><joint damping="2" armature="0.1"/></default>
      </default>
      <worldbody>
        <geom type="box" size=".1 .1 .01"/>
        <body name="b" pos="0 0 .5" childclass="stiff">
          <joint name="x" type="slide" axis="1 0 0"/>
          <joint name="y" type="slide" axis="0 1 0" class="main"/>
          <geom type="sphere" size=".05"/>
        </body>
      </worldbody>
    </mujoco>"#;
    let converted = mjcf_to_document(xml).expect("converts");
    let joints = converted.document["assembly"]["joints"]
        .as_array()
        .expect("joints")
        .clone();
    assert_eq!(joints.len(), 2, "{joints:#?}");
    assert_eq!(joints[0]["damping"], 2.0, "childclass applies");
    assert_eq!(joints[0]["armature"], 0.1);
    assert_eq!(
        joints[1]["damping"], 0.5,
        "an explicit class overrides the childclass"
    );
    assert_eq!(
        joints[0]["child"], joints[1]["parent"],
        "a helper between the two"
    );
    let (env, _) = env(xml, &[]);
    assert_eq!(env.spec().dofs.len(), 2);
}

/// `<inertial>` is written on the body's instance in that instance's own frame (mm), the
/// geoms then weighing next to nothing; `euler` and `quat` give the same orientation.
#[test]
fn an_inertial_lands_in_the_body_instances_frame() {
    let body = |orientation: &str| {
        format!(
            r#"<mujoco><compiler angle="degree"/><worldbody>
            <geom type="box" size=".1 .1 .01"/>
            <body name="b" pos="0 0 1" {orientation}>
              <joint type="hinge" axis="0 1 0"/>
              <geom type="box" size=".1 .2 .3" pos="0.5 0 0"/>
              <inertial mass="2" pos="0.1 0 0" diaginertia="0.1 0.2 0.3"/>
            </body></worldbody></mujoco>"#
        )
    };
    for orientation in [r#"euler="0 0 90""#, r#"quat="0.70710678 0 0 0.70710678""#] {
        let converted = mjcf_to_document(&body(orientation)).expect("converts");
        let instance = &converted.document["assembly"]["instances"][1];
        let close = |v: &serde_json::Value, expected: f64| {
            (v.as_f64().expect("a number") - expected).abs() < 1e-6
        };
        // The box's corner: its centre (0, 0.5, 1) m less R·(0.1, 0.2, 0.3), R = 90° about z.
        assert!(
            close(&instance["position"]["x"], 200.0),
            "{orientation}: {instance}"
        );
        assert!(
            close(&instance["position"]["y"], 400.0),
            "{orientation}: {instance}"
        );
        assert!(
            close(&instance["rotation"]["z"], 90.0),
            "{orientation}: {instance}"
        );
        let inertial = &instance["inertial"];
        assert_eq!(inertial["mass"], 2.0);
        // The centre of mass (0, 0.1, 1) m in the world, seen from the box's corner frame.
        let com = &inertial["center_of_mass"];
        assert!(
            close(&com["x"], -300.0) && close(&com["y"], 200.0) && close(&com["z"], 300.0),
            "{com}"
        );
        let i = &inertial["inertia"];
        assert!(
            close(&i["xx"], 0.1) && close(&i["yy"], 0.2) && close(&i["zz"], 0.3),
            "{i}"
        );
        assert!(
            close(&i["xy"], 0.0) && close(&i["xz"], 0.0) && close(&i["yz"], 0.0),
            "{i}"
        );
        let (env, _) = env(&body(orientation), &["b_geom"]);
        assert_eq!(env.spec().dofs.len(), 1);
    }
}

#[test]
fn a_motor_force_range_bounds_max_effort() {
    let xml = format!(
        "<mujoco>\n<worldbody>\n{BODY}\n</worldbody>\n<actuator>\n<motor joint=\"b_joint\" gear=\"100\" ctrlrange=\"-1 1\" forcerange=\"-30 30\"/>\n</actuator>\n</mujoco>"
    );
    let converted = mjcf_to_document(&xml).expect("converts");
    assert_eq!(
        converted.document["assembly"]["joints"][0]["max_effort"],
        30.0
    );
}

#[test]
fn more_bad_descriptions_name_their_element_and_line() {
    assert_eq!(
        error("<mujoco>\n<option timestep=\"0\"/>\n<worldbody/>\n</mujoco>"),
        "line 2: <option timestep=…>: expected (0, 1] s, got 0"
    );
    assert_eq!(
        error(&model(
            r#"<body quat="1 0 0 0" euler="0 0 0"><geom size=".1"/></body>"#
        )),
        "line 4: <body euler=…>: an orientation is given twice (quat, euler)"
    );
    assert_eq!(
        error(&model(r#"<body quat="0 0 0 0"><geom size=".1"/></body>"#)),
        "line 4: <body quat=…>: the zero quaternion is no rotation"
    );
    assert_eq!(
        error(&model(
            r#"<body xyaxes="1 0 0 2 0 0"><geom size=".1"/></body>"#
        )),
        "line 4: <body xyaxes=…>: the y axis is zero or parallel to the x axis"
    );
    assert_eq!(
        error(&model(
            r#"<body xyaxes="0 0 0 0 1 0"><geom size=".1"/></body>"#
        )),
        "line 4: <body xyaxes=…>: the x axis is the zero vector"
    );
    assert_eq!(
        error(&model(
            r#"<body><joint type="screw"/><geom size=".1"/></body>"#
        )),
        "line 4: <joint type=…>: unknown joint type \"screw\""
    );
    assert_eq!(
        error(&model(
            r#"<body><joint/><geom type="ellipsoid" size=".1 .2"/></body>"#
        )),
        "line 4: <geom size=…>: an ellipsoid needs a positive z semi-axis (size[2])"
    );
    assert_eq!(
        error(&model(r#"<body><geom type="capsule" size=".1"/></body>"#)),
        "line 4: <geom size=…>: a capsule needs a positive half-length (size[1])"
    );
}

#[test]
fn fixed_tendons_become_the_documents_tendons() {
    let body = |name: &str| {
        format!(
            "<body name=\"{name}\"><joint name=\"{name}\" type=\"hinge\" axis=\"0 1 0\"/><geom type=\"capsule\" fromto=\"0 0 0 0 0 -0.1\" size=\"0.01\"/>"
        )
    };
    let xml = format!(
        "<mujoco><worldbody>{}{}</body></body></worldbody>\n<tendon>\n\
         <fixed name=\"t\" stiffness=\"3\" damping=\"0.5\" springlength=\"0.1\" range=\"-0.5 0.5\"><joint joint=\"j1\" coef=\"-1\"/><joint joint=\"j2\" coef=\"2\"/></fixed>\n\
         <fixed><joint joint=\"j2\" coef=\"1\"/></fixed>\n</tendon></mujoco>",
        body("j1"),
        body("j2")
    );
    let converted = mjcf_to_document(&xml).expect("converts");
    assert_eq!(
        converted.document["assembly"]["tendons"],
        serde_json::json!([
            {"name": "t", "joints": [{"joint": "j1", "coef": -1.0}, {"joint": "j2", "coef": 2.0}],
             "stiffness": 3.0, "damping": 0.5, "spring_length": 0.1, "range": [-0.5, 0.5]},
            {"name": "tendon1", "joints": [{"joint": "j2", "coef": 1.0}]}
        ])
    );
    let assembly = gymfleet_assembly::parse(&converted.document.to_string()).expect("parses");
    assert_eq!(assembly.tendons[0].joints, vec![(0, -1.0), (1, 2.0)]);
    let refused = |tendon: &str| {
        error(&format!(
            "<mujoco><worldbody>{}</body></worldbody>\n<tendon>\n{tendon}\n</tendon></mujoco>",
            body("j1")
        ))
    };
    assert_eq!(
        refused(r#"<fixed range="1 0"><joint joint="j1" coef="1"/></fixed>"#),
        "line 3: <fixed range=…>: expected min < max, got 1 0"
    );
    assert_eq!(
        refused(r#"<fixed limited="true"><joint joint="j1" coef="1"/></fixed>"#),
        "line 3: <fixed range=…>: missing: a limited tendon needs a range"
    );
    assert_eq!(
        refused(r#"<fixed frictionloss="1"><joint joint="j1" coef="1"/></fixed>"#),
        "line 3: <fixed>: a tendon's frictionloss is not supported yet"
    );
    assert_eq!(
        refused(r#"<spatial><site site="s"/></spatial>"#),
        "line 3: <spatial site=…>: a spatial tendon needs at least two <site>s, got 1"
    );
    assert_eq!(
        refused(r#"<spatial><site site="s"/><geom geom="g" sidesite="s"/><site site="s"/></spatial>"#),
        "line 3: <geom>: wrapping around a geom (with its sidesite) is not supported yet: a spatial tendon goes straight through its sites"
    );
    assert_eq!(
        refused(r#"<spatial><site site="s"/><pulley divisor="2"/><site site="s"/></spatial>"#),
        "line 3: <pulley>: <pulley> in a spatial tendon is not supported (only <site>)"
    );
    assert_eq!(
        refused(r#"<spatial><site site="s"/><site site="nowhere"/></spatial>"#),
        "line 3: <site site=…>: no site is named \"s\""
    );
    assert_eq!(
        error(&format!(
            "<mujoco><worldbody>{}</body></worldbody>\n<tendon><fixed name=\"t\"><joint joint=\"j1\" coef=\"1\"/></fixed></tendon>\n<actuator>\n<motor site=\"s\"/>\n</actuator></mujoco>",
            body("j1")
        )),
        "line 4: <motor>: site transmissions are not supported (an actuator drives a joint or a tendon)"
    );
    assert_eq!(
        error(&format!(
            "<mujoco><worldbody>{}</body></worldbody>\n<tendon><fixed name=\"t\"><joint joint=\"j1\" coef=\"1\"/></fixed></tendon>\n<actuator>\n<motor tendon=\"u\"/>\n</actuator></mujoco>",
            body("j1")
        )),
        "line 4: <motor tendon=…>: no tendon is named \"u\""
    );
    assert_eq!(
        refused(r#"<fixed><joint joint="j9" coef="1"/></fixed>"#),
        "line 3: <joint joint=…>: no hinge or slide joint is named \"j9\""
    );
    assert_eq!(
        refused(r#"<fixed><joint joint="j1"/></fixed>"#),
        "line 3: <joint coef=…>: missing"
    );
}

#[test]
fn the_worlds_geoms_are_fixed_and_a_plane_stops_what_hangs_above_it() {
    let converted = mjcf_to_document(
        "<mujoco><worldbody>\
         <geom name=\"post\" type=\"box\" size=\"0.01 0.01 0.1\" pos=\"0 0 0.1\" contype=\"0\" conaffinity=\"0\"/>\
         <geom name=\"floor\" type=\"plane\" size=\"1 1 0.1\"/>\
         <body pos=\"0 0 0.2\"><joint type=\"hinge\" axis=\"0 1 0\"/><geom type=\"capsule\" fromto=\"0 0 0 0.3 0 0\" size=\"0.01\"/></body>\
         </worldbody></mujoco>",
    )
    .expect("converts");
    let instances = converted.document["assembly"]["instances"]
        .as_array()
        .unwrap();
    let fixed: Vec<&str> = instances
        .iter()
        .filter(|i| i["fixed"] == true)
        .map(|i| i["name"].as_str().unwrap())
        .collect();
    assert_eq!(fixed, ["post", "floor"], "{instances:?}");
    let (mut env, _) = (
        RobotEnv::from_json(&converted.document.to_string(), EnvConfig::default()).expect("builds"),
        (),
    );
    // The arm falls about its hinge 200 mm above the floor; its 300 mm capsule meets the
    // floor after about 39° and stops there.
    for _ in 0..480 {
        env.step(ActionType::Torque, &[]).expect("steps");
    }
    let q = env.observe().joint_positions[0];
    // The capsule's tip (radius 10 mm) touches the floor when 0.2 − 0.3·sin θ = 0.01; MuJoCo's
    // default compliance lets it sink about half a millimetre (0.12°) into it.
    let stop = (0.19f64 / 0.3).asin().to_degrees() as f32;
    assert!(
        (0.0..0.2).contains(&(q - stop)),
        "the arm rests at {q} deg, on the floor at {stop}"
    );
    // Walls are planes too: as many as the model has, each fixed where it is.
    let walls = mjcf_to_document(
        "<mujoco><worldbody>\n<geom type=\"plane\" size=\"1 1 1\"/>\n<geom type=\"plane\" size=\"1 1 1\" zaxis=\"1 0 0\" pos=\"-1 0 0\"/>\n</worldbody></mujoco>",
    )
    .expect("two planes");
    let instances = walls.document["assembly"]["instances"].as_array().unwrap();
    assert_eq!(instances.len(), 2);
    assert!(
        instances.iter().all(|i| i["fixed"] == true),
        "{instances:?}"
    );
}

#[test]
fn a_range_that_excludes_the_models_pose_starts_at_its_nearest_end() {
    let converted = mjcf_to_document(&model(
        r#"<body name="b"><joint name="j" type="hinge" axis="0 1 0" range="10 50"/><geom size=".1"/></body>"#,
    ))
    .expect("converts");
    let joints = converted.document["assembly"]["joints"]
        .as_array()
        .expect("joints");
    let j = joints.iter().find(|j| j["name"] == "j").expect("joint j");
    assert_eq!(j["initial"], 10.0);
    assert!(
        converted
            .warnings
            .iter()
            .any(|w| w.contains("joint \"j\" starts at 10 deg")),
        "{:?}",
        converted.warnings
    );
    let mut env =
        RobotEnv::from_json(&converted.document.to_string(), EnvConfig::default()).expect("builds");
    assert!((env.reset(None).joint_positions[0] - 10.0).abs() < 1e-4);
}

#[test]
fn a_spatial_tendon_converts_through_its_sites() {
    let xml = r#"<mujoco><worldbody>
      <site name="anchor" pos="0 0 1"/>
      <body name="ball" pos="0 0 0.5">
        <joint name="z" type="slide" axis="0 0 1"/>
        <geom type="sphere" size="0.05"/>
        <site name="ball" pos="0 0 0.05"/>
      </body>
    </worldbody>
    <tendon>
      <spatial name="string" range="0 0.6" stiffness="2" damping="0.1" springlength="0.4">
        <site site="anchor"/><site site="ball"/>
      </spatial>
    </tendon>
    <actuator><motor tendon="string" gear="2"/></actuator>
    </mujoco>"#;
    let converted = mjcf_to_document(xml).expect("converts");
    let tendon = &converted.document["assembly"]["tendons"][0];
    assert_eq!(tendon["name"], "string");
    assert_eq!(tendon["range"], serde_json::json!([0.0, 0.6]));
    assert_eq!(tendon["stiffness"], 2.0);
    assert_eq!(tendon["damping"], 0.1);
    assert_eq!(tendon["spring_length"], 0.4);
    assert!(tendon.get("joints").is_none());
    let sites = tendon["sites"].as_array().expect("sites");
    assert_eq!(sites.len(), 2);
    let assembly = gymfleet_assembly::parse(&converted.document.to_string()).expect("parses");
    let t = &assembly.tendons[0];
    assert!(t.is_spatial() && t.joints.is_empty());
    // The sites' instances: the world's and the ball's.
    let names: Vec<&str> = t
        .sites
        .iter()
        .map(|&s| assembly.instances[assembly.sites[s].instance].name.as_str())
        .collect();
    assert_ne!(names[0], names[1]);
    assert!(names[1].starts_with("ball"), "{names:?}");
    assert_eq!(
        converted.document["assembly"]["actuators"][0]["tendon"],
        "string"
    );
}

#[test]
fn a_site_with_fromto_sits_midway_looking_from_the_second_point_to_the_first() {
    // MuJoCo: the site's z axis runs from the second point to the first (a rangefinder
    // on it looks that way), its size[1] is half the segment.
    let xml = r#"<mujoco><worldbody>
      <body name="b"><joint type="hinge"/><geom type="sphere" size="0.1"/>
        <site name="s" type="capsule" size="0.01" fromto="0.3 0 0 0.1 0 0"/>
      </body>
    </worldbody></mujoco>"#;
    let converted = mjcf_to_document(xml).expect("converts");
    let site = converted.document["assembly"]["sites"]
        .as_array()
        .expect("sites")
        .iter()
        .find(|s| s["name"] == "s")
        .expect("the site")
        .clone();
    let assembly = gymfleet_assembly::parse(&converted.document.to_string()).expect("parses");
    let s = assembly
        .sites
        .iter()
        .find(|s| s.name == "s")
        .expect("the site");
    assert!((s.point[0] - 200.0).abs() < 1e-9, "{:?}", s.point);
    // z onto +x: a turn of +90° about y.
    assert!(
        (s.rotation[1] - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "{:?}",
        s.rotation
    );
    let half = site["volume"]["size"]["y"].as_f64().expect("a half-length");
    assert!((half - 100.0).abs() < 1e-9, "{half} mm");
}
