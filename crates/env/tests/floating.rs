//! A floating base (`"floating_base": true`): the first instance is free, its pose and
//! velocity are observed, and the physics of the free tree is checked against what
//! mechanics says: free fall, momentum conserved under internal torques, landing on a
//! ground, and saved states that continue bit for bit.

mod common;

use common::*;
use gymfleet_env::{ActionType, EnvConfig, Observation, RobotEnv};
use serde_json::{json, Value};

/// Base and arm masses (kg) of [`robot`]: 100×100×20 mm and 20×20×200 mm at 1000 kg/m³.
const BASE_MASS: f64 = 0.2;
const ARM_MASS: f64 = 0.08;

/// A floating base (a 100×100×20 mm slab whose frame is a corner, so its centre of mass is
/// off its origin) with an arm hinged about X on top of it, 500 mm up; `gravity` in m/s².
fn robot(gravity: f64) -> Value {
    json!({
        "floating_base": true,
        "simulation": {"gravity": {"x": 0, "y": 0, "z": gravity}},
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
                 "anchor": {"x": 50, "y": 50, "z": 520}, "axis": {"x": 1, "y": 0, "z": 0}}
            ]
        }
    })
}

fn obs(env: &mut RobotEnv, torque: f32) -> Observation {
    env.step(ActionType::Torque, &[torque])
        .expect("valid action")
        .observation
}

/// The mass-weighted centre of mass of base and arm (the end effectors, in that order).
fn system_com(o: &Observation) -> [f64; 3] {
    let (b, a) = (&o.end_effector_poses[0], &o.end_effector_poses[1]);
    let m = BASE_MASS + ARM_MASS;
    [0, 1, 2].map(|k| (BASE_MASS * f64::from(b[k]) + ARM_MASS * f64::from(a[k])) / m)
}

#[test]
fn the_observation_carries_the_base_pose_and_velocity() {
    let env = env(&robot(-9.81), &["arm"]);
    let spec = env.spec();
    let layout: Vec<(&str, usize)> = spec
        .observation_layout
        .iter()
        .map(|s| (s.name, s.size))
        .collect();
    assert_eq!(
        layout,
        [
            ("joint_positions", 1),
            ("joint_velocities", 1),
            ("base_pose", 7),
            ("base_velocity", 6),
            ("end_effector_poses", 7)
        ]
    );
    assert_eq!(spec.observation_dim, 2 + 13 + 7);
    assert!(spec.floating_base);
    assert_eq!(spec.action_dim, 1, "the base takes no action");
    let o = env.observe();
    // The slab's centre of mass, level, at rest.
    assert_eq!(o.base_pose, [50.0, 50.0, 510.0, 1.0, 0.0, 0.0, 0.0]);
    assert_eq!(o.base_velocity, [0.0; 6]);
    assert_eq!(o.to_flat().len(), spec.observation_dim);
    // Grounded documents keep their layout.
    let mut grounded = robot(-9.81);
    grounded["floating_base"] = json!(false);
    let env = common::env(&grounded, &[]);
    assert!(!env.spec().floating_base);
    assert_eq!(env.spec().observation_dim, 2);
    assert!(env.observe().base_pose.is_empty());
}

/// Dropped, the whole robot falls as one body: `z = z0 − g·t²/2`, `v = −g·t` (to the
/// first-order error of semi-implicit Euler, `1/n` of the drop after `n` substeps), and
/// the hinge does not move.
#[test]
fn a_floating_robot_falls_freely_as_one_body() {
    let g = 9.81;
    let mut env = env(&robot(-g), &["arm"]);
    let z0 = f64::from(env.observe().base_pose[2]);
    let mut o = env.observe();
    let steps = 120;
    for _ in 0..steps {
        o = obs(&mut env, 0.0);
    }
    let t = steps as f64 / 240.0;
    let drop = z0 - f64::from(o.base_pose[2]);
    let expected = 0.5 * g * t * t * 1000.0;
    assert!(
        (drop / expected - 1.0).abs() < 0.005,
        "fell {drop} mm in {t} s, expected {expected}"
    );
    let vz = f64::from(o.base_velocity[2]);
    assert!(
        (vz / (-g * t * 1000.0) - 1.0).abs() < 1e-4,
        "vz {vz} mm/s after {t} s"
    );
    for k in [0, 1, 3, 4, 5] {
        assert!(o.base_velocity[k].abs() < 1e-3, "{:?}", o.base_velocity);
    }
    assert!(o.joint_positions[0].abs() < 1e-3, "{:?}", o.joint_positions);
    assert_eq!(&o.base_pose[3..], &[1.0, 0.0, 0.0, 0.0], "the base turned");
}

