//! Physics against analytic results: pendulum period, energy conservation, free fall,
//! F = m·a on a prismatic joint, PD settling, and hard limits.

mod common;

use common::*;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv};
use serde_json::json;

/// Times (s) at which `samples` crosses zero upwards, linearly interpolated.
fn upward_zero_crossings(samples: &[f64], dt: f64) -> Vec<f64> {
    samples
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
        .map(|(i, w)| (i as f64 + w[0] / (w[0] - w[1])) * dt)
        .collect()
}

#[test]
fn small_angle_compound_pendulum_period_is_within_one_percent() {
    assert_small_angle_period(0.0);
}

/// Armature adds to the joint-space inertia: with twice the arm's own inertia about the
/// pivot as armature, the period is `2π·√(3·I/(m·g·d))`, √3 times the plain one.
#[test]
fn joint_armature_adds_to_the_pendulums_inertia() {
    let (_, i_pivot, _) = arm_mass_and_pivot_inertia();
    assert_small_angle_period(2.0 * i_pivot);
}

/// Mass properties given outright (`inertial`) replace the shape's: 2 g with its centre
/// of mass 30 mm below the pivot and 1e-7 kg·m² about it swing with the period of
/// `I = 1e-7 + m·d²`, whatever the arm's geometry says.
#[test]
fn given_mass_properties_set_the_pendulums_period() {
    let mut doc = hanging_pendulum(json!({}));
    doc["assembly"]["instances"][1]["inertial"] = json!({
        "mass": 0.002,
        "center_of_mass": {"x": 2, "y": 2, "z": 10},
        "inertia": {"xx": 1e-7, "yy": 1e-7, "zz": 2e-8}
    });
    let (m, d) = (0.002, 0.030);
    assert_period_of(env(&doc, &["arm"]), 1e-7 + m * d * d, m, d);
}

/// A capsule arm (radius 2 mm, 40 mm long caps included) hanging from its top end swings
/// with the period of its exact inertia: a 36 mm cylinder and two hemispheres.
#[test]
fn a_capsule_pendulum_swings_with_the_capsules_inertia() {
    let mut doc = hanging_pendulum(json!({}));
    doc["parts"][1]["primitive"] = json!({"type": "capsule", "radius": 2, "height": 40});
    doc["assembly"]["instances"][1]["position"] = json!({"x": 10, "y": 10, "z": -40});
    let (r, h, rho) = (0.002f64, 0.040f64, 1000.0);
    let pi = std::f64::consts::PI;
    let length = h - 2.0 * r;
    let (m_cyl, m_hemi) = (rho * pi * r * r * length, rho * 2.0 / 3.0 * pi * r.powi(3));
    let m = m_cyl + 2.0 * m_hemi;
    // About the centre, perpendicular to the axis; each hemisphere's centre of mass lies
    // 3r/8 beyond the cylinder's end, and its own inertia about it is 83/320·m·r².
    let offset = length / 2.0 + 3.0 * r / 8.0;
    let i_centre = m_cyl * (3.0 * r * r + length * length) / 12.0
        + 2.0 * (83.0 / 320.0 * m_hemi * r * r + m_hemi * offset * offset);
    let d = h / 2.0;
    let env = env(&doc, &["arm"]);
    let parts = env.scene().parts;
    assert!(
        parts.iter().any(|p| matches!(
            p.shape,
            gymfleet_env::SceneShape::Capsule { radius, half_segment }
                if (radius - 2.0).abs() < 1e-4 && (half_segment - 18.0).abs() < 1e-4
        )),
        "{parts:?}"
    );
    assert_period_of(env, i_centre + m * d * d, m, d);
}

/// The arm given as a mesh (its box's 8 corners: a hull) has the box's mass and inertia,
/// so the period of `2π·√(I/(m·g·d))`; its scene carries the hull to draw.
#[test]
fn a_mesh_hull_pendulum_swings_with_its_boxs_period() {
    let mut doc = hanging_pendulum(json!({}));
    let corners: Vec<[u32; 3]> = (0..8u32)
        .map(|i| [4 * (i & 1), 4 * ((i >> 1) & 1), 40 * ((i >> 2) & 1)])
        .collect();
    doc["parts"][1]["primitive"] = json!({"type": "mesh", "vertices": corners});
    let env = env(&doc, &["arm"]);
    let scene = env.scene();
    let arm = scene
        .parts
        .iter()
        .find(|p| p.instance == 1)
        .expect("the arm");
    match &arm.shape {
        gymfleet_env::SceneShape::Mesh {
            vertices,
            triangles,
        } => {
            assert_eq!((vertices.len(), triangles.len()), (8, 12));
        }
        other => panic!("a mesh, got {other:?}"),
    }
    let (m, i_pivot, d) = arm_mass_and_pivot_inertia();
    assert_period_of(env, i_pivot, m, d);
}

