//! The force a joint's limits apply (`joint_limit_force`, MuJoCo's `qfrc_constraint` of a
//! limited joint) and the `square` term, on a block pushed along a prismatic joint into
//! its stops.

mod common;

use common::env_with;
use gymfleet_env::{
    ActionType, DofKind, EnvConfig, RobotEnv, TaskKind, TaskSpec, TermsTask, Units,
};
use serde_json::json;

/// The common slider block between stops at -5 and +20 mm, on the joint `slide`.
fn slider() -> serde_json::Value {
    common::slider(json!({"name": "slide", "min": -5, "max": 20}))
}

fn slider_env(task: &str, units: Units) -> RobotEnv {
    let config = EnvConfig {
        units,
        task: Some(TaskSpec {
            kind: TaskKind::Terms(TermsTask::from_json(task).expect("a terms task")),
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    env_with(&slider(), config)
}

const TASK: &str = r#"{"terms": [
    {"name": "limit", "weight": 0, "value": {"joint_limit_force": "slide"}},
    {"name": "offset", "weight": -2, "square": {"of": {"joint": "slide"}, "center": 0.005}}
]}"#;

/// Pushed by F into a stop, the block rests on it and the stop pushes back with F (the
/// mean over the step of the hard stop's impulses); free of its stops, the force is 0.
#[test]
fn a_stop_pushes_back_with_the_force_that_holds_the_block_on_it() {
    let force = 0.01_f64;
    for units in [Units::Si, Units::Document] {
        let mut env = slider_env(TASK, units);
        let mut reached = None;
        for k in 0..120 {
            let r = env
                .step(ActionType::Torque, &[force as f32])
                .expect("steps");
            let x = f64::from(r.observation.joint_positions[0]);
            let limit = f64::from(env.term_values()[0]);
            let stop = units.dof(DofKind::Linear, 0.020);
            if x < stop - units.dof(DofKind::Linear, 1e-4) {
                assert_eq!(limit, 0.0, "{units:?} step {k}: free at {x}, force {limit}");
            } else {
                reached.get_or_insert(k);
            }
            if reached.is_some_and(|r| k > r + 2) {
                // N in every unit system, negative at the upper stop.
                assert!(
                    (limit + force).abs() < 1e-4 * force,
                    "{units:?} step {k}: the stop pushes with {limit} N, expected {}",
                    -force
                );
            }
        }
        assert!(
            reached.is_some(),
            "{units:?}: the block never reached its stop"
        );
        // Pulled away from the stop, it leaves it: no force on the first step already.
        env.step(ActionType::Torque, &[-force as f32])
            .expect("steps");
        assert_eq!(env.term_values()[0], 0.0);
        // At the lower stop the force is positive.
        for _ in 0..200 {
            env.step(ActionType::Torque, &[-force as f32])
                .expect("steps");
        }
        let limit = f64::from(env.term_values()[0]);
        assert!((limit - force).abs() < 1e-4 * force, "{units:?}: {limit}");
        // A reset starts from zero.
        env.reset(Some(0));
        assert_eq!(env.term_values()[0], 0.0);
    }
}

/// `square` is `(of − center)²`, in the coordinate's units, weighted into the reward.
#[test]
fn a_square_term_is_the_squared_offset_of_its_coordinate() {
    let mut env = slider_env(TASK, Units::Si);
    for _ in 0..40 {
        let r = env.step(ActionType::Torque, &[0.002]).expect("steps");
        let x = f64::from(r.observation.joint_positions[0]);
        let value = f64::from(env.term_values()[1]);
        let expected = (x - 0.005).powi(2);
        assert!(
            (value - expected).abs() <= 1e-6 * expected.max(1e-9),
            "{value} vs {expected}"
        );
        assert!((f64::from(r.flags.reward) + 2.0 * value).abs() < 1e-9);
    }
}

#[test]
fn bad_limit_force_and_square_terms_get_their_own_errors() {
    for (json, expected) in [
        (
            r#"{"terms": [{"name": "a", "value": {"joint_limit_force": "slide", "axis": "x"}}]}"#,
            "task.terms.terms[0].value: a joint limit force takes no axis or point (they are for instance, site and center_of_mass)",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"joint_limit_force": "elbow"}}]}"#,
            "task.terms.terms[0].value.joint_limit_force: unknown joint \"elbow\" (joints with a DOF: \"slide\")",
        ),
        (
            r#"{"terms": [{"name": "a", "square": {"of": {"joint": "slide"}, "center": 1e300}}]}"#,
            "task.terms.terms[0].square.center: expected a finite centre within ±1e9, got 1e300",
        ),
        (
            r#"{"terms": [{"name": "a", "square": {"of": {}}}]}"#,
            "task.terms.terms[0].square.of: expected exactly one of joint, joint_velocity, joint_limit_force, tendon_length, tendon_velocity, actuator_force, actuator, actuator_activation, sensor (with a component when it reports several), contact_wrench, body_inertia, body_velocity (the last three with a component), body_center, instance, site or center_of_mass (the last four with an axis), or action",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"actuator": "push"}}]}"#,
            "task.terms.terms[0].value.actuator: unknown actuator \"push\" (the document has no actuators)",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"actuator_activation": "push", "axis": "x"}}]}"#,
            "task.terms.terms[0].value: a named actuator's activation takes no axis or point (they are for instance, site and center_of_mass)",
        ),
        (
            r#"{"terms": [{"name": "a", "square": {"of": {"joint": "slide"}}, "ctrl_cost": {}}]}"#,
            "task.terms.terms[0]: expected exactly one of velocity, value, ctrl_cost, healthy, distance, square, contact_cost, tolerance, product, sum or norm",
        ),
    ] {
        let err = common::with_terms(&slider().to_string(), json, EnvConfig::default())
            .err()
            .expect("refused")
            .to_string();
        assert_eq!(err, expected);
    }
}
