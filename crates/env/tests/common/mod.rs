//! Documents and helpers shared by the physics tests.
#![allow(dead_code, unreachable_pub)]

use gymfleet_env::{ActionType, EnvConfig, EnvError, RobotEnv, TaskKind, TaskSpec, TermsTask};
use serde_json::{json, Value};

pub const PENDULUM: &str = include_str!("../../../../models/pendulum.json");
pub const ARM2: &str = include_str!("../../../../models/arm2.json");

pub const G: f64 = 9.81;

/// A grounded base and one 4×4×40 mm arm hanging straight down from a revolute joint
/// about +Y at its top centre (10, 10, 0).
pub fn hanging_pendulum(joint_extra: Value) -> Value {
    let mut joint = json!({
        "type": "revolute", "parent": "base", "child": "arm",
        "anchor": {"x": 10, "y": 10, "z": 0}, "axis": {"x": 0, "y": 1, "z": 0}
    });
    merge(&mut joint, joint_extra);
    json!({
        "parts": [
            {"name": "Base", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 5}}},
            {"name": "Arm", "primitive": {"type": "cube", "size": {"x": 4, "y": 4, "z": 40}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Base", "name": "base"},
                {"part": "Arm", "name": "arm", "position": {"x": 8, "y": 8, "z": -40}}
            ],
            "joints": [joint]
        }
    })
}

/// A 10×10×10 mm block (m = 1e-3 kg) sliding along +X on a grounded base.
pub fn slider(joint_extra: serde_json::Value) -> serde_json::Value {
    let mut joint = json!({"type": "prismatic", "parent": "base", "child": "block",
                           "anchor": {"x": 5, "y": 10, "z": 10}, "axis": {"x": 1, "y": 0, "z": 0}});
    merge(&mut joint, joint_extra);
    json!({
        "parts": [
            {"name": "Base", "primitive": {"type": "cube", "size": {"x": 100, "y": 20, "z": 5}}},
            {"name": "Block", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Base", "name": "base"},
                {"part": "Block", "name": "block", "position": {"x": 0, "y": 5, "z": 5}}
            ],
            "joints": [joint]
        }
    })
}

/// A floating 100×100×20 mm slab (its frame a corner) with an arm hinged on top, limited to
/// [-60°, 60°].
pub fn slab_with_arm() -> Value {
    json!({
        "floating_base": true,
        "parts": [
            {"name": "Slab", "primitive": {"type": "cube", "size": {"x": 100, "y": 100, "z": 20}}},
            {"name": "Arm", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 200}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Slab", "name": "base", "position": {"x": 0, "y": 0, "z": 500}},
                {"part": "Arm", "name": "arm", "position": {"x": 40, "y": 40, "z": 520}}
            ],
            "joints": [
                {"type": "revolute", "name": "hinge", "parent": "base", "child": "arm",
                 "anchor": {"x": 50, "y": 50, "z": 520}, "axis": {"x": 1, "y": 0, "z": 0},
                 "min": -60, "max": 60}
            ]
        }
    })
}

/// Merges the fields of `extra` (an object) into `target`.
pub fn merge(target: &mut Value, extra: Value) {
    if let (Some(t), Value::Object(e)) = (target.as_object_mut(), extra) {
        t.extend(e);
    }
}

pub fn env(doc: &Value, ee: &[&str]) -> RobotEnv {
    env_with(doc, EnvConfig::with_end_effectors(ee.iter().copied()))
}

/// Asserts that `doc` is refused with a message containing `expected`.
pub fn assert_refused(doc: &Value, expected: &str) {
    let message = RobotEnv::from_json(&doc.to_string(), EnvConfig::default())
        .err()
        .expect("refused")
        .to_string();
    assert!(
        message.contains(expected),
        "{message}\nexpected: {expected}"
    );
}

/// An env of `doc` with the terms task `task` (JSON) and `config`'s other options: the
/// task's own error (its shape, when parsed), else the build's (its names, against the
/// document).
pub fn with_terms(doc: &str, task: &str, config: EnvConfig) -> Result<RobotEnv, EnvError> {
    let terms = TermsTask::from_json(task)?;
    let config = EnvConfig {
        task: Some(TaskSpec {
            kind: TaskKind::Terms(terms),
            action_cost: 0.0,
        }),
        ..config
    };
    RobotEnv::from_json(doc, config)
}

pub fn env_with(doc: &Value, config: EnvConfig) -> RobotEnv {
    RobotEnv::from_json(&doc.to_string(), config).expect("valid test document")
}