/// The document's `simulation.gravity` is the world's: at a quarter of g (along a tilted
/// axis) the pendulum's period doubles, `2π·√(I/(m·g/4·d))`.
#[test]
fn the_documents_gravity_sets_the_pendulums_period() {
    let mut doc = hanging_pendulum(json!({}));
    // g/4 straight down, plus a component along the hinge axis (Y) that cannot swing it.
    doc["simulation"] = json!({"gravity": {"x": 0.0, "y": 3.0, "z": -G / 4.0}});
    let env = env(&doc, &["arm"]);
    let (m, i_pivot, d) = arm_mass_and_pivot_inertia();
    assert_period_of(env, i_pivot, m / 4.0, d);
}

/// A joint's `initial` position is where every reset starts: observed there (positions are
/// measured from the document's pose), with the body (and its drawn collider) moved there,
/// and the swing that follows is the pendulum's from that angle. Reset noise stays within
/// the limits around it.
#[test]
fn a_joint_starts_at_its_initial_position() {
    let mut doc = hanging_pendulum(json!({"min": -40, "max": 40, "initial": 30}));
    let mut env = env(&doc, &["arm"]);
    let start = env.reset(Some(0));
    assert!((start.joint_positions[0] - 30.0).abs() < 1e-4, "{start:?}");
    // The arm's centre of mass, 20 mm below the pivot at (10, 10, 0), turned 30° about +Y.
    let com = start.end_effector_poses[0];
    let (s, c) = 30f64.to_radians().sin_cos();
    assert!(
        (f64::from(com[0]) - (10.0 - 20.0 * s)).abs() < 1e-3,
        "{com:?}"
    );
    assert!((f64::from(com[2]) - (-20.0 * c)).abs() < 1e-3, "{com:?}");
    let part = env
        .scene()
        .parts
        .into_iter()
        .find(|p| p.instance == 1)
        .expect("the arm");
    let scene_x = f64::from(part.position[0]);
    assert!(
        (scene_x - (10.0 - 20.0 * s)).abs() < 1e-3,
        "drawn at the start pose: {part:?}"
    );
    // Released from 30°, it swings through to about −30° (energy kept within 1 %).
    let mut lowest = f32::MAX;
    for _ in 0..60 {
        lowest = lowest.min(step(&mut env, ActionType::Torque, &[0.0])[0]);
    }
    assert!((lowest + 30.0).abs() < 0.3, "swung to {lowest}");
    // Noise wider than the limits: every start stays within [-40, 40] around 30.
    doc["assembly"]["joints"][0]["initial"] = json!(35);
    let mut noisy = env_with(
        &doc,
        EnvConfig {
            reset_noise: 100.0,
            ..EnvConfig::with_end_effectors(["arm"])
        },
    );
    let mut seen_top = false;
    for seed in 0..40 {
        let q = noisy.reset(Some(seed)).joint_positions[0];
        assert!((-40.0..=40.0).contains(&q), "started at {q}");
        seen_top |= q > 39.99;
    }
    assert!(seen_top, "some draws clamp at the upper limit");
}

/// A document's `simulation.dt` is the env step when the request leaves `dt` at 0.
#[test]
fn the_documents_dt_is_the_default_env_step() {
    let mut doc = hanging_pendulum(json!({}));
    doc["simulation"] = json!({"dt": 0.002});
    assert_eq!(env(&doc, &["arm"]).spec().dt, 0.002);
    let asked = gymfleet_env::EnvConfig {
        dt: 0.01,
        ..gymfleet_env::EnvConfig::default()
    };
    assert_eq!(env_with(&doc, asked).spec().dt, 0.01);
    assert_eq!(
        env(&hanging_pendulum(json!({})), &["arm"]).spec().dt,
        gymfleet_env::DEFAULT_DT
    );
}

