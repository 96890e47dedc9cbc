//! Domain randomisation: drawn masses change the dynamics as physics predicts, default
//! gains follow the drawn inertia, draws replay by seed and are reported by name.

use gymfleet_env::{ActionType, EnvConfig, Randomization, RobotEnv};

const PENDULUM: &str = include_str!("../../../models/pendulum.json");

fn pendulum(randomize: Randomization) -> RobotEnv {
    let config = EnvConfig {
        randomize: Some(randomize),
        ..EnvConfig::default()
    };
    RobotEnv::from_json(PENDULUM, config).expect("pendulum")
}

fn mass(factor: f64) -> Randomization {
    Randomization {
        mass_scale: Some([factor, factor]),
        ..Randomization::default()
    }
}

#[test]
fn a_heavier_arm_turns_less_under_the_same_torque() {
    // Upright, gravity exerts no torque on the arm: one step of τ gives Δθ ∝ τ / I, and
    // the inertia scales with the mass.
    let turn = |factor| {
        let mut env = pendulum(mass(factor));
        env.step(ActionType::Torque, &[1e-4])
            .unwrap()
            .observation
            .joint_positions[0]
    };
    let (light, heavy) = (turn(1.0), turn(2.0));
    assert!(light > 0.0);
    let ratio = f64::from(heavy / light);
    assert!((ratio - 0.5).abs() < 0.01, "{heavy} / {light} = {ratio}");
}

#[test]
fn default_gains_follow_the_drawn_inertia() {
    // Position control to 30°: a 3× heavier arm still settles there, critically damped
    // (no overshoot), because its gains were recomputed from its drawn mass.
    for factor in [1.0, 3.0] {
        let mut env = pendulum(mass(factor));
        let mut peak = f32::MIN;
        let mut last = 0.0;
        for _ in 0..120 {
            last = env
                .step(ActionType::Position, &[30.0])
                .unwrap()
                .observation
                .joint_positions[0];
            peak = peak.max(last);
        }
        assert!((last - 30.0).abs() < 1.5, "mass ×{factor}: {last}");
        assert!(peak < 31.5, "mass ×{factor}: overshoot to {peak}");
    }
    // Scaled gains: a quarter of the stiffness sags further under gravity.
    let soft = Randomization {
        gain_scale: Some([0.25, 0.25]),
        ..Randomization::default()
    };
    let mut env = pendulum(soft);
    let mut stiff = pendulum(mass(1.0));
    let (mut a, mut b) = (0.0, 0.0);
    for _ in 0..240 {
        a = env
            .step(ActionType::Position, &[30.0])
            .unwrap()
            .observation
            .joint_positions[0];
        b = stiff
            .step(ActionType::Position, &[30.0])
            .unwrap()
            .observation
            .joint_positions[0];
    }
    assert!(
        a > b && (a - 30.0).abs() > (b - 30.0).abs() * 2.0,
        "soft {a}, stiff {b}"
    );
}

#[test]
fn draws_are_per_reset_replay_by_seed_and_are_reported_by_name() {
    let wide = Randomization {
        mass_scale: Some([0.5, 2.0]),
        friction_scale: Some([0.8, 1.2]),
        damping_scale: None,
        gain_scale: Some([0.9, 1.1]),
    };
    let mut env = pendulum(wide);
    env.reset(Some(4));
    let first = env.draws().expect("draws");
    assert_eq!(first.instances.len(), 2);
    assert_eq!(first.instances[1].0, "arm");
    assert_eq!(first.joints, [("arm".to_string(), 1.0, first.joints[0].2)]);
    for (_, m, f) in &first.instances {
        assert!((0.5..=2.0).contains(m) && (0.8..=1.2).contains(f));
    }
    env.reset(None);
    assert_ne!(env.draws(), Some(first.clone()), "new factors every reset");
    env.reset(Some(4));
    assert_eq!(
        env.draws(),
        Some(first),
        "the same seed draws the same factors"
    );
    let plain = RobotEnv::from_json(PENDULUM, EnvConfig::default()).unwrap();
    assert_eq!(plain.draws(), None);
}

#[test]
fn bad_ranges_are_refused_with_their_field() {
    let config = EnvConfig {
        randomize: Some(Randomization {
            friction_scale: Some([0.0, 1.0]),
            ..Randomization::default()
        }),
        ..EnvConfig::default()
    };
    let Err(err) = RobotEnv::from_json(PENDULUM, config) else {
        panic!("accepted");
    };
    assert_eq!(
        err.to_string(),
        "randomize.friction_scale: expected factors 0.01 <= min <= max <= 100, got [0, 1]"
    );
}
