//! Keyframes: the document's named initial states (`assembly.keyframes`, MJCF's `<key>`),
//! which a reset starts from, the reset's noise on top (`RobotEnv::reset_to_into`).

mod common;

use common::*;
use gymfleet_env::{ActionType, EnvConfig, EnvError, RobotEnv, Units};
use serde_json::{json, Value};

/// A floating 100×100×20 mm slab (its frame a corner, its centre 50, 50, 10 mm from it)
/// with an arm hinged on top, limited to [-60°, 60°], and `keyframes`.
fn robot(keyframes: Value, initial: Option<&str>) -> Value {
    let mut doc = slab_with_arm();
    doc["assembly"]["keyframes"] = keyframes;
    if let Some(name) = initial {
        doc["assembly"]["initial_keyframe"] = json!(name);
    }
    doc
}

/// "lifted": the slab's corner at (0, 0, 800) mm, turned 90° about z, moving along x at
/// 100 mm/s and spinning about z at 90°/s; the hinge at 30°, turning at 10°/s.
fn lifted() -> Value {
    json!([
        {"name": "lifted", "positions": {"hinge": 30}, "velocities": {"hinge": 10},
         "base": {"position": {"x": 0, "y": 0, "z": 800},
                  "orientation": [std::f64::consts::FRAC_1_SQRT_2, 0, 0, std::f64::consts::FRAC_1_SQRT_2],
                  "linear_velocity": {"x": 100, "y": 0, "z": 0},
                  "angular_velocity": {"x": 0, "y": 0, "z": 90}}},
        {"name": "bent", "positions": {"hinge": -45}}
    ])
}

fn si(config: EnvConfig) -> EnvConfig {
    EnvConfig {
        units: Units::Si,
        ..config
    }
}

fn reset(env: &mut RobotEnv, seed: Option<u64>, key: Option<&str>) -> Vec<f64> {
    let mut out = vec![0.0f32; env.spec().observation_dim];
    env.reset_to_into(seed, key, &mut out)
        .expect("a keyframe of the document");
    out.iter().map(|&v| f64::from(v)).collect()
}

fn close(got: &[f64], want: &[f64], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() < tol,
            "{what}[{k}]: {g}, expected {w} (all: {got:?})"
        );
    }
}

#[test]
fn a_reset_to_a_keyframe_starts_there_and_a_plain_reset_does_not() {
    let mut env = env_with(&robot(lifted(), None), si(EnvConfig::default()));
    assert_eq!(env.keyframes(), ["lifted", "bent"]);
    assert_eq!(env.spec().keyframes, ["lifted", "bent"]);
    let obs = reset(&mut env, None, Some("lifted"));
    // SI layout: hinge position, velocity, base pose (centre, quaternion), base velocity.
    close(
        &obs[0..2],
        &[30f64.to_radians(), 10f64.to_radians()],
        1e-6,
        "hinge",
    );
    // The slab's centre, (50, 50, 10) mm from its corner, turned 90° about z.
    close(&obs[2..5], &[-0.05, 0.05, 0.81], 1e-6, "base centre");
    let h = 0.5f64.sqrt();
    close(&obs[5..9], &[h, 0.0, 0.0, h], 1e-6, "base orientation");
    // The centre's velocity: the corner's, plus ω × (centre − corner).
    let w = 90f64.to_radians();
    close(
        &obs[9..15],
        &[0.1 - w * 0.05, -w * 0.05, 0.0, 0.0, 0.0, w],
        1e-5,
        "base velocity",
    );
    let bent = reset(&mut env, None, Some("bent"));
    close(&bent[0..2], &[-45f64.to_radians(), 0.0], 1e-6, "bent hinge");
    close(
        &bent[2..5],
        &[0.05, 0.05, 0.51],
        1e-6,
        "bent leaves the base",
    );
    let plain = reset(&mut env, None, None);
    close(
        &plain[0..9],
        &[0.0, 0.0, 0.05, 0.05, 0.51, 1.0, 0.0, 0.0, 0.0],
        1e-6,
        "plain",
    );
}