/// The hanging arm's small-angle period with `armature` (kg·m²) at its joint, within 1 %
/// of `2π·√((I + armature)/(m·g·d))`.
fn assert_small_angle_period(armature: f64) {
    let env = env(&hanging_pendulum(json!({"armature": armature})), &["arm"]);
    let (m, i_pivot, d) = arm_mass_and_pivot_inertia();
    assert_period_of(env, i_pivot + armature, m, d);
}

/// A pendulum's small-angle period within 1 % of `2π·√(I/(m·g·d))`: `I` about the pivot
/// (armature included), `m` its mass, `d` the pivot to centre of mass distance.
fn assert_period_of(mut env: gymfleet_env::RobotEnv, inertia: f64, m: f64, d: f64) {
    let dt = env.spec().dt;
    let analytic = 2.0 * std::f64::consts::PI * (inertia / (m * G * d)).sqrt();
    let (m0, i0, d0) = arm_mass_and_pivot_inertia();

    // A short push from rest: about a 2.5° amplitude (scaled from the plain arm's).
    let push = 8e-5 * ((inertia * m * d) / (i0 * m0 * d0)).sqrt() as f32;
    step(&mut env, ActionType::Torque, &[push]);
    let mut angles = Vec::new();
    let steps = (12.0 * analytic / dt) as usize;
    for _ in 0..steps {
        angles.push(f64::from(step(&mut env, ActionType::Torque, &[0.0])[0]));
    }
    let amplitude = angles.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    assert!(
        (1.0..5.0).contains(&amplitude),
        "amplitude {amplitude}° is not small"
    );

    let crossings = upward_zero_crossings(&angles, dt);
    assert!(
        crossings.len() >= 10,
        "only {} periods seen",
        crossings.len()
    );
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let error = (measured - analytic).abs() / analytic;
    assert!(
        error < 0.01,
        "period {measured:.5} s vs analytic {analytic:.5} s ({:.3} % off)",
        error * 100.0
    );
}

/// Energy of the hanging arm above its rest state, from a measured observation:
/// `½·I·θ̇² + m·g·d·(1 − cos θ)`.
fn pendulum_energy(obs: &[f32]) -> f64 {
    let (m, i_pivot, d) = arm_mass_and_pivot_inertia();
    let theta = f64::from(obs[0]).to_radians();
    let omega = f64::from(obs[1]).to_radians();
    0.5 * i_pivot * omega * omega + m * G * d * (1.0 - theta.cos())
}

#[test]
fn undamped_pendulum_energy_drifts_less_than_one_percent_over_ten_periods() {
    let mut env = env(&hanging_pendulum(json!({})), &["arm"]);
    let (m, i_pivot, d) = arm_mass_and_pivot_inertia();
    let period = 2.0 * std::f64::consts::PI * (i_pivot / (m * G * d)).sqrt();

    // Kick to a large swing (about 40°), then let go.
    let start = pendulum_energy(&step(&mut env, ActionType::Torque, &[1.2e-3]));
    let steps = (10.0 * period / env.spec().dt) as usize;
    let mut peak_angle = 0.0f32;
    let mut worst = 0.0f64;
    for _ in 0..steps {
        let obs = step(&mut env, ActionType::Torque, &[0.0]);
        peak_angle = peak_angle.max(obs[0].abs());
        worst = worst.max((pendulum_energy(&obs) - start).abs() / start);
    }
    assert!(peak_angle > 20.0, "swing too small to test: {peak_angle}°");
    assert!(worst < 0.01, "energy drifted by {:.3} %", worst * 100.0);
}

#[test]
fn joint_damping_from_the_document_dissipates_energy() {
    let mut env = env(&hanging_pendulum(json!({"damping": 1e-6})), &["arm"]);
    let start = pendulum_energy(&step(&mut env, ActionType::Torque, &[1.2e-3]));
    let mut obs = Vec::new();
    for _ in 0..500 {
        obs = step(&mut env, ActionType::Torque, &[0.0]);
    }
    let end = pendulum_energy(&obs);
    assert!(end < 0.5 * start, "damped energy {end} vs start {start}");
}

