//! Terms tasks (the Gymnasium suite's reward vocabulary, for any robot) and SI units:
//! each term's value recomputed from the observation, the reward as their weighted sum,
//! the `unhealthy` termination, the reset's noise, geared actions, states that carry the
//! velocity terms, and an exact error for each bad task.

use gymfleet_env::{
    ActionType, EnvConfig, EnvError, RobotEnv, TaskKind, TaskSpec, TermsTask, Units,
};

const ARM2: &str = include_str!("../../../models/arm2.json");
const PENDULUM: &str = include_str!("../../../models/pendulum.json");

fn task(json: &str) -> TaskSpec {
    TaskSpec {
        kind: TaskKind::Terms(TermsTask::from_json(json).expect("a terms task")),
        action_cost: 0.0,
    }
}

fn arm2(json: &str, units: Units) -> RobotEnv {
    let config = EnvConfig {
        units,
        task: Some(task(json)),
        ..EnvConfig::default()
    };
    RobotEnv::from_json(ARM2, config).expect("arm2 with a terms task")
}

fn error_of(document: &str, json: &str, units: Units) -> String {
    let spec = match TermsTask::from_json(json) {
        Ok(t) => TaskSpec {
            kind: TaskKind::Terms(t),
            action_cost: 0.0,
        },
        Err(e) => return e.to_string(),
    };
    let config = EnvConfig {
        units,
        task: Some(spec),
        ..EnvConfig::default()
    };
    match RobotEnv::from_json(document, config) {
        Err(e @ (EnvError::BadTask { .. } | EnvError::BadConfig { .. })) => e.to_string(),
        Err(other) => panic!("not a task error: {other}"),
        Ok(_) => panic!("accepted: {json}"),
    }
}

const LOCOMOTION: &str = r#"{
    "terms": [
        {"name": "reward_forward", "weight": 2.0, "velocity": {"joint": "upper"}},
        {"name": "reward_ctrl", "weight": -0.1, "ctrl_cost": {}},
        {"name": "reward_survive", "weight": 1.0, "healthy": {}},
        {"name": "x_position", "weight": 0.0, "value": {"joint": "upper"}},
        {"name": "tip_z", "weight": 0.0, "value": {"instance": "forearm", "axis": "z"}},
        {"name": "com_x", "weight": 0.0, "value": {"center_of_mass": true, "axis": "x"}},
        {"name": "reach", "weight": -1.0,
         "distance": [{"instance": "forearm"}, {"instance": "base", "point": [0, 0, 0]}]}
    ],
    "healthy": {"ranges": [{"of": {"joint": "forearm"}, "min": -2.5}], "terminate": true}
}"#;

#[test]
fn term_values_are_recomputed_from_the_observation_and_sum_into_the_reward() {
    let mut env = arm2(LOCOMOTION, Units::Si);
    let spec = env.spec().clone();
    assert_eq!(
        spec.term_names,
        [
            "reward_forward",
            "reward_ctrl",
            "reward_survive",
            "x_position",
            "tip_z",
            "com_x",
            "reach"
        ]
    );
    assert_eq!(spec.units, Units::Si);
    let mut before = env.reset(Some(3)).joint_positions[0];
    assert_eq!(
        env.term_values(),
        [0.0; 7],
        "no values before the first step"
    );
    for step in 0..20 {
        let action = [0.0004, -0.0003];
        let result = env.step(ActionType::Torque, &action).expect("steps");
        let obs = &result.observation;
        let v = env.term_values().to_vec();
        let dt = spec.dt;
        // Forward: Δ position / dt, in rad/s (the observation is in rad).
        let forward = (f64::from(obs.joint_positions[0]) - f64::from(before)) / dt;
        assert!(
            (f64::from(v[0]) - forward).abs() < 1e-3 * forward.abs().max(1e-3),
            "step {step}: {} against {forward}",
            v[0]
        );
        let ctrl: f64 = action.iter().map(|a| f64::from(*a).powi(2)).sum();
        assert!((f64::from(v[1]) - ctrl).abs() < 1e-12);
        assert_eq!(v[2], 1.0, "healthy");
        assert_eq!(v[3], obs.joint_positions[0]);
        // The tip's height in m, and the distance from the base's origin.
        let pose = env.observe();
        assert!(pose.joint_positions == obs.joint_positions);
        let weighted =
            2.0 * f64::from(v[0]) - 0.1 * f64::from(v[1]) + f64::from(v[2]) - f64::from(v[6]);
        assert!(
            (f64::from(result.flags.reward) - weighted).abs() < 1e-4 * weighted.abs().max(1.0),
            "reward {} against Σ w·v = {weighted}",
            result.flags.reward
        );
        before = obs.joint_positions[0];
    }
}

