//! MJCF's `<option>`: gravity, timestep, fluid and integrator become the document's
//! `simulation`; what gymfleet cannot do is an error or a warning naming its line.

mod common;

use common::{error, model};
use gymfleet_assembly::Integrator;
use gymfleet_env::{EnvConfig, RobotEnv};
use gymfleet_import::mjcf_to_document;

const PENDULUM: &str = r#"<body><joint type="hinge" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.1" size="0.01"/></body>"#;

/// The converted document's `simulation.integrator` and its warnings, for `<option>`'s
/// attributes `option` (no `<option>` at all when `None`).
fn integrator(option: Option<&str>) -> (serde_json::Value, Vec<String>) {
    let option = option.map_or(String::new(), |a| format!("<option {a}/>"));
    let converted = mjcf_to_document(&format!(
        "<mujoco>\n{option}\n<worldbody>\n{PENDULUM}\n</worldbody>\n</mujoco>"
    ))
    .expect("converts");
    let assembly = gymfleet_assembly::parse(&converted.document.to_string()).expect("parses");
    let value = converted.document["simulation"]["integrator"].clone();
    let expected = match value.as_str() {
        Some("euler") => Integrator::Euler,
        Some("implicit") => Integrator::Implicit,
        other => panic!("no integrator in the document: {other:?}"),
    };
    assert_eq!(assembly.integrator, expected);
    (value, converted.warnings)
}

