//! `EnvConfig::reset_noise`: seeded initial-state noise. The same seed gives the same
//! start, the stream advances across resets, limits bound the draw, and the bodies
//! follow the perturbed joints.

mod common;

use common::*;
use gymfleet_env::{ActionType, EnvConfig, EnvError, RobotEnv};

fn noisy(doc: &str, ee: &str, noise: f64, seed: u64) -> RobotEnv {
    let config = EnvConfig {
        reset_noise: noise,
        seed,
        ..EnvConfig::with_end_effectors([ee])
    };
    RobotEnv::from_json(doc, config).unwrap()
}

fn bits(values: &[f32]) -> Vec<u32> {
    values.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn the_same_seed_gives_the_same_start_and_the_stream_advances() {
    let mut env = noisy(ARM2, "forearm", 10.0, 42);
    let first = env.reset(Some(42)).to_flat();
    let angles = &first[..2];
    assert!(angles[0] != 0.0, "the shoulder starts off zero: {angles:?}");
    assert!((-10.0..=10.0).contains(&angles[0]), "{angles:?}");
    assert!(
        (-10.0..=0.0).contains(&angles[1]),
        "elbow limits are [-120, 0]: {angles:?}"
    );
    assert_eq!(&first[2..4], &[0.0, 0.0], "velocities start at zero");

    let second = env.reset(None).to_flat();
    assert_ne!(bits(&first), bits(&second), "reset(None) draws a new start");
    let again = env.reset(Some(42)).to_flat();
    assert_eq!(bits(&first), bits(&again), "reseeding replays the stream");

    let mut other = noisy(ARM2, "forearm", 10.0, 42);
    assert_eq!(bits(&other.reset(Some(42)).to_flat()), bits(&first));
    assert_ne!(bits(&other.reset(Some(43)).to_flat()), bits(&first));
}

#[test]
fn the_end_effector_follows_the_perturbed_joint() {
    // The pendulum turns about +y through its anchor; the observed orientation must be
    // that rotation, and stepping from it must be continuous (no snap back to zero).
    let mut env = noisy(PENDULUM, "arm", 30.0, 7);
    let obs = env.reset(Some(7));
    let theta = f64::from(obs.joint_positions[0]).to_radians();
    let q = obs.end_effector_poses[0];
    let (qw, qy) = ((theta / 2.0).cos(), (theta / 2.0).sin());
    assert!(
        (f64::from(q[3]) - qw).abs() < 1e-5 && (f64::from(q[5]) - qy).abs() < 1e-5,
        "angle {theta} rad, orientation {q:?}"
    );
    let after = env.step(ActionType::Torque, &[0.0]).unwrap().observation;
    let moved = (after.joint_positions[0] - obs.joint_positions[0]).abs();
    assert!(
        moved < 1.0,
        "one step moves less than a degree, moved {moved}°"
    );
}

#[test]
fn zero_noise_is_an_exact_reset() {
    let mut plain = RobotEnv::from_json(ARM2, EnvConfig::with_end_effectors(["forearm"])).unwrap();
    let mut zero = noisy(ARM2, "forearm", 0.0, 99);
    assert_eq!(
        bits(&plain.reset(Some(1)).to_flat()),
        bits(&zero.reset(Some(2)).to_flat())
    );
}

#[test]
fn negative_or_non_finite_noise_is_rejected() {
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        let config = EnvConfig {
            reset_noise: bad,
            ..EnvConfig::with_end_effectors(["arm"])
        };
        let err = RobotEnv::from_json(PENDULUM, config).err().unwrap();
        assert!(matches!(
            err,
            EnvError::BadConfig {
                field: "reset_noise",
                ..
            }
        ));
        assert_eq!(
            err.to_string(),
            format!("reset_noise: expected a finite half-width >= 0 (deg or mm), got {bad}")
        );
    }
}

/// Regression: a huge `reset_noise` (1e308) overflowed the uniform draw's width and
/// panicked inside the pool (the server answered INTERNAL); it is refused instead.
#[test]
fn a_huge_noise_is_refused_not_a_panic() {
    for huge in [1e7, 1e308, f64::MAX] {
        let config = EnvConfig {
            reset_noise: huge,
            ..EnvConfig::with_end_effectors(["arm"])
        };
        let err = RobotEnv::from_json(PENDULUM, config).err().unwrap();
        assert_eq!(
            err.to_string(),
            format!(
                "reset_noise: expected a half-width of at most 1000000 (deg or mm), got {huge:e}"
            )
        );
    }
    let config = EnvConfig {
        reset_noise: 1e6,
        ..EnvConfig::with_end_effectors(["arm"])
    };
    let mut env = RobotEnv::from_json(PENDULUM, config).unwrap();
    assert!(env.reset(Some(3)).joint_positions[0].is_finite());
}
