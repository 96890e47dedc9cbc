//! Default PD gains that account for what a joint drives (issue F): a velocity-driven crank
//! of a CAD-scale crank-rocker turns at its commanded rate, where gains from the crank's own
//! subtree let gravity stall it.

mod common;

use common::{env_with, wrap_deg};
use gymfleet_env::{ActionType, EnvConfig};
use serde_json::{json, Value};

/// Link lengths (mm): crank, coupler, rocker, ground (a Grashof crank-rocker).
const CRANK: f64 = 20.0;
const COUPLER: f64 = 60.0;
const ROCKER: f64 = 50.0;
const GROUND: f64 = 60.0;
/// The pivots' height (mm): 100 mm above the 5 mm base.
const PIVOT_Z: f64 = 105.0;
/// The crank's pivot O2 (x, mm); the rocker's O4 is `GROUND` further along x.
const O2_X: f64 = 30.0;

/// The coupler–rocker pin B (x, z in mm) at crank angle `theta` (rad, from +x towards +z):
/// the crossing of the coupler's circle about the crank pin and the rocker's about O4, on
/// the upper branch.
fn pin_b(theta: f64) -> [f64; 2] {
    let a = [O2_X + CRANK * theta.cos(), PIVOT_Z + CRANK * theta.sin()];
    let o4 = [O2_X + GROUND, PIVOT_Z];
    let (dx, dz) = (o4[0] - a[0], o4[1] - a[1]);
    let dist = (dx * dx + dz * dz).sqrt();
    let along = (COUPLER * COUPLER - ROCKER * ROCKER + dist * dist) / (2.0 * dist);
    let across = (COUPLER * COUPLER - along * along).sqrt();
    let (ux, uz) = (dx / dist, dz / dist);
    [
        a[0] + along * ux - across * uz,
        a[1] + along * uz + across * ux,
    ]
}

/// A rod (a 2 mm-radius cylinder, density 1000) of `part` from `from` to `to` (x, z in mm)
/// at depth `y`: the cylinder's local Z turned onto the link.
fn rod(part: &str, name: &str, from: [f64; 2], to: [f64; 2], y: f64) -> Value {
    let heading = (to[1] - from[1]).atan2(to[0] - from[0]).to_degrees();
    json!({"part": part, "name": name,
           "position": {"x": from[0], "y": y, "z": from[1]},
           "rotation": {"x": 0, "y": 90.0 - heading, "z": 0}})
}

fn pin(name: &str, parent: &str, child: &str, at: [f64; 2], actuated: bool) -> Value {
    json!({"name": name, "type": "revolute", "parent": parent, "child": child,
           "anchor": {"x": at[0], "y": 0, "z": at[1]}, "axis": {"x": 0, "y": -1, "z": 0},
           "actuated": actuated})
}

/// Issue F's four-bar: a 120 × 30 × 5 mm base, the crank driven, the rods offset in y so that
/// they do not touch, the loop closed by a named coupler–rocker joint. The crank starts
/// straight up.
fn crank_rocker() -> Value {
    let theta = 90f64.to_radians();
    let o2 = [O2_X, PIVOT_Z];
    let o4 = [O2_X + GROUND, PIVOT_Z];
    let a = [O2_X + CRANK * theta.cos(), PIVOT_Z + CRANK * theta.sin()];
    let b = pin_b(theta);
    let cylinder = |name: &str, length: f64| json!({"name": name, "primitive": {"type": "cylinder", "radius": 2, "height": length}});
    json!({
        "parts": [
            {"name": "Base", "primitive": {"type": "cube", "size": {"x": 120, "y": 30, "z": 5}}},
            cylinder("Crank", CRANK), cylinder("Coupler", COUPLER), cylinder("Rocker", ROCKER)
        ],
        "assembly": {
            "instances": [
                {"part": "Base", "name": "base"},
                rod("Crank", "crank", o2, a, 25.0),
                rod("Coupler", "coupler", a, b, 20.0),
                rod("Rocker", "rocker", o4, b, 15.0)
            ],
            "joints": [
                pin("crank", "base", "crank", o2, true),
                pin("elbow", "crank", "coupler", a, false),
                pin("rocker", "base", "rocker", o4, false),
                pin("closer", "coupler", "rocker", b, false)
            ]
        }
    })
}

/// Issue F's bar: driven with velocity actions of −120 °/s and the default gains, the crank
/// turns at the commanded rate within 5 % over 3 s (it turned 220° and stalled at 2 °/s when
/// its gains came from its own subtree: the 2 mm rods' weight, carried through the loop,
/// outweighed a damping gain sized for the crank's inertia at 20 Hz).
#[test]
fn a_velocity_driven_crank_turns_at_its_commanded_rate_with_default_gains() {
    let mut env = env_with(&crank_rocker(), EnvConfig::default());
    let dt = env.spec().dt;
    let steps = (3.0 / dt).round() as usize;
    let mut previous = f64::from(env.observe().joint_positions[0]);
    let (mut turned, mut slowest) = (0.0, f64::MAX);
    for _ in 0..steps {
        let q = f64::from(
            env.step(ActionType::Velocity, &[-120.0])
                .expect("steps")
                .observation
                .joint_positions[0],
        );
        let d = wrap_deg(q - previous);
        slowest = slowest.min(-d / dt);
        turned += d;
        previous = q;
    }
    let rate = -turned / (steps as f64 * dt);
    println!(
        "turned {turned:.1}° in 3 s: {rate:.2} °/s on average, {slowest:.1} °/s at the slowest"
    );
    assert!(
        (rate - 120.0).abs() <= 0.05 * 120.0,
        "the crank turned at {rate:.2} °/s on average (commanded 120 °/s; slowest {slowest:.1} °/s)"
    );
}

/// Given gains drive velocity targets with `kd` alone (`pd_gains.kd`), not with the raised
/// default velocity gain: with a `kd` of 1e-6 N·m·s/rad the same crank is far from its
/// commanded rate (gravity and the loop outweigh the servo).
#[test]
fn a_given_kd_drives_velocity_targets_instead_of_the_default_gain() {
    let probe = env_with(&crank_rocker(), EnvConfig::default());
    let n = probe.spec().num_dofs;
    let config = EnvConfig {
        pd_gains: Some(gymfleet_env::PdGains {
            kp: Vec::new(),
            kd: vec![1e-6; n],
        }),
        ..EnvConfig::default()
    };
    let mut env = env_with(&crank_rocker(), config);
    let dt = env.spec().dt;
    let steps = (1.0 / dt).round() as usize;
    let mut previous = f64::from(env.observe().joint_positions[0]);
    let mut turned = 0.0;
    for _ in 0..steps {
        let q = f64::from(
            env.step(ActionType::Velocity, &[-120.0])
                .expect("steps")
                .observation
                .joint_positions[0],
        );
        turned += wrap_deg(q - previous);
        previous = q;
    }
    let rate = -turned / (steps as f64 * dt);
    println!("with kd = 1e-6 the crank turned at {rate:.2} °/s on average over 1 s");
    assert!(
        (rate - 120.0).abs() > 60.0,
        "a given kd of 1e-6 turned the crank at {rate:.2} °/s: the default velocity gain was used"
    );
}