#[test]
fn si_observations_are_the_document_units_converted() {
    let config = |units| EnvConfig {
        units,
        end_effector_ids: vec!["forearm".into()],
        ..EnvConfig::default()
    };
    let mut doc = RobotEnv::from_json(ARM2, config(Units::Document)).expect("env");
    let mut si = RobotEnv::from_json(ARM2, config(Units::Si)).expect("env");
    for _ in 0..50 {
        let a = doc
            .step(ActionType::Torque, &[0.0005, 0.0002])
            .expect("steps");
        let b = si
            .step(ActionType::Torque, &[0.0005, 0.0002])
            .expect("steps");
        for (d, s) in a
            .observation
            .joint_positions
            .iter()
            .zip(&b.observation.joint_positions)
        {
            assert!(
                (f64::from(*d).to_radians() - f64::from(*s)).abs() < 1e-6,
                "{d} deg, {s} rad"
            );
        }
        for (d, s) in a
            .observation
            .joint_velocities
            .iter()
            .zip(&b.observation.joint_velocities)
        {
            assert!((f64::from(*d).to_radians() - f64::from(*s)).abs() < 1e-5);
        }
        for k in 0..3 {
            let (d, s) = (
                a.observation.end_effector_poses[0][k],
                b.observation.end_effector_poses[0][k],
            );
            assert!(
                (f64::from(d) / 1000.0 - f64::from(s)).abs() < 1e-7,
                "{d} mm, {s} m"
            );
        }
    }
}

#[test]
fn an_unhealthy_state_ends_the_episode_with_a_zero_healthy_value() {
    // The forearm's joint is limited to [-120°, 0°]: healthy while above -0.5 rad.
    let json = r#"{
        "terms": [{"name": "alive", "healthy": {}}],
        "healthy": {"ranges": [{"of": {"joint": "forearm"}, "min": -0.5, "max": 0.5}]}
    }"#;
    let mut env = arm2(json, Units::Si);
    let mut ended = None;
    for step in 1..=400 {
        let r = env.step(ActionType::Torque, &[0.0, -0.002]).expect("steps");
        let q = r.observation.joint_positions[1];
        if r.flags.terminated {
            assert!(q <= -0.5, "ended at {q} rad");
            assert_eq!(r.flags.termination.map(|t| t.as_str()), Some("unhealthy"));
            assert_eq!(env.term_values(), [0.0]);
            assert_eq!(r.flags.reward, 0.0);
            ended = Some(step);
            break;
        }
        assert!(q > -0.5);
        assert_eq!(env.term_values(), [1.0]);
        assert_eq!(r.flags.reward, 1.0);
    }
    assert!(ended.is_some(), "the forearm never left the healthy range");
    // Without `terminate`, the value drops to 0 and the episode goes on.
    let json = json.replace("\"max\": 0.5}]", "\"max\": 0.5}], \"terminate\": false");
    let mut env = arm2(&json, Units::Si);
    let mut zeros = 0;
    for _ in 0..400 {
        let r = env.step(ActionType::Torque, &[0.0, -0.002]).expect("steps");
        assert!(!r.flags.terminated);
        zeros += usize::from(env.term_values()[0] == 0.0);
    }
    assert!(zeros > 0);
}