#[test]
fn option_integrator_becomes_the_documents_integrator() {
    // MuJoCo's default is Euler, with or without an <option>.
    for option in [
        None,
        Some(r#"timestep="0.01""#),
        Some(r#"integrator="Euler""#),
    ] {
        let (value, warnings) = integrator(option);
        assert_eq!(value, "euler", "{option:?}");
        assert!(warnings.is_empty(), "{option:?}: {warnings:?}");
    }
    for option in [r#"integrator="implicit""#, r#"integrator="implicitfast""#] {
        let (value, warnings) = integrator(Some(option));
        assert_eq!(value, "implicit", "{option}");
        assert!(warnings.is_empty(), "{option}: {warnings:?}");
    }
    let (value, warnings) = integrator(Some(r#"integrator="RK4""#));
    assert_eq!(value, "implicit");
    assert_eq!(
        warnings,
        ["line 2: <option> integrator=\"RK4\" integrates as \"implicit\" (no RK4 here)"]
    );
    assert_eq!(
        error("<mujoco>\n<option integrator=\"rk45\"/>\n<worldbody/></mujoco>"),
        "line 2: <option integrator=…>: expected Euler, RK4, implicit or implicitfast, got \"rk45\""
    );
    let long = "x".repeat(5000);
    let message = error(&format!(
        "<mujoco><option integrator=\"{long}\"/><worldbody/></mujoco>"
    ));
    assert!(message.len() < 200, "unbounded: {} bytes", message.len());
}

#[test]
fn a_document_names_its_integrator_or_gets_the_implicit_one() {
    let document = |simulation: &str| {
        format!(
            r#"{{"parts": [{{"name": "p", "primitive": {{"type": "sphere", "radius": 10}}}}],
                "assembly": {{"instances": [{{"name": "a", "part": "p"}}]}},
                "simulation": {simulation}}}"#
        )
    };
    let parsed = |simulation: &str| gymfleet_assembly::parse(&document(simulation));
    assert_eq!(
        parsed("{}").expect("parses").integrator,
        Integrator::Implicit
    );
    assert_eq!(
        parsed(r#"{"integrator": "implicit"}"#)
            .expect("parses")
            .integrator,
        Integrator::Implicit
    );
    assert_eq!(
        parsed(r#"{"integrator": "euler"}"#)
            .expect("parses")
            .integrator,
        Integrator::Euler
    );
    let message = parsed(r#"{"integrator": "RK4"}"#)
        .expect_err("rejects")
        .to_string();
    assert!(
        message.contains("unknown variant `RK4`, expected `implicit` or `euler`"),
        "{message}"
    );
}

#[test]
fn option_gravity_and_timestep_become_the_documents_simulation() {
    let converted = mjcf_to_document(
        "<mujoco><option gravity=\"0 0 -1.5\" timestep=\"0.002\"/><worldbody>\
         <body><joint type=\"hinge\" axis=\"0 1 0\"/><geom type=\"capsule\" fromto=\"0 0 0 0 0 -0.1\" size=\"0.01\"/></body>\
         </worldbody></mujoco>",
    )
    .expect("converts");
    assert_eq!(
        converted.document["simulation"],
        serde_json::json!({"gravity": {"x": 0.0, "y": 0.0, "z": -1.5}, "dt": 0.002, "integrator": "euler"})
    );
    let assembly = gymfleet_assembly::parse(&converted.document.to_string()).expect("parses");
    assert_eq!(assembly.gravity, [0.0, 0.0, -1.5]);
    let env = RobotEnv::new(&assembly, EnvConfig::default()).expect("builds");
    assert_eq!(env.spec().dt, 0.002);
    let asked = RobotEnv::new(
        &assembly,
        EnvConfig {
            dt: 0.01,
            ..EnvConfig::default()
        },
    )
    .expect("builds");
    assert_eq!(asked.spec().dt, 0.01, "the request's dt wins");
}

#[test]
fn option_density_and_viscosity_become_the_documents_fluid() {
    let converted = mjcf_to_document(
        "<mujoco><option density=\"4000\" viscosity=\"0.1\" wind=\"0 0 0\"/><worldbody>\
         <body><joint type=\"hinge\" axis=\"0 1 0\"/><geom type=\"capsule\" fromto=\"0 0 0 0 0 -0.1\" size=\"0.01\"/></body>\
         </worldbody></mujoco>",
    )
    .expect("converts");
    assert_eq!(
        converted.document["simulation"],
        serde_json::json!({"fluid": {"density": 4000.0, "viscosity": 0.1}, "integrator": "euler"})
    );
    let assembly = gymfleet_assembly::parse(&converted.document.to_string()).expect("parses");
    assert_eq!(
        assembly.fluid,
        Some(gymfleet_assembly::Fluid {
            density: 4000.0,
            viscosity: 0.1
        })
    );
    assert_eq!(
        error("<mujoco>\n<option wind=\"1 0 0\"/>\n<worldbody/></mujoco>"),
        "line 2: <option>: wind is not supported yet"
    );
    assert_eq!(
        error("<mujoco>\n<option viscosity=\"-1\"/>\n<worldbody/></mujoco>"),
        "line 2: <option viscosity=…>: expected a number ≥ 0, got -1"
    );
    assert_eq!(
        error(&model(r#"<body><joint type="hinge"/><geom size=".1" fluidshape="ellipsoid"/></body>"#)),
        "line 4: <geom>: fluidshape=\"ellipsoid\" (MuJoCo's ellipsoid fluid model) is not supported yet; the inertia-box model of <option density viscosity> is"
    );
}

/// A double pendulum released level swings through large coriolis forces: with MuJoCo's
/// Euler the trees apply them explicitly (vendored Rapier patch 26), with RK4 (here the
/// implicit form) they enter each substep's matrix. The two integrate the same equations,
/// so they stay close over half a second, and they differ, so the integrator reaches the
/// trees.
#[test]
fn the_integrator_reaches_the_joint_trees() {
    let swing = |integrator: &str| {
        let xml = format!(
            "<mujoco><option timestep=\"0.002\" integrator=\"{integrator}\"/><worldbody>\
             <body><joint type=\"hinge\" axis=\"0 1 0\"/>\
             <geom type=\"capsule\" fromto=\"0 0 0 0.2 0 0\" size=\"0.02\"/>\
             <body pos=\"0.2 0 0\"><joint type=\"hinge\" axis=\"0 1 0\"/>\
             <geom type=\"capsule\" fromto=\"0 0 0 0.2 0 0\" size=\"0.02\"/></body></body>\
             </worldbody></mujoco>"
        );
        let converted = mjcf_to_document(&xml).expect("converts");
        let mut env = RobotEnv::from_json(&converted.document.to_string(), EnvConfig::default())
            .expect("builds");
        (0..250)
            .map(|_| {
                env.step(gymfleet_env::ActionType::Torque, &[])
                    .expect("steps")
                    .observation
                    .joint_positions
            })
            .collect::<Vec<_>>()
    };
    let (euler, implicit) = (swing("Euler"), swing("RK4"));
    let mut largest = 0.0f32;
    for (e, i) in euler.iter().zip(&implicit) {
        for (a, b) in e.iter().zip(i) {
            assert!(a.is_finite() && b.is_finite());
            largest = largest.max((a - b).abs());
        }
    }
    let swung = euler.last().expect("stepped")[0].abs();
    assert!(swung > 30.0, "the pendulum hardly moved: {swung}°");
    assert!(largest > 1e-4, "the two integrators step alike: {largest}°");
    assert!(largest < 2.0, "the two integrators part by {largest}°");
}
