//! Each actuated DOF's action-space bound (`JointDof::action_bound`): `max_effort / |gear|`
//! where the document sets a clamp, else twice the effort that holds the joint's subtree
//! against gravity, and at least what gives the DOF's apparent inertia 10 rad/s² or m/s².

mod common;

use common::{arm_mass_and_pivot_inertia, env, hanging_pendulum, merge, slider, ARM2, G};
use gymfleet_physics::{FALLBACK_ACCELERATION, GRAVITY_MULTIPLE};
use serde_json::{json, Value};

fn bounds(doc: &Value) -> Vec<f64> {
    env(doc, &[])
        .spec()
        .dofs
        .iter()
        .map(|d| d.action_bound)
        .collect()
}

#[test]
fn a_hinge_across_gravity_may_push_twice_its_holding_torque() {
    // The arm hangs from a horizontal axis: held level, gravity's torque is m·g·d.
    let (m, i_pivot, d) = arm_mass_and_pivot_inertia();
    let hold = m * G * d;
    assert!(GRAVITY_MULTIPLE * hold > i_pivot * FALLBACK_ACCELERATION);
    let bound = bounds(&hanging_pendulum(json!({})))[0];
    assert!(
        (bound - 2.0 * hold).abs() < 1e-6 * hold,
        "{bound} vs {}",
        2.0 * hold
    );
    // The seed pendulum (the same arm standing up) gets the same bound: it is the largest
    // torque over the joint's turn, not the torque at the document's pose (zero there).
    let seed: Value = serde_json::from_str(common::PENDULUM).unwrap();
    assert!((bounds(&seed)[0] - bound).abs() < 1e-6 * bound);
}

#[test]
fn a_clamp_or_a_gear_sets_the_bound() {
    let clamped = bounds(&hanging_pendulum(json!({"max_effort": 0.5})))[0];
    assert_eq!(clamped, 0.5);
    let geared = bounds(&hanging_pendulum(json!({"max_effort": 0.5, "gear": -4.0})))[0];
    assert_eq!(geared, 0.125);
    // A gear without a clamp divides the derived effort too.
    let (m, _, d) = arm_mass_and_pivot_inertia();
    let derived = bounds(&hanging_pendulum(json!({"gear": 10.0})))[0];
    assert!((derived - 2.0 * m * G * d / 10.0).abs() < 1e-9);
}

#[test]
fn an_axis_that_gravity_does_not_load_falls_back_to_its_inertia() {
    // The same arm on a vertical axis through its top: gravity never turns it.
    let bound = bounds(&hanging_pendulum(json!({"axis": {"x": 0, "y": 0, "z": 1}})))[0];
    // The arm turns about its own long axis: I = m·(a² + a²)/12 with a = 4 mm.
    let (m, _, _) = arm_mass_and_pivot_inertia();
    let i_axis = m * (0.004f64.powi(2) * 2.0) / 12.0;
    assert!(
        (bound - i_axis * FALLBACK_ACCELERATION).abs() < 1e-3 * bound,
        "{bound}"
    );
    // Zero gravity: the hanging arm too.
    let mut level = hanging_pendulum(json!({}));
    merge(
        &mut level,
        json!({"simulation": {"gravity": {"x": 0, "y": 0, "z": 0}}}),
    );
    let (_, i_pivot, _) = arm_mass_and_pivot_inertia();
    let bound = bounds(&level)[0];
    assert!(
        (bound - i_pivot * FALLBACK_ACCELERATION).abs() < 1e-3 * bound,
        "{bound}"
    );
}

#[test]
fn a_slide_is_bounded_by_the_weight_along_it_or_its_mass() {
    // A horizontal slide: gravity gives nothing along it; m·10 m/s².
    let m = 1e-3;
    let bound = bounds(&slider(json!({})))[0];
    assert!(
        (bound - m * FALLBACK_ACCELERATION).abs() < 1e-6 * bound,
        "{bound}"
    );
    // A vertical one holds the block's weight.
    let vertical = bounds(&slider(json!({"axis": {"x": 0, "y": 0, "z": 1}})))[0];
    assert!(
        (vertical - 2.0 * m * G).abs() < 1e-6 * vertical,
        "{vertical}"
    );
}

#[test]
fn every_seed_joint_gets_a_finite_positive_bound_that_grows_towards_the_base() {
    let arm2: Value = serde_json::from_str(ARM2).unwrap();
    let b = bounds(&arm2);
    assert_eq!(b.len(), 2);
    assert!(b.iter().all(|x| x.is_finite() && *x > 0.0), "{b:?}");
    // The shoulder holds the whole arm, the elbow the forearm only.
    assert!(b[0] > b[1], "{b:?}");
    for name in ["arm6", "chain20"] {
        let path = format!("{}/../../models/{name}.json", env!("CARGO_MANIFEST_DIR"));
        let doc: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let b = bounds(&doc);
        eprintln!("{name}: {b:?}");
        assert!(b.iter().all(|x| x.is_finite() && *x > 0.0), "{name}: {b:?}");
    }
}
