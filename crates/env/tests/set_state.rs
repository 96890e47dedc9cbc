//! Setting a joint state from values (`RobotEnv::set_joint_state`, MuJoCo's `set_state`)
//! and reading every instance's and site's state (`RobotEnv::bodies`).

mod common;

use common::*;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, StateAdjustment, Units};
use serde_json::{json, Value};

/// A floating 100×100×20 mm slab (its frame a corner) with an arm hinged on top, limited to
/// [-60°, 60°], and a site on the arm.
fn robot() -> Value {
    let mut doc = slab_with_arm();
    doc["assembly"]["sites"] =
        json!([{"name": "tip", "instance": "arm", "point": {"x": 10, "y": 10, "z": 200}}]);
    doc
}

fn si_env() -> RobotEnv {
    let config = EnvConfig {
        units: Units::Si,
        ..EnvConfig::with_end_effectors(["tip"])
    };
    env_with(&robot(), config)
}

/// The state an env reached after some torque steps: positions, velocities, base state.
fn moving_state(env: &mut RobotEnv) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut flat = Vec::new();
    for k in 0..30 {
        flat = step(
            env,
            ActionType::Torque,
            &[if k < 15 { 0.02 } else { -0.01 }],
        );
    }
    let f = |r: std::ops::Range<usize>| flat[r].iter().map(|&v| f64::from(v)).collect();
    (f(0..1), f(1..2), f(2..15))
}

#[test]
fn a_set_state_reads_back_as_set_and_the_episode_goes_on() {
    let mut source = si_env();
    let (q, v, base) = moving_state(&mut source);
    assert!(
        base[2] < 0.5 && v[0].abs() > 0.01,
        "the source moved: {base:?} {v:?}"
    );
    let mut env = si_env();
    step(&mut env, ActionType::Torque, &[0.0]);
    let mut out = vec![0.0f32; env.spec().observation_dim];
    let notes = env
        .set_joint_state(&q, &v, &base, &mut out)
        .expect("a usable state");
    assert!(notes.is_empty(), "{notes:?}");
    assert_eq!(env.elapsed_steps(), 1, "the episode goes on");
    let expected: Vec<f64> = q.iter().chain(&v).chain(&base).copied().collect();
    for (k, (&got, want)) in out.iter().zip(expected).enumerate() {
        assert!(
            (f64::from(got) - want).abs() < 1e-5,
            "value {k}: {got} read back, {want} set"
        );
    }
    assert_eq!(
        out,
        env.observe().to_flat(),
        "the observation written is the env's"
    );
    // The site follows the arm: where the source has it; and the links move as the
    // source's do at once (not from the next substep on).
    let (set, from) = (env.bodies(), source.bodies());
    for (a, b) in set.site_poses[0].iter().zip(from.site_poses[0]) {
        assert!(
            (a - b).abs() < 1e-5,
            "tip {:?} against {:?}",
            set.site_poses,
            from.site_poses
        );
    }
    for (a, b) in set
        .velocities
        .iter()
        .flatten()
        .zip(from.velocities.iter().flatten())
    {
        assert!(
            (a - b).abs() < 1e-4,
            "cvel {:?} against {:?}",
            set.velocities,
            from.velocities
        );
    }
}

#[test]
fn a_set_state_then_a_step_continues_as_its_saved_state_does() {
    let mut source = si_env();
    let (q, v, base) = moving_state(&mut source);
    let mut env = si_env();
    let mut out = vec![0.0f32; env.spec().observation_dim];
    env.set_joint_state(&q, &v, &base, &mut out)
        .expect("a usable state");
    let saved = env.save().expect("saves");
    let first: Vec<Vec<f32>> = (0..20)
        .map(|_| step(&mut env, ActionType::Torque, &[0.01]))
        .collect();
    env.load(&saved).expect("loads");
    let again: Vec<Vec<f32>> = (0..20)
        .map(|_| step(&mut env, ActionType::Torque, &[0.01]))
        .collect();
    assert_eq!(first, again, "bit for bit");
    // And the set state moves on as the source does, to float32 noise.
    for (k, row) in first.iter().enumerate() {
        let s = step(&mut source, ActionType::Torque, &[0.01]);
        for (a, b) in s.iter().zip(row) {
            assert!((a - b).abs() < 2e-3, "step {k}: {s:?} against {row:?}");
        }
    }
}

