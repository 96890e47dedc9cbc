//! A material's `soft_contact` (MuJoCo's compliant contact, vendored Rapier patch 43) in an
//! assembly document, against the closed form of MuJoCo's model: at rest a row's
//! acceleration `d·a_ref + (1 − d)·a₀` is zero, so with a flat impedance `d` (`dmin = dmax`)
//! a body sinks `s·(1 − d)·g·timeconst²·dampratio²` deep, `s` the cone's normal scale (1
//! elliptic; `μ²·(1 + μ²)/2` for the pyramid at friction `μ`). The ball is a free body: its
//! contacts take the generic solver path that patch 43 routes compliant contacts to.
//! MJCF's compliant contacts are checked against MuJoCo itself in
//! `client/python/tests/test_soft_contacts.py`.

mod common;

use common::*;
use gymfleet_env::ActionType;
use serde_json::{json, Value};

const G: f64 = 9.81;
const TIMECONST: f64 = 0.02;
const IMPEDANCE: f64 = 0.9;

/// A 50 mm ball resting on a plane, both of `material`.
fn ball_on_plane(material: Value) -> Value {
    json!({
        "parts": [
            {"name": "Ground", "primitive": {"type": "plane"}, "material": "soft"},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": 50}, "material": "soft"}
        ],
        "materials": {"soft": material},
        "assembly": {"instances": [
            {"part": "Ground", "name": "ground"},
            {"part": "Ball", "name": "ball", "position": {"x": 0, "y": 0, "z": 50}}
        ]}
    })
}

/// The ball's depth below touching, mm, after 2 s.
fn depth(material: Value) -> f64 {
    let mut env = env(&ball_on_plane(material), &["ball"]);
    for _ in 0..480 {
        step(&mut env, ActionType::Torque, &[]);
    }
    assert_eq!(env.spec().free_bodies, ["ball"]);
    50.0 - f64::from(env.observe().free_body_poses[2])
}

fn soft(cone: &str, friction: f64) -> Value {
    json!({
        "friction": friction,
        "soft_contact": {
            "solref": [TIMECONST, 1.0],
            "solimp": [IMPEDANCE, IMPEDANCE, 1.0, 0.5, 2.0],
            "cone": cone
        }
    })
}

#[test]
fn a_ball_sinks_as_mujocos_model_says() {
    let closed_form = (1.0 - IMPEDANCE) * G * TIMECONST * TIMECONST * 1000.0;
    let elliptic = depth(soft("elliptic", 0.5));
    assert!(
        (elliptic - closed_form).abs() < 0.01 * closed_form,
        "elliptic: {elliptic} mm deep, MuJoCo's model {closed_form} mm"
    );
    // The pyramid at friction 0.5 is stiffer along the normal by μ²·(1 + μ²)/2.
    let scale = 0.25 * 1.25 / 2.0;
    let pyramidal = depth(soft("pyramidal", 0.5));
    assert!(
        (pyramidal - scale * closed_form).abs() < 0.01 * scale * closed_form,
        "pyramidal: {pyramidal} mm deep, MuJoCo's model {} mm",
        scale * closed_form
    );
}

#[test]
fn without_soft_contact_a_material_stays_rigid() {
    let rigid = depth(json!({"friction": 0.5}));
    assert!(rigid.abs() < 0.01, "{rigid} mm");
}