#[test]
fn the_end_effector_pose_follows_the_measured_joint_angle() {
    let mut env = env(&hanging_pendulum(json!({})), &["arm"]);
    step(&mut env, ActionType::Torque, &[1.2e-3]);
    for _ in 0..37 {
        let obs = step(&mut env, ActionType::Torque, &[0.0]);
        let theta = f64::from(obs[0]).to_radians();
        // The centre of mass hangs 20 mm below the pivot at (10, 10, 0).
        let (x, z) = (10.0 - 20.0 * theta.sin(), -20.0 * theta.cos());
        assert!((f64::from(obs[2]) - x).abs() < 1e-3, "x {} vs {x}", obs[2]);
        assert!((f64::from(obs[4]) - z).abs() < 1e-3, "z {} vs {z}", obs[4]);
        // The orientation is a rotation by θ about +Y.
        let (qw, qy) = ((theta / 2.0).cos(), (theta / 2.0).sin());
        assert!((f64::from(obs[5]) - qw).abs() < 1e-4 && (f64::from(obs[7]) - qy).abs() < 1e-4);
    }
}

#[test]
fn an_unjointed_body_falls_as_half_g_t_squared() {
    let doc = json!({
        "parts": [
            {"name": "Floor", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 1}}},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": 5}}
        ],
        "assembly": {"instances": [
            {"part": "Floor", "name": "floor"},
            {"part": "Ball", "name": "ball", "position": {"x": 500, "y": 0, "z": 2000}}
        ]}
    });
    let mut env = env(&doc, &["ball"]);
    let z0 = f64::from(env.observe().end_effector_poses[0][2]);
    let dt = env.spec().dt;
    let h = dt / f64::from(env.spec().substeps);
    let steps = 120;
    let mut obs = Vec::new();
    for _ in 0..steps {
        obs = step(&mut env, ActionType::Torque, &[]);
    }
    let t = steps as f64 * dt;
    let drop_mm = z0 - f64::from(obs[2]);
    let analytic_mm = 0.5 * G * t * t * 1000.0;
    // Semi-implicit Euler falls an extra ½·g·h·t; allow that and f32 rounding, no more.
    let bound = 0.5 * G * h * t * 1000.0 + 0.05;
    assert!(
        (drop_mm - analytic_mm).abs() <= bound,
        "fell {drop_mm:.3} mm, analytic {analytic_mm:.3} mm (bound {bound:.3})"
    );
    assert!((f64::from(obs[0]) - 500.0).abs() < 1e-3, "drifted sideways");
}

/// A ground plane (the grounded instance) stops a falling ball: it comes to rest touching
/// the plane, wherever it lands (the plane is unbounded), with no sinking.
#[test]
fn a_ground_plane_catches_a_falling_ball() {
    let doc = json!({
        "parts": [
            {"name": "Ground", "primitive": {"type": "plane"}},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": 5}}
        ],
        "assembly": {"instances": [
            {"part": "Ground", "name": "ground"},
            {"part": "Ball", "name": "ball", "position": {"x": 5000, "y": -3000, "z": 100}}
        ]}
    });
    let mut env = env(&doc, &["ball"]);
    let mut obs = Vec::new();
    for _ in 0..480 {
        obs = step(&mut env, ActionType::Torque, &[]);
    }
    let z = f64::from(obs[2]);
    assert!(
        (z - 5.0).abs() < 0.1,
        "the ball's centre rests at {z} mm, its radius is 5"
    );
    assert!(
        (f64::from(obs[0]) - 5000.0).abs() < 1e-3,
        "it rolled off to {}",
        obs[0]
    );
    // A plane is a ground wherever it is listed: after a grounded ball, it is fixed too.
    let mut other = doc.clone();
    other["assembly"]["instances"] = json!([
        {"part": "Ball", "name": "ball", "position": {"x": 0, "y": 0, "z": 100}},
        {"part": "Ground", "name": "ground", "position": {"x": 0, "y": 0, "z": -50}}
    ]);
    let mut env = common::env(&other, &["ball"]);
    for _ in 0..48 {
        obs = step(&mut env, ActionType::Torque, &[]);
    }
    assert_eq!(obs[2], 100.0, "the grounded ball moved");
}