pub fn step(env: &mut RobotEnv, action_type: ActionType, values: &[f32]) -> Vec<f32> {
    let result = env.step(action_type, values).expect("valid action");
    assert!(!result.flags.terminated, "unexpected termination");
    result.observation.to_flat()
}

/// Mass (kg) and inertia about the pivot (kg·m²) of the 4×4×40 mm arm at 1000 kg/m³,
/// rotating about Y through the centre of one 4×4 end face.
pub fn arm_mass_and_pivot_inertia() -> (f64, f64, f64) {
    let (a, c) = (0.004, 0.040);
    let m = 1000.0 * a * a * c;
    let d = c / 2.0;
    let i_pivot = m * (a * a + c * c) / 12.0 + m * d * d;
    (m, i_pivot, d)
}

/// A post welded to the base, an arm welded on top of it, and a hand hinged (about Y) at the
/// arm's far end, hanging 37 mm from the post. The hand and the post are links of one chain
/// that no joint connects, so they collide: driven towards the post, the hand stops on it.
pub fn hand_and_post() -> Value {
    json!({
        "parts": [
            {"name": "Base", "primitive": {"type": "cube", "size": {"x": 100, "y": 10, "z": 5}}},
            {"name": "Post", "primitive": {"type": "cube", "size": {"x": 6, "y": 6, "z": 50}}},
            {"name": "Arm", "primitive": {"type": "cube", "size": {"x": 40, "y": 6, "z": 4}}},
            {"name": "Hand", "primitive": {"type": "cube", "size": {"x": 4, "y": 4, "z": 42}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Base", "name": "base"},
                {"part": "Post", "name": "post", "position": {"x": 47, "y": 2, "z": 5}},
                {"part": "Arm", "name": "arm", "position": {"x": 50, "y": 2, "z": 55}},
                {"part": "Hand", "name": "hand", "position": {"x": 88, "y": 3, "z": 15}}
            ],
            "joints": [
                {"type": "fixed", "parent": "base", "child": "post", "anchor": {"x": 50, "y": 5, "z": 5}},
                {"type": "fixed", "parent": "post", "child": "arm", "anchor": {"x": 50, "y": 5, "z": 55}},
                {"type": "revolute", "parent": "arm", "child": "hand",
                 "anchor": {"x": 90, "y": 5, "z": 57}, "axis": {"x": 0, "y": 1, "z": 0}}
            ]
        }
    })
}

/// The difference of two angles in deg, wrapped into (−180, 180].
pub fn wrap_deg(d: f64) -> f64 {
    let d = d.rem_euclid(360.0);
    if d > 180.0 {
        d - 360.0
    } else {
        d
    }
}

/// The turntables' sphere radius, m.
pub const TURNTABLE_R: f64 = 0.05;

/// A turntable sphere's moment of inertia about a diameter (radius [`TURNTABLE_R`],
/// 1000 kg/m³), kg·m².
pub fn turntable_inertia() -> f64 {
    let r = TURNTABLE_R;
    let m = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * 1000.0;
    0.4 * m * r * r
}

/// Two spheres, each on a vertical hinge through its centre (`a`, `b`; `a` starts at
/// `initial_a` degrees), without gravity; `assembly` adds fields to the assembly (tendons,
/// couplings).
pub fn turntables(initial_a: f64, assembly: Value) -> Value {
    let mut doc = json!({
        "simulation": {"gravity": {"x": 0, "y": 0, "z": 0}},
        "parts": [
            {"name": "Post", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": TURNTABLE_R * 1000.0}}
        ],
        "assembly": {
            "instances": [
                {"part": "Post", "name": "post", "position": {"x": -5, "y": -5, "z": -200}},
                {"part": "Ball", "name": "ball_a", "position": {"x": 0, "y": 0, "z": 0}},
                {"part": "Ball", "name": "ball_b", "position": {"x": 200, "y": 0, "z": 0}}
            ],
            "joints": [
                {"type": "revolute", "name": "a", "parent": "post", "child": "ball_a", "initial": initial_a,
                 "anchor": {"x": 0, "y": 0, "z": 0}, "axis": {"x": 0, "y": 0, "z": 1}},
                {"type": "revolute", "name": "b", "parent": "post", "child": "ball_b",
                 "anchor": {"x": 200, "y": 0, "z": 0}, "axis": {"x": 0, "y": 0, "z": 1}}
            ]
        }
    });
    merge(&mut doc["assembly"], assembly);
    doc
}