#[test]
fn the_initial_keyframe_starts_every_reset_and_the_first() {
    let mut env = env_with(&robot(lifted(), Some("bent")), si(EnvConfig::default()));
    let first = env.observe().to_flat();
    assert!(
        (f64::from(first[0]) + 45f64.to_radians()).abs() < 1e-6,
        "{first:?}"
    );
    let again = reset(&mut env, None, None);
    assert!((again[0] + 45f64.to_radians()).abs() < 1e-6, "{again:?}");
    let other = reset(&mut env, None, Some("lifted"));
    assert!((other[0] - 30f64.to_radians()).abs() < 1e-6, "{other:?}");
}

#[test]
fn the_reset_noise_is_drawn_on_top_of_the_keyframe() {
    let config = si(EnvConfig {
        reset_noise: 5.0,
        ..EnvConfig::default()
    });
    let mut plain = env_with(&robot(lifted(), None), config.clone());
    let mut keyed = env_with(&robot(lifted(), None), config);
    let noise = reset(&mut plain, Some(3), None);
    let start = reset(&mut keyed, Some(3), Some("bent"));
    assert!(noise[0].abs() > 1e-4, "the draw moved the hinge: {noise:?}");
    // The same draw, from -45° instead of 0.
    close(
        &[start[0] - noise[0]],
        &[-45f64.to_radians()],
        1e-6,
        "offset",
    );
    // Past the limit, the start is clamped into it: -45° - 20° stops at -60°.
    let config = si(EnvConfig {
        reset_noise: 40.0,
        ..EnvConfig::default()
    });
    let mut wide = env_with(&robot(lifted(), None), config);
    for seed in 0..20 {
        let start = reset(&mut wide, Some(seed), Some("bent"));
        assert!(
            start[0] >= -60f64.to_radians() - 1e-6,
            "seed {seed}: {start:?}"
        );
    }
}

#[test]
fn an_unknown_keyframe_is_refused_and_nothing_changes() {
    let mut env = env_with(&robot(lifted(), None), EnvConfig::default());
    reset(&mut env, None, Some("bent"));
    let before = env.observe().to_flat();
    let mut out = vec![0.0f32; env.spec().observation_dim];
    let err = env
        .reset_to_into(None, Some("home"), &mut out)
        .expect_err("no such keyframe");
    assert!(matches!(err, EnvError::UnknownKeyframe { .. }), "{err:?}");
    assert_eq!(
        err.to_string(),
        "keyframe: no keyframe is named \"home\"; the document's are \"lifted\", \"bent\""
    );
    assert_eq!(env.observe().to_flat(), before, "nothing changed");
    let mut bare = env_with(&robot(json!([]), None), EnvConfig::default());
    let err = bare
        .reset_to_into(None, Some("home"), &mut out)
        .expect_err("no keyframes at all");
    assert_eq!(
        err.to_string(),
        "keyframe: no keyframe is named \"home\"; the document has none"
    );
}

#[test]
fn a_keyframe_and_its_copy_step_the_same_bits() {
    let mut a = env_with(&robot(lifted(), None), si(EnvConfig::default()));
    let mut b = a.clone();
    reset(&mut a, Some(9), Some("lifted"));
    reset(&mut b, Some(9), Some("lifted"));
    for _ in 0..20 {
        let x = step(&mut a, gymfleet_env::ActionType::Torque, &[0.01]);
        let y = step(&mut b, gymfleet_env::ActionType::Torque, &[0.01]);
        assert_eq!(x, y);
    }
}

