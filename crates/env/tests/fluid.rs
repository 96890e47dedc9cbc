//! A fluid around the bodies (`simulation.fluid`, MJCF's `<option density viscosity>`):
//! MuJoCo's inertia-box drag, checked against closed forms. A solid sphere of radius r is
//! the box with edges √2.4·r; its terminal velocities and spin rates follow from Stokes'
//! drag (viscosity) and the quadratic face drag (density) of that box.

mod common;

use std::f64::consts::PI;

use common::*;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, Units};
use serde_json::{json, Value};

const G: f64 = 9.81;
/// Sphere radius, m, and its mass at 1000 kg/m³, kg.
const R: f64 = 0.05;
fn sphere_mass() -> f64 {
    4.0 / 3.0 * PI * R.powi(3) * 1000.0
}
/// The equivalent box's edge of a solid sphere: √((I + I − I)/m · 6) with I = 2/5·m·r².
fn sphere_box_edge() -> f64 {
    (2.4f64).sqrt() * R
}

/// A free sphere (the floating base) falling from 10 m in the fluid.
fn falling(fluid: Value, welded_twin: bool) -> Value {
    let mut instances =
        vec![json!({"part": "Ball", "name": "ball", "position": {"x": 0, "y": 0, "z": 10000}})];
    let mut joints = vec![];
    if welded_twin {
        instances.push(
            json!({"part": "Ball", "name": "twin", "position": {"x": 100, "y": 0, "z": 10000}}),
        );
        joints.push(json!({"type": "fixed", "name": "weld", "parent": "ball", "child": "twin"}));
    }
    json!({
        "floating_base": true,
        "simulation": {"fluid": fluid},
        "parts": [{"name": "Ball", "primitive": {"type": "sphere", "radius": R * 1000.0}}],
        "assembly": {"instances": instances, "joints": joints}
    })
}

fn si(doc: &Value, substeps: u32) -> RobotEnv {
    env_with(
        doc,
        EnvConfig {
            dt: 0.01,
            substeps,
            max_steps: 100_000,
            units: Units::Si,
            ..EnvConfig::default()
        },
    )
}

/// The base's vertical velocity (m/s) after `seconds` of falling.
fn fall_speed(doc: &Value, seconds: f64) -> f64 {
    let mut env = si(doc, 10);
    for _ in 0..(seconds / 0.01).round() as usize {
        env.step(ActionType::Torque, &[]).expect("steps");
    }
    -f64::from(env.observe().base_velocity[2])
}

#[test]
fn viscosity_gives_stokes_terminal_velocity_and_time_constant() {
    let mu = 10.0;
    let doc = falling(json!({"viscosity": mu}), false);
    let drag = 3.0 * PI * sphere_box_edge() * mu; // N per m/s
    let terminal = sphere_mass() * G / drag;
    let tau = sphere_mass() / drag;
    let v = fall_speed(&doc, 3.0);
    assert!(
        (v / terminal - 1.0).abs() < 1e-3,
        "terminal {v} m/s, Stokes {terminal} m/s"
    );
    // On the way: v(t) = v∞·(1 − e^(−t/τ)) at t ≈ τ (to the nearest step).
    let t = (tau / 0.01).round() * 0.01;
    let expected = terminal * (1.0 - (-t / tau).exp());
    let v = fall_speed(&doc, t);
    assert!(
        (v / expected - 1.0).abs() < 0.01,
        "after {t} s: {v} m/s, expected {expected} m/s"
    );
}

#[test]
fn density_gives_quadratic_drag_on_the_boxs_face() {
    let rho = 1000.0;
    let b = sphere_box_edge();
    let terminal = (2.0 * sphere_mass() * G / (rho * b * b)).sqrt();
    let v = fall_speed(&falling(json!({"density": rho}), false), 4.0);
    assert!(
        (v / terminal - 1.0).abs() < 1e-3,
        "terminal {v} m/s, expected {terminal} m/s"
    );
}