/// Without gravity, a torque at the hinge is internal: base and arm turn against each
/// other, and the centre of mass of the whole robot stays where it was (zero momentum),
/// up to the integrator's first-order error, which shrinks with the substep. The slab's
/// centre of mass is 51 mm off its frame's origin: a free root that turned about its origin
/// instead of its centre of mass (upstream Rapier, `vendor/rapier3d/PATCHES.md`) drifted
/// 102 mm here at any substep count.
#[test]
fn internal_torques_do_not_move_the_centre_of_mass() {
    let wander = |substeps: u32| -> f64 {
        let mut config = EnvConfig::with_end_effectors(["base", "arm"]);
        config.substeps = substeps;
        let mut env = env_with(&robot(0.0), config);
        let start = system_com(&env.observe());
        let mut o = env.observe();
        let mut largest: f64 = 0.0;
        for k in 0..480 {
            o = obs(&mut env, if k < 120 { 0.002 } else { -0.001 });
            let c = system_com(&o);
            let d = (0..3)
                .map(|i| (c[i] - start[i]).powi(2))
                .sum::<f64>()
                .sqrt();
            largest = largest.max(d);
        }
        // It really moved: the base spun by hundreds of degrees per second.
        let peak = f64::from(o.base_velocity[3]).abs();
        assert!(peak > 10.0, "the base turns at {peak}°/s");
        largest
    };
    let (coarse, fine, finest) = (wander(5), wander(20), wander(80));
    assert!(
        coarse < 2.0,
        "5 substeps: the centre of mass wandered {coarse} mm"
    );
    assert!(
        fine < coarse / 3.0,
        "20 substeps: {fine} mm against {coarse} at 5 (first order)"
    );
    assert!(finest < 0.05, "80 substeps: {finest} mm");
}