/// Each bad keyframe is refused at its JSON path, with what was expected.
#[test]
fn bad_keyframes_are_refused_with_their_paths() {
    let cases: Vec<(Value, Option<&str>, &str)> = vec![
        (
            json!([{"name": "k", "positions": {"elbow": 1}}]),
            None,
            "assembly.keyframes[0].positions.elbow: no joint is named \"elbow\"",
        ),
        (
            json!([{"name": "k", "velocities": {"hinge": f64::MAX}}]),
            None,
            "assembly.keyframes[0].velocities.hinge: expected a finite number within ±1e9, got 1.7976931348623157e308",
        ),
        (
            json!([{"name": "k", "base": {"position": {"x": 0, "y": 0, "z": 0},
                                          "orientation": [0, 0, 0, 0]}}]),
            None,
            "assembly.keyframes[0].base.orientation: expected a quaternion [qw, qx, qy, qz] of finite numbers, not all zero, got [0, 0, 0, 0]",
        ),
        (
            json!([{"name": "k", "free_bodies": {"arm": {"position": {"x": 0, "y": 0, "z": 0},
                                                         "orientation": [1, 0, 0, 0]}}}]),
            None,
            "assembly.keyframes[0].free_bodies.arm: no free body is named \"arm\" (the document's: none)",
        ),
        (
            json!([{"name": "k", "mocap": {"base": {"position": {"x": 0, "y": 0, "z": 0},
                                                    "orientation": [1, 0, 0, 0]}}}]),
            None,
            "assembly.keyframes[0].mocap.base: no mocap body is named \"base\" (the document's: none)",
        ),
        (
            json!([{"name": "k", "rotations": {"hinge": [1, 0, 0, 0]}}]),
            None,
            "assembly.keyframes[0].rotations.hinge: \"hinge\" is a Revolute joint; rotations and spins are a ball joint's",
        ),
        (
            json!([{"name": "k", "spins": {"elbow": {"x": 1, "y": 0, "z": 0}}}]),
            None,
            "assembly.keyframes[0].spins.elbow: no joint is named \"elbow\"",
        ),
        (
            json!([{"name": "k"}, {"name": "k"}]),
            None,
            "assembly.keyframes[1].name: \"k\" names an earlier keyframe too",
        ),
        (
            json!([{"name": "k"}]),
            Some("home"),
            "assembly.initial_keyframe: no keyframe is named \"home\"; the keyframes are \"k\"",
        ),
    ];
    for (keyframes, initial, expected) in cases {
        let doc = robot(keyframes, initial);
        let err = RobotEnv::from_json(&doc.to_string(), EnvConfig::default())
            .err()
            .expect("a bad keyframe");
        assert!(
            err.to_string().contains(expected),
            "expected {expected:?} in: {err}"
        );
    }
    // A keyframe's base needs a floating base.
    let mut grounded = robot(
        json!([{"name": "k", "base": {"position": {"x": 0, "y": 0, "z": 0},
                                      "orientation": [1, 0, 0, 0]}}]),
        None,
    );
    grounded["floating_base"] = json!(false);
    let err = RobotEnv::from_json(&grounded.to_string(), EnvConfig::default())
        .err()
        .expect("a base without a floating base");
    assert!(
        err.to_string().contains(
            "assembly.keyframes[0].base: the document has no floating base (set floating_base to true)"
        ),
        "{err}"
    );
}