#[test]
fn welded_instances_are_one_body_in_the_fluid() {
    // Two spheres 100 mm apart along X: Ixx = 0.8·m·r², Iyy = Izz = 2.8·m·r² (m each).
    let mu = 10.0;
    let edges = [14.4f64.sqrt() * R, 2.4f64.sqrt() * R, 2.4f64.sqrt() * R];
    let d = edges.iter().sum::<f64>() / 3.0;
    let terminal = 2.0 * sphere_mass() * G / (3.0 * PI * d * mu);
    let v = fall_speed(&falling(json!({"viscosity": mu}), true), 3.0);
    assert!(
        (v / terminal - 1.0).abs() < 1e-3,
        "terminal {v} m/s, expected {terminal} m/s (two separate spheres would fall at {})",
        sphere_mass() * G / (3.0 * PI * sphere_box_edge() * mu)
    );
}

/// A sphere on a vertical hinge through its centre, driven by a constant torque (N·m):
/// the spin rate (rad/s) after 5 s in the fluid.
fn spin_rate(fluid: Value, torque: f32) -> f64 {
    let doc = json!({
        "simulation": {"fluid": fluid, "gravity": {"x": 0, "y": 0, "z": 0}},
        "parts": [
            {"name": "Post", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": R * 1000.0}}
        ],
        "assembly": {
            "instances": [
                {"part": "Post", "name": "post", "position": {"x": -5, "y": -5, "z": -200}},
                {"part": "Ball", "name": "ball", "position": {"x": 0, "y": 0, "z": 0}}
            ],
            "joints": [{"type": "revolute", "name": "spin", "parent": "post", "child": "ball",
                        "anchor": {"x": 0, "y": 0, "z": 0}, "axis": {"x": 0, "y": 0, "z": 1}}]
        }
    });
    let mut env = si(&doc, 10);
    for _ in 0..500 {
        env.step(ActionType::Torque, &[torque]).expect("steps");
    }
    f64::from(env.observe().joint_velocities[0])
}

#[test]
fn the_spin_settles_where_the_fluids_torque_balances_the_drive() {
    let b = sphere_box_edge();
    // Viscous: torque = π·d³·μ·ω, d = b for a cube.
    let mu = 1.0;
    let expected = 0.01 / (PI * b.powi(3) * mu);
    let w = spin_rate(json!({"viscosity": mu}), 0.01);
    assert!(
        (w / expected - 1.0).abs() < 1e-3,
        "viscous spin {w} rad/s, expected {expected} rad/s"
    );
    // Quadratic: torque = ρ·b·(b⁴ + b⁴)/64·ω².
    let rho = 1000.0;
    let expected = (0.01 / (rho * b.powi(5) / 32.0)).sqrt();
    let w = spin_rate(json!({"density": rho}), 0.01);
    assert!(
        (w / expected - 1.0).abs() < 1e-3,
        "quadratic spin {w} rad/s, expected {expected} rad/s"
    );
    // No fluid: the drive keeps accelerating it, ω = τ·t/I.
    let free = 0.01 * 5.0 / (0.4 * sphere_mass() * R * R);
    let w = spin_rate(json!({}), 0.01);
    assert!(
        (w / free - 1.0).abs() < 1e-3,
        "spin without a fluid {w} rad/s, expected {free} rad/s"
    );
}

#[test]
fn a_bad_fluid_is_refused_with_its_path() {
    let bad = |fluid: Value| {
        RobotEnv::from_json(&falling(fluid, false).to_string(), EnvConfig::default())
            .err()
            .expect("refused")
            .to_string()
    };
    let message = bad(json!({"density": -1.0}));
    assert!(
        message
            .contains("simulation.fluid.density: expected a density in [0, 100000] kg/m³, got -1"),
        "{message}"
    );
    let message = bad(json!({"viscosity": 1e9}));
    assert!(
        message.contains(
            "simulation.fluid.viscosity: expected a viscosity in [0, 1000] Pa·s, got 1000000000"
        ),
        "{message}"
    );
    let message = bad(json!({"wind": 1.0}));
    assert!(message.contains("unknown field `wind`"), "{message}");
}