#[test]
fn prismatic_displacement_under_a_known_force_matches_f_equals_m_a() {
    let mut env = env(&slider(json!({})), &["block"]);
    let (force, mass) = (0.01, 1e-3);
    let dt = env.spec().dt;
    let h = dt / f64::from(env.spec().substeps);
    let steps = 60;
    let mut obs = Vec::new();
    for _ in 0..steps {
        obs = step(&mut env, ActionType::Torque, &[force as f32]);
    }
    let t = steps as f64 * dt;
    let a = force / mass;
    let analytic_mm = 0.5 * a * t * t * 1000.0;
    let bound = 0.5 * a * h * t * 1000.0 + 0.05;
    let x = f64::from(obs[0]);
    assert!(
        (x - analytic_mm).abs() <= bound,
        "moved {x:.3} mm, analytic {analytic_mm:.3} mm"
    );
    let v = f64::from(obs[1]);
    let analytic_v = a * t * 1000.0;
    assert!(
        (v - analytic_v).abs() / analytic_v < 1e-3,
        "velocity {v} vs {analytic_v} mm/s"
    );
    // The end effector moved by the same amount as the joint says.
    assert!((f64::from(obs[2]) - (5.0 + x)).abs() < 1e-2);
}

/// A joint spring (`stiffness`, MuJoCo's): the block on its slider oscillates about the
/// spring's rest position with the period `2π·√(m/k)` (within 1 %), from a displaced start
/// or about a displaced rest.
#[test]
fn a_joint_spring_oscillates_with_the_analytic_period() {
    let (mass, k) = (1e-3f64, 1.0f64);
    let expected = 2.0 * std::f64::consts::PI * (mass / k).sqrt();
    for (initial, rest) in [(10.0, 0.0), (0.0, -8.0)] {
        let doc = slider(json!({"stiffness": k, "spring_rest": rest, "initial": initial}));
        let mut env = env(&doc, &["block"]);
        let dt = env.spec().dt;
        let samples: Vec<f64> = (0..480)
            .map(|_| f64::from(step(&mut env, ActionType::Torque, &[0.0])[0]) - rest)
            .collect();
        let crossings = upward_zero_crossings(&samples, dt);
        let periods: Vec<f64> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(periods.len() >= 5, "{crossings:?}");
        let period = periods.iter().sum::<f64>() / periods.len() as f64;
        assert!(
            (period / expected - 1.0).abs() < 0.01,
            "start {initial} mm, rest {rest} mm: period {period} s, expected {expected}"
        );
        // It swings about the rest position, as far to each side.
        let (lo, hi) = samples
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        let amplitude = (initial - rest).abs();
        assert!(
            (hi - amplitude).abs() < 0.05 * amplitude && (lo + amplitude).abs() < 0.05 * amplitude,
            "{lo} .. {hi} about the rest, amplitude {amplitude}"
        );
    }
}

/// Joint friction (`friction`, MuJoCo's `frictionloss`): a force below it leaves the block
/// on its slider at rest; a force above it accelerates the block at `(F − F_f)/m`.
#[test]
fn joint_friction_holds_below_it_and_subtracts_above_it() {
    let (friction, mass) = (0.005, 1e-3);
    let mut env = env(&slider(json!({"friction": friction})), &["block"]);
    let mut obs = Vec::new();
    for _ in 0..60 {
        obs = step(&mut env, ActionType::Torque, &[0.004]);
    }
    assert!(
        f64::from(obs[0]).abs() < 1e-3,
        "moved {} mm under 0.004 N",
        obs[0]
    );
    let force = 0.01;
    let (dt, substeps) = (env.spec().dt, f64::from(env.spec().substeps));
    let steps = 60;
    for _ in 0..steps {
        obs = step(&mut env, ActionType::Torque, &[force as f32]);
    }
    let t = steps as f64 * dt;
    let a = (force - friction) / mass;
    let analytic_mm = 0.5 * a * t * t * 1000.0;
    let bound = 0.5 * a * (dt / substeps) * t * 1000.0 + 0.05;
    let x = f64::from(obs[0]);
    assert!(
        (x - analytic_mm).abs() <= bound,
        "moved {x:.3} mm, analytic {analytic_mm:.3} mm"
    );
}