#[test]
fn a_position_past_a_limit_is_set_at_the_limit_and_said() {
    let mut env = si_env();
    let mut out = vec![0.0f32; env.spec().observation_dim];
    let base = env.observe().to_flat()[2..15]
        .iter()
        .map(|&v| f64::from(v))
        .collect::<Vec<_>>();
    let past = 61f64.to_radians();
    let notes = env
        .set_joint_state(&[past], &[0.0], &base, &mut out)
        .expect("accepted");
    assert_eq!(notes.len(), 1);
    let StateAdjustment::Clamped { dof, set, .. } = &notes[0] else {
        panic!("{notes:?}")
    };
    assert_eq!(*dof, 0);
    assert!((set - 60f64.to_radians()).abs() < 1e-12);
    assert!(
        notes[0].to_string().starts_with(&format!(
            "joint_positions[0] (hinge): {past} is past the joint's limit; set to 1.047"
        )),
        "{}",
        notes[0]
    );
    assert!(
        (f64::from(out[0]) - 60f64.to_radians()).abs() < 1e-5,
        "{}",
        out[0]
    );
}

#[test]
fn an_unusable_state_is_refused_and_leaves_the_env_as_it_was() {
    let mut env = si_env();
    step(&mut env, ActionType::Torque, &[0.02]);
    let before = env.observe().to_flat();
    let base: Vec<f64> = before[2..15].iter().map(|&v| f64::from(v)).collect();
    let mut out = vec![0.0f32; env.spec().observation_dim];
    let mut zero_quat = base.clone();
    zero_quat[3..7].fill(0.0);
    type Case<'a> = (&'a [f64], &'a [f64], &'a [f64], &'a str);
    let cases: [Case; 5] = [
        (&[0.0, 0.0], &[0.0], &base, "joint_positions: expected 1 values (one per DOF), got 2"),
        (&[0.0], &[f64::NAN], &base, "joint_velocities[0]: expected a finite number, got NaN"),
        (&[0.0], &[0.0], &base[..7], "base_state: expected 13 values (the base's pose x, y, z, qw, qx, qy, qz, then its velocity vx, vy, vz, wx, wy, wz), got 7"),
        (&[0.0], &[0.0], &zero_quat, "base_state[3..7]: the orientation quaternion (qw, qx, qy, qz) is all zeros"),
        (&[f64::INFINITY], &[0.0], &base, "joint_positions[0]: expected a finite number, got inf"),
    ];
    for (q, v, b, message) in cases {
        let err = env.set_joint_state(q, v, b, &mut out).expect_err(message);
        assert_eq!(err.to_string(), message);
        assert_eq!(env.observe().to_flat(), before, "unchanged after {message}");
    }
    // Without a floating base, a base state is refused.
    let mut grounded = env_with(&hanging_pendulum(json!({})), EnvConfig::default());
    let err = grounded
        .set_joint_state(&[0.0], &[0.0], &[0.0; 13], &mut [0.0; 2])
        .expect_err("no base");
    assert_eq!(
        err.to_string(),
        "base_state: the env has no floating base: give no values, got 13"
    );
}

#[test]
fn bodies_report_each_instance_and_site() {
    let env = si_env();
    let b = env.bodies();
    assert_eq!(b.instances, ["base", "arm"]);
    // 1000 kg/m³: 100×100×20 mm and 20×20×200 mm.
    assert!(
        (b.masses[0] - 0.2).abs() < 1e-6 && (b.masses[1] - 0.08).abs() < 1e-6,
        "{:?}",
        b.masses
    );
    // The slab's centre, in metres; the arm's 100 mm above its base.
    let close = |a: [f64; 3], e: [f64; 3]| a.iter().zip(e).all(|(x, y)| (x - y).abs() < 1e-6);
    assert!(
        close(b.centers_of_mass[0], [0.05, 0.05, 0.51]),
        "{:?}",
        b.centers_of_mass
    );
    assert!(
        close(b.centers_of_mass[1], [0.05, 0.05, 0.62]),
        "{:?}",
        b.centers_of_mass
    );
    let com =
        [0, 1, 2].map(|k| (0.2 * b.centers_of_mass[0][k] + 0.08 * b.centers_of_mass[1][k]) / 0.28);
    assert!(close(b.about, com), "about {:?} vs {com:?}", b.about);
    // cinert's mass and mass × offset; at rest, no velocity and no contact.
    assert!((b.inertias[1][9] - 0.08).abs() < 1e-6);
    assert!(
        (b.inertias[1][8] - 0.08 * (0.62 - com[2])).abs() < 1e-7,
        "{:?}",
        b.inertias[1]
    );
    assert!(b.velocities.iter().flatten().all(|&v| v == 0.0));
    assert!(b.contact_wrenches.iter().flatten().all(|&v| v == 0.0));
    assert_eq!(b.sites, ["tip"]);
    let tip = b.site_poses[0];
    assert!(
        close([0, 1, 2].map(|k| f64::from(tip[k])), [0.05, 0.05, 0.72]),
        "{tip:?}"
    );
    assert_eq!(b.actuator_forces, [0.0]);
}