#[test]
fn the_state_range_bounds_every_position_after_the_skipped_ones_and_every_velocity() {
    let json = r#"{
        "terms": [{"name": "alive", "healthy": {}}],
        "healthy": {"state_range": {"min": -1.0, "max": 1.0, "skip_positions": 1}}
    }"#;
    let mut env = arm2(json, Units::Si);
    // Spin the shoulder: its position is skipped, but its velocity is bounded.
    let mut step = 0;
    loop {
        step += 1;
        let r = env.step(ActionType::Torque, &[0.01, 0.0]).expect("steps");
        if r.flags.terminated {
            let v = r.observation.joint_velocities[0].abs();
            assert!(v >= 1.0, "ended with the shoulder at {v} rad/s");
            break;
        }
        assert!(step < 2000, "never unhealthy");
    }
}

#[test]
fn reset_noise_draws_positions_and_velocities_from_the_seed() {
    let json = r#"{
        "terms": [{"name": "x", "value": {"joint": "upper"}}],
        "reset_noise": {"position": {"uniform": 0.1}, "velocity": {"normal": 0.2}}
    }"#;
    let mut a = arm2(json, Units::Si);
    let mut b = arm2(json, Units::Si);
    let first = a.reset(Some(7));
    assert_eq!(first, b.reset(Some(7)), "same seed, same start");
    let other = a.reset(Some(8));
    assert_ne!(first, other);
    // Many resets: uniform positions within ±0.1 rad (clamped into the limits), normal
    // velocities with σ ≈ 0.2 rad/s.
    let (mut sum, mut sum2, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for seed in 0..400 {
        let obs = a.reset(Some(seed));
        assert!(obs.joint_positions[0].abs() <= 0.1 + 1e-6);
        assert!(obs.joint_positions[1] <= 1e-6 && obs.joint_positions[1] >= -0.1 - 1e-6);
        for v in &obs.joint_velocities {
            let v = f64::from(*v);
            sum += v;
            sum2 += v * v;
            n += 1.0;
        }
    }
    let mean = sum / n;
    let sd = (sum2 / n - mean * mean).sqrt();
    assert!(mean.abs() < 0.03, "mean {mean}");
    assert!((sd - 0.2).abs() < 0.02, "sd {sd}");
    // And the first step starts from those velocities: against an env at rest, the
    // shoulder has moved by about v·dt more.
    let only_velocity = r#"{"terms": [], "reset_noise": {"velocity": {"normal": 0.2}}}"#;
    let mut moving = arm2(only_velocity, Units::Si);
    let mut still = arm2(r#"{"terms": []}"#, Units::Si);
    let start = moving.reset(Some(5));
    assert_eq!(start.joint_positions, still.reset(Some(5)).joint_positions);
    assert!(
        start.joint_velocities[0].abs() > 0.01,
        "{:?}",
        start.joint_velocities
    );
    let a = moving.step(ActionType::Torque, &[0.0, 0.0]).expect("steps");
    let b = still.step(ActionType::Torque, &[0.0, 0.0]).expect("steps");
    let moved = a.observation.joint_positions[0] - b.observation.joint_positions[0];
    let expected = start.joint_velocities[0] * moving.spec().dt as f32;
    // Within a quarter: the forearm starts moving too, and the two joints are coupled.
    assert!(
        (moved - expected).abs() < 0.25 * expected.abs(),
        "moved {moved} rad further, expected about {expected}"
    );
}

#[test]
fn a_gear_makes_the_action_a_control_signal() {
    let geared = ARM2.replacen(
        "\"type\": \"revolute\"",
        "\"type\": \"revolute\", \"gear\": 4",
        1,
    );
    assert_ne!(geared, ARM2, "the document names its first joint's type");
    let mut plain = RobotEnv::from_json(ARM2, EnvConfig::default()).expect("env");
    let mut ctrl = RobotEnv::from_json(&geared, EnvConfig::default()).expect("env");
    assert_eq!(ctrl.spec().dofs[0].gear, 4.0);
    for _ in 0..30 {
        let a = plain
            .step(ActionType::Torque, &[0.0008, 0.0001])
            .expect("steps");
        let b = ctrl
            .step(ActionType::Torque, &[0.0002, 0.0001])
            .expect("steps");
        assert_eq!(
            a.observation, b.observation,
            "gear × ctrl is the same torque"
        );
    }
}

#[test]
fn a_reference_is_added_to_observed_positions_and_position_targets() {
    let shifted = ARM2.replacen(
        "\"type\": \"revolute\"",
        "\"type\": \"revolute\", \"reference\": 30",
        1,
    );
    let mut plain = RobotEnv::from_json(ARM2, EnvConfig::default()).expect("env");
    let mut moved = RobotEnv::from_json(&shifted, EnvConfig::default()).expect("env");
    for _ in 0..30 {
        let a = plain
            .step(ActionType::Position, &[10.0, -20.0])
            .expect("steps");
        let b = moved
            .step(ActionType::Position, &[40.0, -20.0])
            .expect("steps");
        let shift = b.observation.joint_positions[0] - a.observation.joint_positions[0];
        assert!((shift - 30.0).abs() < 1e-4, "{shift}");
        assert_eq!(
            a.observation.joint_positions[1],
            b.observation.joint_positions[1]
        );
    }
}

#[test]
fn a_saved_state_carries_the_velocity_terms() {
    let mut env = arm2(LOCOMOTION, Units::Si);
    for _ in 0..10 {
        env.step(ActionType::Torque, &[0.0005, 0.0]).expect("steps");
    }
    let state = env.save().expect("saves");
    let mut copy = RobotEnv::from_state(&state).expect("loads");
    for _ in 0..10 {
        let a = env
            .step(ActionType::Torque, &[0.0005, -0.0002])
            .expect("steps");
        let b = copy
            .step(ActionType::Torque, &[0.0005, -0.0002])
            .expect("steps");
        assert_eq!(a.observation, b.observation);
        assert_eq!(env.term_values(), copy.term_values());
        assert_eq!(a.flags, b.flags);
    }
}

#[test]
fn each_bad_terms_task_gets_its_own_error() {
    let si = Units::Si;
    for (json, expected) in [
        (
            r#"{"terms": [{"name": "a", "velocity": {"joint": "elbow"}}]}"#,
            "task.terms.terms[0].velocity.joint: unknown joint \"elbow\" (joints with a DOF: \"upper\", \"forearm\")",
        ),
        (
            r#"{"terms": [{"name": "a", "ctrl_cost": {}, "healthy": {}}]}"#,
            "task.terms.terms[0]: expected exactly one of velocity, value, ctrl_cost, healthy, distance, square, contact_cost, tolerance, product, sum or norm",
        ),
        (
            r#"{"terms": [{"name": "a", "healthy": {}}]}"#,
            "task.terms.terms[0].healthy: a healthy term needs the task's healthy conditions (task.terms.healthy)",
        ),
        (
            r#"{"terms": [{"name": "a", "ctrl_cost": {}}, {"name": "a", "ctrl_cost": {}}]}"#,
            "task.terms.terms[1].name: \"a\" names an earlier term too; names must be unique",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"instance": "upper"}}]}"#,
            "task.terms.terms[0].value.axis: a point's coordinate needs an axis: \"x\", \"y\" or \"z\"",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"joint": "upper", "axis": "x"}}]}"#,
            "task.terms.terms[0].value: a joint position takes no axis or point (they are for instance, site and center_of_mass)",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"instance": "hand", "axis": "x"}}]}"#,
            "task.terms.terms[0].value.instance: unknown instance \"hand\" (known: \"base\", \"upper\", \"forearm\")",
        ),
        (
            r#"{"terms": [{"name": "a", "weight": 1e300, "ctrl_cost": {}}]}"#,
            "task.terms.terms[0].weight: expected a finite weight within ±1e9, got 1e300",
        ),
        (
            r#"{"terms": [], "healthy": {"ranges": [{"of": {"joint": "upper"}, "min": 1, "max": 0}]}}"#,
            "task.terms.healthy.ranges[0].max: expected max > min = 1, got 0",
        ),
        (
            r#"{"terms": [], "healthy": {"state_range": {"min": -1, "max": 1, "skip_positions": 3}}}"#,
            "task.terms.healthy.state_range.skip_positions: expected at most the number of DOFs (2), got 3",
        ),
        (
            r#"{"terms": [], "reset_noise": {"position": {"uniform": 0.1, "normal": 0.1}}}"#,
            "task.terms.reset_noise.position: expected exactly one of uniform (half-width) or normal (standard deviation)",
        ),
        (
            r#"{"terms": [], "reset_noise": {"velocity": {"normal": -1}}}"#,
            "task.terms.reset_noise.velocity: expected a scale 0 <= s <= 1e9 (the env's units), got -1",
        ),
        (
            r#"{"terms": [{"name": "a", "speed": {}}]}"#,
            "task.terms.terms[0].speed: unknown field `speed`, expected one of `name`, `weight`",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"site": "tip", "axis": "x"}}]}"#,
            "task.terms.terms[0].value.site: unknown site \"tip\" (sites: none: the document has no assembly.sites)",
        ),
        (
            r#"{"terms": [{"name": "a", "distance": [{"site": "tip", "instance": "upper"}, {"instance": "upper"}]}]}"#,
            "task.terms.terms[0].distance[0]: expected a site, or an instance (with an optional point)",
        ),
        (
            r#"{"terms": [], "reset_noise": {"set": [{"joints": ["upper"], "low": [0.1], "high": [0.0]}]}}"#,
            "task.terms.reset_noise.set[0].high[0]: expected high >= low = 0.1, got 0",
        ),
        (
            r#"{"terms": [], "reset_noise": {"set": [{"joints": ["upper"], "low": [0], "high": [0]}, {"joints": ["upper"], "low": [0], "high": [0]}]}}"#,
            "task.terms.reset_noise.set[1].joints[0]: the joint is set by an earlier entry too",
        ),
        (
            r#"{"terms": [], "reset_noise": {"set": [{"joints": ["upper", "forearm"], "low": [0], "high": [0]}]}}"#,
            "task.terms.reset_noise.set[0]: expected one low and one high per joint (2), got 1 and 1",
        ),
        (
            r#"{"terms": [{"name": "", "ctrl_cost": {}}]}"#,
            "task.terms.terms[0].name: expected a name of 1 to 64 printable characters",
        ),
    ] {
        let got = error_of(ARM2, json, si);
        assert!(got.starts_with(expected), "{json}\n got: {got}\nwant: {expected}");
        assert!(got.len() < 600, "unbounded: {got}");
    }
}