/// Dropped onto a ground plane listed after it, the robot lands and rests on it.
#[test]
fn a_floating_robot_lands_on_a_plane_and_rests() {
    let mut doc = robot(-9.81);
    doc["parts"]
        .as_array_mut()
        .unwrap()
        .push(json!({"name": "Floor", "primitive": {"type": "plane"}}));
    doc["assembly"]["instances"]
        .as_array_mut()
        .unwrap()
        .push(json!({"part": "Floor", "name": "floor"}));
    // Hold the arm upright with a position target while the robot falls and settles.
    let mut env = env(&doc, &[]);
    let mut o = env.observe();
    for _ in 0..720 {
        o = env
            .step(ActionType::Position, &[0.0])
            .expect("valid")
            .observation;
    }
    let z = f64::from(o.base_pose[2]);
    assert!((z - 10.0).abs() < 0.5, "the slab's centre rests at {z} mm");
    let speed = o.base_velocity[..3]
        .iter()
        .map(|v| f64::from(*v).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(speed < 1.0, "still moving at {speed} mm/s");
    assert!(
        o.joint_positions[0].abs() < 1.0,
        "arm at {}°",
        o.joint_positions[0]
    );
}

fn bits(o: &Observation) -> Vec<u32> {
    o.to_flat().iter().map(|v| v.to_bits()).collect()
}

/// A floating robot's saved state (its base's pose and six velocities included)
/// continues bit for bit.
#[test]
fn a_floating_robots_state_continues_bitwise() {
    let mut env = env_with(&robot(0.0), EnvConfig::with_end_effectors(["arm"]));
    for k in 0..60 {
        obs(&mut env, if k < 30 { 0.02 } else { -0.015 });
    }
    assert!(env.observe().base_velocity.iter().any(|v| v.abs() > 1.0));
    let state = env.save().expect("saves");
    let bytes = state.encode();
    let mut loaded =
        RobotEnv::from_state(&gymfleet_env::SavedState::decode(&bytes).expect("decodes"))
            .expect("loads");
    assert_eq!(bits(&loaded.observe()), bits(&env.observe()));
    for k in 0..120 {
        let torque = (k as f32 * 0.1).sin() * 0.02;
        assert_eq!(
            bits(&obs(&mut loaded, torque)),
            bits(&obs(&mut env, torque)),
            "step {k} after the load"
        );
    }
    // A reset puts the base back where the document placed it.
    let first = env.reset(None);
    assert_eq!(first.base_pose, [50.0, 50.0, 510.0, 1.0, 0.0, 0.0, 0.0]);
    assert_eq!(first.base_velocity, [0.0; 6]);
}

/// A floating base nothing is jointed to is a plain free body: observed all the same.
#[test]
fn a_lone_floating_base_is_observed_as_it_falls() {
    let mut doc = robot(-9.81);
    doc["assembly"]["instances"]
        .as_array_mut()
        .unwrap()
        .truncate(1);
    doc["assembly"]["joints"] = json!([]);
    let mut env = env(&doc, &[]);
    assert_eq!(env.spec().action_dim, 0);
    assert_eq!(env.spec().observation_dim, 13);
    let mut o = env.observe();
    for _ in 0..24 {
        o = env
            .step(ActionType::Torque, &[])
            .expect("valid")
            .observation;
    }
    let vz = f64::from(o.base_velocity[2]);
    assert!((vz / (-9.81 * 0.1 * 1000.0) - 1.0).abs() < 1e-4, "vz {vz}");
    assert!(o.base_pose[2] < 510.0 - 40.0, "z {}", o.base_pose[2]);
}

fn base_noise_env(units: gymfleet_env::Units, task: &str, doc: &Value) -> Result<RobotEnv, String> {
    let config = EnvConfig {
        units,
        task: Some(gymfleet_env::TaskSpec {
            kind: gymfleet_env::TaskKind::Terms(
                gymfleet_env::TermsTask::from_json(task).expect("a terms task"),
            ),
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    RobotEnv::from_json(&doc.to_string(), config).map_err(|e| e.to_string())
}

fn std_dev(values: &[f64]) -> f64 {
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt()
}

/// `reset_noise.base`: MuJoCo's free-joint noise. The base's frame moves by the position
/// distribution on each axis, its quaternion's components get the same noise (then are
/// normalized), and its velocity is drawn from the velocity distribution.
#[test]
fn base_noise_moves_and_spins_the_floating_base() {
    use gymfleet_env::Units;
    let task = r#"{"terms": [], "reset_noise": {"position": {"uniform": 0.1}, "velocity": {"normal": 0.1}, "base": true}}"#;
    let mut env = base_noise_env(Units::Si, task, &robot(0.0)).expect("env");
    let still = base_noise_env(Units::Si, r#"{"terms": []}"#, &robot(0.0))
        .expect("env")
        .reset(Some(0));
    let (mut dx, mut wx, mut vz) = (Vec::new(), Vec::new(), Vec::new());
    for seed in 0..400 {
        let o = env.reset(Some(seed));
        let (p, q) = (&o.base_pose[..3], &o.base_pose[3..]);
        let norm = q.iter().map(|c| f64::from(*c).powi(2)).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-5, "seed {seed}: |q| = {norm}");
        assert!(q[0] > 0.9, "seed {seed}: a small turn, q = {q:?}");
        // The centre of mass moves with the frame (±0.1 m) and the turn (≤ ~0.03 m here).
        for (k, (now, start)) in p.iter().zip(&still.base_pose).enumerate() {
            let d = f64::from(now - start);
            assert!(d.abs() < 0.1 + 0.04, "seed {seed}: axis {k} moved {d} m");
        }
        dx.push(f64::from(p[0] - still.base_pose[0]));
        wx.push(f64::from(o.base_velocity[3]));
        vz.push(f64::from(o.base_velocity[2]));
    }
    // Uniform ±0.1: σ = 0.1/√3 (the turn adds a little); normal σ = 0.1.
    let s = std_dev(&dx);
    assert!(
        (s - 0.1 / 3f64.sqrt()).abs() < 0.15 * 0.1 / 3f64.sqrt(),
        "σ(x) = {s}"
    );
    let s = std_dev(&wx);
    assert!((s - 0.1).abs() < 0.015, "σ(ωx) = {s}");
    let s = std_dev(&vz);
    assert!((s - 0.1).abs() < 0.02, "σ(vz) = {s}");
    assert_eq!(
        env.reset(Some(7)),
        env.reset(Some(7)),
        "the seed decides the draw"
    );
    // The drawn velocities move the base: a free, gravity-free body coasts.
    let start = env.reset(Some(3));
    let after = obs(&mut env, 0.0);
    assert_ne!(start.base_pose, after.base_pose);
}

#[test]
fn base_noise_needs_a_floating_base_and_si_units() {
    use gymfleet_env::Units;
    let task = r#"{"terms": [], "reset_noise": {"position": {"uniform": 0.1}, "base": true}}"#;
    let err = base_noise_env(Units::Document, task, &robot(0.0))
        .err()
        .expect("refused");
    assert_eq!(
        err,
        "task.terms.reset_noise.base: a floating base's noise is drawn in SI units (metres, radians, a quaternion's components): create the env with units \"si\""
    );
    let mut grounded = robot(0.0);
    grounded["floating_base"] = json!(false);
    let err = base_noise_env(Units::Si, task, &grounded)
        .err()
        .expect("refused");
    assert_eq!(
        err,
        "task.terms.reset_noise.base: the document has no floating base"
    );
}