/// A grounded post, a free cube and a mocap cube, and a keyframe placing both cubes.
fn scene(key: Value) -> Value {
    json!({
        "parts": [{"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}],
        "assembly": {
            "instances": [
                {"part": "Cube", "name": "post"},
                {"part": "Cube", "name": "free", "position": {"x": 500, "y": 0, "z": 500},
                 "body_frame": {"position": {"x": 10, "y": 10, "z": 10}}},
                {"part": "Cube", "name": "hand", "position": {"x": -500, "y": 0, "z": 500}, "mocap": true,
                 "body_frame": {"position": {"x": 10, "y": 10, "z": 10}}, "collision": {"group": 0, "mask": 0}}
            ],
            "joints": [],
            "keyframes": [key]
        }
    })
}

#[test]
fn a_keyframe_places_free_and_mocap_bodies() {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let key = json!({"name": "k",
        "free_bodies": {"free": {"position": {"x": 100, "y": 200, "z": 300}, "orientation": [h, 0, 0, h],
                                 "linear_velocity": {"x": 0, "y": 0, "z": 50},
                                 "angular_velocity": {"x": 90, "y": 0, "z": 0}}},
        "mocap": {"hand": {"position": {"x": -100, "y": 0, "z": 700}, "orientation": [0, 1, 0, 0]}}});
    let mut env = env_with(&scene(key), si(EnvConfig::with_end_effectors(["hand"])));
    let obs = reset(&mut env, None, Some("k"));
    // SI layout: free pose (7), free velocity (6), then the hand's pose (its centre).
    close(
        &obs[0..7],
        &[0.1, 0.2, 0.3, h, 0.0, 0.0, h],
        1e-6,
        "free pose",
    );
    close(
        &obs[7..13],
        &[0.0, 0.0, 0.05, 90f64.to_radians(), 0.0, 0.0],
        1e-5,
        "free velocity",
    );
    close(
        &obs[13..16],
        &[-0.1, 0.0, 0.7],
        1e-6,
        "the mocap cube's centre",
    );
    // It stays where the keyframe put it; a plain reset puts both back.
    for _ in 0..5 {
        env.step(ActionType::Torque, &[]).expect("steps");
    }
    close(
        &env.observe().to_flat()[13..16]
            .iter()
            .map(|&v| f64::from(v))
            .collect::<Vec<_>>(),
        &[-0.1, 0.0, 0.7],
        1e-6,
        "held",
    );
    let plain = reset(&mut env, None, None);
    close(
        &plain[0..3],
        &[0.51, 0.01, 0.51],
        1e-6,
        "the free cube back",
    );
    close(
        &plain[13..16],
        &[-0.49, 0.01, 0.51],
        1e-6,
        "the mocap cube back",
    );
    // A mocap body's keyframe is a pose only.
    let moving = json!({"name": "k", "mocap": {"hand": {"position": {"x": 0, "y": 0, "z": 0},
        "orientation": [1, 0, 0, 0], "linear_velocity": {"x": 1, "y": 0, "z": 0}}}});
    let err = RobotEnv::from_json(&scene(moving).to_string(), EnvConfig::default())
        .err()
        .expect("a moving mocap key");
    assert!(
        err.to_string()
            .contains("assembly.keyframes[0].mocap.hand: a mocap body's keyframe is a pose: give no velocities"),
        "{err}"
    );
}

#[test]
fn a_keyframe_holds_its_controls_and_activations_until_the_first_step() {
    // Two arms side by side: one a direct motor's, one an actuator's with a filter.
    let mut doc = slab_with_arm();
    doc["floating_base"] = json!(false);
    doc["assembly"]["instances"]
        .as_array_mut()
        .expect("instances")
        .push(json!({"part": "Arm", "name": "arm2", "position": {"x": 40, "y": 40, "z": 300}}));
    doc["assembly"]["joints"]
        .as_array_mut()
        .expect("joints")
        .push(
            json!({"type": "revolute", "name": "slow_hinge", "parent": "base", "child": "arm2",
                     "anchor": {"x": 50, "y": 50, "z": 300}, "axis": {"x": 1, "y": 0, "z": 0}}),
        );
    doc["assembly"]["actuators"] = json!([{"name": "slow", "type": "general", "joint": "slow_hinge",
        "dynamics": "filter", "timeconst": 0.5, "gain": [2, 0, 0]}]);
    doc["assembly"]["sensors"] = json!([
        {"name": "direct", "type": "actuatorfrc", "actuator": "hinge"},
        {"name": "filtered", "type": "actuatorfrc", "actuator": "slow"}
    ]);
    doc["assembly"]["keyframes"] = json!([{"name": "k", "controls": {"hinge": 0.5, "slow": 1},
                                           "activations": {"slow": 0.25}}]);
    let mut env = env_with(&doc, si(EnvConfig::default()));
    let force = |env: &RobotEnv| env.bodies().sensor_data;
    reset(&mut env, None, Some("k"));
    // The held command: the direct motor's control, the filter's activation × gain.
    close(&force(&env), &[0.5, 0.5], 1e-6, "held at the keyframe");
    reset(&mut env, None, None);
    close(
        &force(&env),
        &[0.0, 0.0],
        1e-12,
        "a plain reset holds nothing",
    );
    let err = |key: Value| {
        let mut d = doc.clone();
        d["assembly"]["keyframes"] = json!([key]);
        RobotEnv::from_json(&d.to_string(), EnvConfig::default())
            .err()
            .expect("a bad keyframe")
            .to_string()
    };
    let e = err(json!({"name": "k", "controls": {"nope": 1}}));
    assert!(
        e.contains("assembly.keyframes[0].controls.nope: no actuator or directly actuated joint is named \"nope\" (the document's: \"slow\", \"hinge\")"),
        "{e}"
    );
    let e = err(json!({"name": "k", "activations": {"hinge": 1}}));
    assert!(
        e.contains("assembly.keyframes[0].activations.hinge: no actuator is named \"hinge\" (actuators with an activation: \"slow\")"),
        "{e}"
    );
}