/// A horizontal arm turning about a vertical axis: gravity exerts no torque on it.
fn turntable(joint_extra: serde_json::Value) -> serde_json::Value {
    let mut joint = json!({"type": "revolute", "parent": "base", "child": "arm",
                           "anchor": {"x": 0, "y": 0, "z": 5}, "axis": {"x": 0, "y": 0, "z": 1}});
    merge(&mut joint, joint_extra);
    json!({
        "parts": [
            {"name": "Base", "primitive": {"type": "cylinder", "radius": 10, "height": 5}},
            {"name": "Arm", "primitive": {"type": "cube", "size": {"x": 40, "y": 4, "z": 4}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Base", "name": "base"},
                {"part": "Arm", "name": "arm", "position": {"x": -2, "y": -2, "z": 5}}
            ],
            "joints": [joint]
        }
    })
}

#[test]
fn a_position_target_settles_within_one_percent_without_overshoot() {
    let mut env = env(&turntable(json!({})), &["arm"]);
    let target = 30.0f32;
    let mut peak = 0.0f32;
    let mut settled_at = None;
    for i in 0..400 {
        let obs = step(&mut env, ActionType::Position, &[target]);
        peak = peak.max(obs[0]);
        let within = (obs[0] - target).abs() <= 0.01 * target;
        match (within, settled_at) {
            (true, None) => settled_at = Some(i),
            (false, Some(_)) => settled_at = None,
            _ => {}
        }
    }
    // Default gains are critically damped at 20 Hz: settled in well under 0.5 s.
    let settled_at = settled_at.expect("never settled within 1 %");
    assert!(
        (settled_at as f64) * env.spec().dt < 0.5,
        "settled after {settled_at} steps"
    );
    assert!(
        peak <= target * 1.01,
        "overshoot to {peak}° for a {target}° target"
    );
}

#[test]
fn a_velocity_target_is_tracked() {
    let mut env = env(&turntable(json!({})), &["arm"]);
    let mut obs = Vec::new();
    for _ in 0..100 {
        obs = step(&mut env, ActionType::Velocity, &[90.0]);
    }
    assert!((obs[1] - 90.0).abs() < 0.9, "velocity {} deg/s", obs[1]);
}

#[test]
fn revolute_limits_hold_under_a_large_torque_in_every_mode() {
    let doc = turntable(json!({"min": -30, "max": 45}));
    for (action_type, value) in [
        (ActionType::Torque, 1.0f32),
        (ActionType::Torque, -1.0),
        (ActionType::Position, 170.0),
        (ActionType::Velocity, -5000.0),
    ] {
        let mut env = env(&doc, &["arm"]);
        let mut reached = 0.0f32;
        for _ in 0..300 {
            let obs = step(&mut env, action_type, &[value]);
            assert!(
                (-30.05..=45.05).contains(&obs[0]),
                "{action_type} {value}: joint at {}° beyond [-30, 45]",
                obs[0]
            );
            reached = if value > 0.0 {
                reached.max(obs[0])
            } else {
                reached.min(obs[0])
            };
        }
        let stop = if value > 0.0 { 45.0 } else { -30.0 };
        assert!(
            (reached - stop).abs() < 0.5,
            "{action_type}: reached {reached}°, stop {stop}°"
        );
    }
}

#[test]
fn max_effort_clamps_every_mode() {
    let clamped = turntable(json!({"max_effort": 1e-4}));
    let mut a = env(&clamped, &["arm"]);
    let mut b = env(&turntable(json!({})), &["arm"]);
    for _ in 0..20 {
        let oa = step(&mut a, ActionType::Torque, &[5.0]);
        let ob = step(&mut b, ActionType::Torque, &[1e-4]);
        assert_eq!(oa, ob, "a clamped 5 N·m must equal 1e-4 N·m exactly");
    }
    // A position target far away accelerates no faster than max_effort allows.
    let mut c = env(&clamped, &["arm"]);
    let mut d = env(&turntable(json!({})), &["arm"]);
    let (oc, od) = (
        step(&mut c, ActionType::Position, &[90.0]),
        step(&mut d, ActionType::Position, &[90.0]),
    );
    assert!(oc[1] < od[1], "clamped {} vs free {} deg/s", oc[1], od[1]);
    assert!(oc[1] > 0.0);
}

#[test]
fn gain_overrides_change_the_response() {
    let soft = EnvConfig {
        pd_gains: Some(gymfleet_env::PdGains {
            kp: vec![1e-5],
            kd: vec![1e-7],
        }),
        ..EnvConfig::with_end_effectors(["arm"])
    };
    let mut a = env_with(&turntable(json!({})), soft);
    let mut b = env(&turntable(json!({})), &["arm"]);
    let (oa, ob) = (
        step(&mut a, ActionType::Position, &[30.0]),
        step(&mut b, ActionType::Position, &[30.0]),
    );
    assert!(
        oa[0] < ob[0],
        "soft gains moved {}°, default {}°",
        oa[0],
        ob[0]
    );
}

#[test]
fn jointed_pairs_do_not_collide_and_everything_else_does() {
    // The arm starts 3 mm deep inside the base it is jointed to: no contact pushes it.
    // A 4 mm cube dropped from 20 mm lands on the base and rests on its top face.
    let doc = json!({
        "parts": [
            {"name": "Base", "primitive": {"type": "cube", "size": {"x": 60, "y": 60, "z": 5}}},
            {"name": "Arm", "primitive": {"type": "cube", "size": {"x": 40, "y": 4, "z": 4}}},
            {"name": "Pebble", "primitive": {"type": "cube", "size": {"x": 4, "y": 4, "z": 4}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Base", "name": "base"},
                {"part": "Arm", "name": "arm", "position": {"x": 10, "y": 10, "z": 2}},
                {"part": "Pebble", "name": "pebble", "position": {"x": 40, "y": 40, "z": 20}}
            ],
            "joints": [{"type": "revolute", "parent": "base", "child": "arm",
                        "anchor": {"x": 12, "y": 12, "z": 2}, "axis": {"x": 0, "y": 0, "z": 1}}]
        }
    });
    let mut env = env(&doc, &["arm", "pebble"]);
    let mut obs = Vec::new();
    for _ in 0..240 {
        obs = step(&mut env, ActionType::Torque, &[0.0]);
    }
    assert_eq!(obs[0], 0.0, "the jointed arm was pushed by its own base");
    assert_eq!(obs[1], 0.0);
    // The pebble is a free body: its pose and velocity (13 floats) come before the end
    // effectors, the arm's pose and the pebble's.
    assert_eq!(env.spec().free_bodies, ["pebble"]);
    assert_eq!(
        &obs[2..5],
        &obs[22..25],
        "the free body's pose is its centre's"
    );
    // Pebble: centre 2 mm above the base's top face at z = 5, at rest, upright.
    let pebble = &obs[22..29];
    assert!(
        (pebble[2] - 7.0).abs() < 0.05,
        "pebble rests at z = {}",
        pebble[2]
    );
    assert!((pebble[0] - 42.0).abs() < 0.05 && (pebble[1] - 42.0).abs() < 0.05);
    assert!((pebble[3] - 1.0).abs() < 1e-3, "pebble tipped: {pebble:?}");
}

/// Regression: Rapier's limit constraint engages only once a joint is past its limit,
/// so a large effort carried the seed arm's elbow ([-120, 0]°) 42° past its stop at
/// 0.25 N·m and 146° at 0.875 N·m, and with 2 solver substeps the env diverged. The
/// multibody now projects limited DOFs back onto their stops after every substep (the
/// hard limits of `vendor/rapier3d/PATCHES.md`), up to 10 N·m: 10⁴ times what holds the
/// arm out horizontally.
#[test]
fn seed_arm_limits_are_hard_stops_under_extreme_torques() {
    for torque in [0.05f32, 0.25, 0.875, 2.0, 5.0, 10.0] {
        for sign in [1.0f32, -1.0] {
            let mut env =
                RobotEnv::from_json(ARM2, EnvConfig::with_end_effectors(["forearm"])).unwrap();
            let action = [sign * torque, -sign * torque];
            for k in 0..480 {
                let result = env.step(ActionType::Torque, &action).unwrap();
                assert!(!result.flags.terminated, "{action:?}: diverged at step {k}");
                let [shoulder, elbow] = result.observation.joint_positions[..] else {
                    unreachable!("two DOFs")
                };
                assert!(
                    (-90.001..=90.001).contains(&shoulder) && (-120.001..=0.001).contains(&elbow),
                    "{action:?}, step {k}: shoulder {shoulder}° (stops ±90), elbow {elbow}° \
                     (stops -120..0)"
                );
            }
        }
    }
}

/// A 1 g block driven along a prismatic joint by 10 N (10⁴ g) into its 20 mm stop: it
/// must never pass the stop, and it rests there (inelastic stop: velocity 0).
#[test]
fn prismatic_stop_holds_a_block_slammed_into_it() {
    let mut env = env(&slider(json!({"min": -5, "max": 20})), &["block"]);
    let mut obs = Vec::new();
    for k in 0..120 {
        obs = step(&mut env, ActionType::Torque, &[10.0]);
        assert!(
            obs[0] <= 20.001,
            "step {k}: block at {} mm, stop at 20",
            obs[0]
        );
    }
    assert!(
        (obs[0] - 20.0).abs() < 1e-3,
        "rests on its stop: {} mm",
        obs[0]
    );
    assert!(obs[1].abs() < 1e-2, "and is still: {} mm/s", obs[1]);
}

/// The hand angle (deg, positive towards the post) at which its corner nearest the post
/// touches the post's face at x = 53 mm: the corner is 2 mm beside and 42 mm below the
/// hinge at x = 90 mm, so `90 - 2·cos θ - 42·sin θ = 53`.
fn hand_contact_angle() -> f64 {
    let gap = |theta: f64| 90.0 - 2.0 * theta.cos() - 42.0 * theta.sin() - 53.0;
    let (mut lo, mut hi) = (0.0f64, std::f64::consts::FRAC_PI_2);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if gap(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo.to_degrees()
}

/// Collision filters (MuJoCo's contype/conaffinity rule): a hand whose bits share none with
/// the post's swings through it; bits that match one way only are enough to collide.
#[test]
fn collision_filter_bits_decide_which_instances_collide() {
    let contact = hand_contact_angle();
    let with_bits = |post: serde_json::Value, hand: serde_json::Value| {
        let mut doc = hand_and_post();
        doc["assembly"]["instances"][1]["collision"] = post;
        doc["assembly"]["instances"][3]["collision"] = hand;
        let mut env = env(&doc, &["hand"]);
        let mut furthest = f64::MIN;
        for _ in 0..240 {
            let obs = step(&mut env, ActionType::Torque, &[2e-3]);
            furthest = furthest.max(f64::from(obs[0]));
        }
        furthest
    };
    let apart = with_bits(
        json!({"group": 2, "mask": 2}),
        json!({"group": 1, "mask": 1}),
    );
    assert!(
        apart > contact + 20.0,
        "filtered apart, the hand reached only {apart}° (contact at {contact:.2}°)"
    );
    // The post's group is in the hand's mask (one way): they collide.
    let one_way = with_bits(
        json!({"group": 2, "mask": 0}),
        json!({"group": 0, "mask": 2}),
    );
    assert!(
        one_way < contact + 0.1,
        "one matching direction should collide: the hand reached {one_way}°"
    );
    let none = with_bits(json!({"group": 0, "mask": 0}), json!({}));
    assert!(
        none > contact + 20.0,
        "a post that collides with nothing stopped the hand at {none}°"
    );
}

/// Collision detection runs once per step (the solver substeps reuse its contacts), so a
/// link of a chain swung into another link of the same chain must still be stopped by it,
/// and never pass through. Up to 2e-3 N·m (the hand hits at 5900°/s, 22° per step) it stops
/// on the post within 0.1°; at 2e-2 N·m (12000°/s, 30° per step, a 9 m/s tip) the speculative
/// contact still stops it, 2° in at worst (1.5 mm), and pushes it back out.
#[test]
fn links_of_one_chain_that_no_joint_connects_collide() {
    let contact = hand_contact_angle();
    for (torque, past) in [(2e-4f32, 0.1), (2e-3, 0.1), (2e-2, 3.0)] {
        let mut env = env(&hand_and_post(), &["hand"]);
        let mut obs = Vec::new();
        for k in 0..480 {
            obs = step(&mut env, ActionType::Torque, &[torque]);
            assert!(
                f64::from(obs[0]) < contact + past,
                "{torque} N·m, step {k}: the hand is at {}°, into the post (contact at \
                 {contact:.2}°)",
                obs[0]
            );
        }
        assert!(
            (f64::from(obs[0]) - contact).abs() < 0.5,
            "{torque} N·m: the hand rests at {}°, not on the post (contact at {contact:.2}°)",
            obs[0]
        );
        assert!(
            obs[1].abs() < 1.0,
            "{torque} N·m: still moving at {} deg/s",
            obs[1]
        );
    }
}
