//! MJCF `<equality>`: `<connect>` and `<weld>` close kinematic loops, `<joint>` and
//! `<tendon>` become couplings; the other kinds are refused with their element and line.

use gymfleet_env::{ActionType, EnvConfig, RobotEnv};
use gymfleet_import::mjcf_to_document;

/// A crank-rocker four-bar (crank 40 mm, coupler 120, rocker 100, ground 110), its loop
/// closed by a `<connect>` at the coupler's end: MuJoCo's way of writing a closed chain.
const FOUR_BAR: &str = r#"<mujoco>
  <worldbody>
    <body name="crank">
      <joint name="crank" type="hinge" axis="0 -1 0"/>
      <geom type="capsule" fromto="0 0 0 0.02 0 0.034641" size="0.004"/>
      <body name="coupler" pos="0.02 0 0.034641">
        <joint name="elbow" type="hinge" axis="0 -1 0"/>
        <geom type="capsule" fromto="0 0 0 0.1010328 0 0.0647485" size="0.004"/>
      </body>
    </body>
    <body name="rocker" pos="0.11 0 0">
      <joint name="rocker" type="hinge" axis="0 -1 0"/>
      <geom type="capsule" fromto="0 0 0 0.0110328 0 0.0993895" size="0.004"/>
    </body>
  </worldbody>
  <equality>
    <connect name="pin" body1="coupler" body2="rocker" anchor="0.1010328 0 0.0647485"/>
  </equality>
  <actuator><motor joint="crank"/></actuator>
</mujoco>"#;

#[test]
fn a_connect_closes_the_loop_and_adds_no_observed_dof() {
    let converted = mjcf_to_document(FOUR_BAR).expect("converts");
    let pin = converted.document["assembly"]["joints"]
        .as_array()
        .expect("joints")
        .iter()
        .find(|j| j["name"] == "pin")
        .expect("the connect's joint")
        .clone();
    assert_eq!(pin["type"], "ball");
    assert_eq!(pin["observed"], false);
    // The anchor in body1's frame, in the world: the coupler's far end (mm).
    let x = pin["anchor"]["x"].as_f64().expect("x");
    let z = pin["anchor"]["z"].as_f64().expect("z");
    assert!(
        (x - 121.0328).abs() < 1e-6 && (z - 99.3895).abs() < 1e-6,
        "{pin}"
    );
    let text = converted.document.to_string();
    let assembly = gymfleet_assembly::parse(&text).expect("valid");
    assert_eq!(
        assembly.joints.iter().filter(|j| j.closes_loop).count(),
        1,
        "the connect closes the loop"
    );
    let mut env =
        RobotEnv::from_json(&text, EnvConfig::with_end_effectors(["rocker"])).expect("builds");
    assert_eq!(
        env.spec().num_dofs,
        3,
        "MuJoCo's qpos: crank, elbow, rocker"
    );
    assert_eq!(env.spec().action_dim, 1);
    // Driven a quarter turn, the rocker follows the linkage (it swings, it is not free).
    let mut q = Vec::new();
    for _ in 0..240 {
        q = env
            .step(ActionType::Velocity, &[90.0])
            .expect("steps")
            .observation
            .joint_positions;
    }
    // The rocker against the closed form at the measured crank angle (from 60°): the
    // crossing of the coupler's circle about the crank pin and the rocker's about O4.
    let theta = (60.0 + f64::from(q[0])).to_radians();
    let (ax, az) = (40.0 * theta.cos(), 40.0 * theta.sin());
    let (dx, dz) = (110.0 - ax, -az);
    let dist = dx.hypot(dz);
    let along = (120.0f64.powi(2) - 100.0f64.powi(2) + dist * dist) / (2.0 * dist);
    let across = (120.0f64.powi(2) - along * along).sqrt();
    let b = [
        ax + (along * dx - across * dz) / dist,
        az + (along * dz + across * dx) / dist,
    ];
    let rocker = (b[1].atan2(b[0] - 110.0) - 99.3895f64.atan2(11.0328)).to_degrees();
    println!(
        "crank {:.3}°, rocker {:.4}° (closed form {rocker:.4}°)",
        q[0], q[2]
    );
    assert!(q[0] > 45.0, "the crank turns: {}", q[0]);
    assert!(
        (f64::from(q[2]) - rocker).abs() < 0.05,
        "rocker {} against {rocker}",
        q[2]
    );
}