#[test]
fn si_units_refuse_the_document_unit_tasks_and_noise_is_set_once() {
    let config = EnvConfig {
        units: Units::Si,
        task: Some(TaskSpec {
            kind: TaskKind::Upright {
                instance: "arm".into(),
                axis: [0.0, 0.0, 1.0],
                max_tilt_deg: 30.0,
            },
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    let err = RobotEnv::from_json(PENDULUM, config)
        .err()
        .expect("refused");
    assert_eq!(
        err.to_string(),
        "task: reach, track and upright tasks are in the document's units (mm, deg); with units \"si\" use a terms task"
    );
    let config = EnvConfig {
        reset_noise: 1.0,
        task: Some(task(
            r#"{"terms": [], "reset_noise": {"position": {"uniform": 1}}}"#,
        )),
        ..EnvConfig::default()
    };
    let err = RobotEnv::from_json(PENDULUM, config)
        .err()
        .expect("refused");
    assert_eq!(
        err.to_string(),
        "reset_noise: the task draws the positions (task.terms.reset_noise.position); set one of the two"
    );
}

/// An arm2 whose forearm carries a site at its far end (the arm's links are 40 mm long
/// along their local z in the seed model; the site is checked against the instance's
/// point, whatever the frame).
fn arm2_with_site() -> String {
    let mut doc: serde_json::Value = serde_json::from_str(ARM2).expect("json");
    doc["assembly"]["sites"] = serde_json::json!([{"name": "tip", "instance": "forearm", "point": {"x": 1, "y": 2, "z": 30}}]);
    doc.to_string()
}

#[test]
fn a_site_is_a_named_point_of_its_instance() {
    let json = r#"{"terms": [
        {"name": "site_z", "weight": 0, "value": {"site": "tip", "axis": "z"}},
        {"name": "point_z", "weight": 0, "value": {"instance": "forearm", "point": [1, 2, 30], "axis": "z"}},
        {"name": "gap", "weight": 0, "distance": [{"site": "tip"}, {"instance": "forearm", "point": [1, 2, 30]}]},
        {"name": "reach", "weight": 0, "distance": [{"site": "tip"}, {"instance": "base", "point": [0, 0, 0]}]}
    ]}"#;
    // An end effector may name a site: its point is observed, with its instance's
    // orientation.
    let config = EnvConfig {
        units: Units::Si,
        task: Some(task(json)),
        end_effector_ids: vec!["tip".into(), "forearm".into()],
        ..EnvConfig::default()
    };
    let mut env = RobotEnv::from_json(&arm2_with_site(), config).expect("env");
    for _ in 0..30 {
        let obs = env
            .step(ActionType::Torque, &[0.0004, -0.0003])
            .expect("steps")
            .observation;
        let v = env.term_values();
        assert_eq!(v[0], v[1], "the site is the instance's point");
        assert_eq!(obs.end_effector_poses[0][2], v[0], "the site's z, observed");
        assert_eq!(
            obs.end_effector_poses[0][3..],
            obs.end_effector_poses[1][3..]
        );
        assert_eq!(v[2], 0.0);
        assert!(v[3] > 0.0);
    }
    // A document whose site names an unknown instance is refused by the validator.
    let bad = arm2_with_site().replace("\"instance\":\"forearm\"", "\"instance\":\"hand\"");
    let err = RobotEnv::from_json(&bad, EnvConfig::default())
        .err()
        .expect("refused");
    assert!(
        err.to_string()
            .contains("assembly.sites[0].instance: unknown instance \"hand\""),
        "{err}"
    );
}

#[test]
fn set_joints_start_where_drawn_at_rest() {
    // The shoulder drawn in a ring 0.2 <= |q| <= 0.3 rad of a box [-0.5, 0.5]; the noise on
    // the other joint stays as drawn.
    let json = r#"{"terms": [], "reset_noise": {
        "velocity": {"uniform": 0.5},
        "set": [{"joints": ["upper"], "low": [-0.5], "high": [0.5], "min_norm": 0.2, "max_norm": 0.3}]
    }}"#;
    let mut env = arm2(json, Units::Si);
    let mut signs = [0, 0];
    for seed in 0..200 {
        let obs = env.reset(Some(seed));
        let q = obs.joint_positions[0].abs();
        assert!((0.2 - 1e-6..=0.3 + 1e-6).contains(&q), "seed {seed}: {q}");
        assert_eq!(obs.joint_velocities[0], 0.0, "set joints start at rest");
        signs[usize::from(obs.joint_positions[0] > 0.0)] += 1;
        assert!(obs.joint_velocities[1] != 0.0);
    }
    assert!(signs[0] > 50 && signs[1] > 50, "{signs:?}");
    // The same seed, the same draw; a fixed value is set exactly.
    assert_eq!(env.reset(Some(4)), env.reset(Some(4)));
    let fixed = r#"{"terms": [], "reset_noise": {"set": [{"joints": ["forearm"], "low": [-0.25], "high": [-0.25]}]}}"#;
    let mut env = arm2(fixed, Units::Si);
    let q = env.reset(Some(1)).joint_positions[1];
    assert!((q + 0.25).abs() < 1e-6, "{q}");
}