/// A body on six joints (three slides and a ball) welded to the world: the weld takes
/// exactly its six DOFs, and gravity does not move it. A `relpose` that would pull the body
/// elsewhere at the start is refused.
#[test]
fn a_weld_to_the_world_holds_a_body_and_a_displaced_relpose_is_refused() {
    let xml = r#"<mujoco>
  <worldbody>
    <body name="block" pos="0 0 0.2">
      <joint name="x" type="slide" axis="1 0 0"/>
      <joint name="y" type="slide" axis="0 1 0"/>
      <joint name="z" type="slide" axis="0 0 1"/>
      <joint name="turn" type="ball"/>
      <geom type="box" size="0.05 0.02 0.01" pos="0.03 0 0"/>
    </body>
  </worldbody>
  <equality><weld body1="block"/></equality>
</mujoco>"#;
    let converted = mjcf_to_document(xml).expect("converts");
    let text = converted.document.to_string();
    let mut env =
        RobotEnv::from_json(&text, EnvConfig::with_end_effectors(["block"])).expect("builds");
    let mut q = Vec::new();
    for _ in 0..240 {
        q = env
            .step(ActionType::Torque, &[])
            .expect("steps")
            .observation
            .joint_positions;
    }
    // Welded to the world, the block does not fall (mm and deg).
    println!("after 1 s: {q:?}");
    assert!(q.iter().all(|v| v.abs() < 0.01), "{q:?}");
    // relpose is body2's (the world's) pose in body1's frame: 0.2 m below the block.
    let holding = xml.replace(
        r#"<weld body1="block"/>"#,
        r#"<weld body1="block" relpose="0 0 -0.2 1 0 0 0"/>"#,
    );
    mjcf_to_document(&holding).expect("a relpose that holds in the model's pose converts");
    let displaced = xml.replace(
        r#"<weld body1="block"/>"#,
        r#"<weld body1="block" relpose="0 0 -0.19 1 0 0 0"/>"#,
    );
    assert_eq!(
        mjcf_to_document(&displaced).expect_err("refused").to_string(),
        "line 11: <weld relpose=…>: places body2 10.000 mm and 0.000° from where the model places it; a weld must hold in the model's pose (leave relpose out)"
    );
}

#[test]
fn other_equalities_are_refused_with_their_line_and_inactive_ones_left_out() {
    let with = |inner: &str| {
        FOUR_BAR.replace(
        r#"<connect name="pin" body1="coupler" body2="rocker" anchor="0.1010328 0 0.0647485"/>"#,
        inner,
    )
    };
    let refused = |inner: &str| {
        mjcf_to_document(&with(inner))
            .expect_err("refused")
            .to_string()
    };
    assert_eq!(
        refused(r#"<flex flex="cloth"/>"#),
        "line 17: <flex>: <flex> equality constraints are not supported (connect, weld, joint and tendon are)"
    );
    assert_eq!(
        refused(r#"<joint joint1="crank" joint2="nothing"/>"#),
        "line 17: <joint joint2=…>: no hinge or slide joint is named \"nothing\""
    );
    assert_eq!(
        refused(r#"<joint joint2="crank"/>"#),
        "line 17: <joint joint1=…>: missing"
    );
    assert_eq!(
        refused(r#"<tendon tendon1="t"/>"#),
        "line 17: <tendon tendon1=…>: no fixed tendon is named \"t\""
    );
    assert_eq!(
        refused(r#"<joint joint1="crank" joint2="rocker" polycoef="0 1 0.5 0 0"/>"#),
        "line 17: <joint>: polycoef: a nonlinear coupling (a term past the second) is not supported yet"
    );
    assert_eq!(
        refused(r#"<connect body1="coupler" body2="nowhere" anchor="0 0 0"/>"#),
        "line 17: <connect body2=…>: no body is named \"nowhere\""
    );
    assert_eq!(
        refused(r#"<connect site1="a" site2="b"/>"#),
        "line 17: <connect>: site1: an equality between sites is not supported yet (name body1 and body2)"
    );
    let inactive = mjcf_to_document(&with(
        r#"<connect body1="coupler" body2="rocker" anchor="0 0 0" active="false"/>"#,
    ))
    .expect("converts");
    assert!(inactive
        .warnings
        .iter()
        .any(|w| w.contains("an inactive equality is left out")));
}

#[test]
fn joint_and_tendon_equalities_become_couplings() {
    let xml = FOUR_BAR
        .replace(
            r#"<connect name="pin" body1="coupler" body2="rocker" anchor="0.1010328 0 0.0647485"/>"#,
            r#"<joint name="gear" joint1="crank" joint2="rocker" polycoef="0.1 -2 0 0 0" solref="0.01 1"/>
    <tendon tendon1="sum"/>"#,
        )
        .replace(
            "<actuator>",
            r#"<tendon><fixed name="sum"><joint joint="crank" coef="1"/><joint joint="elbow" coef="1"/></fixed></tendon>
  <actuator>"#,
        );
    let converted = mjcf_to_document(&xml).expect("converts");
    let couplings = &converted.document["assembly"]["couplings"];
    assert_eq!(
        couplings,
        &serde_json::json!([
            {"name": "gear", "joint1": "crank", "joint2": "rocker", "polycoef": [0.1, -2.0]},
            {"name": "tendon_coupling1", "tendon1": "sum", "polycoef": [0.0, 1.0]}
        ])
    );
    assert!(converted
        .warnings
        .iter()
        .any(|w| w.contains("solref/solimp ignored: the constraint is hard")));
}
