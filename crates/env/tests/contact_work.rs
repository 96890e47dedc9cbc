//! The contact work a step may ask of the solver (`RobotEnv::set_contact_work_limit`): a
//! step over it stops before its solver, fails with `EnvError::ContactWork`, and leaves the
//! env where its last step left it; `initial_contact_work` estimates the first step's.

use gymfleet_env::{ActionType, EnvConfig, EnvError, RobotEnv};
use serde_json::{json, Value};

/// Issue O1's document: `n` cubes of 2 mm, the default density, no joints, all at
/// (0, 0, 10) mm (the first one grounded, the others free and overlapping it).
fn cube_pile(n: usize) -> String {
    let instances: Vec<_> = (0..n)
        .map(|i| {
            json!({"part": "Cube", "name": format!("cube{i}"),
                   "position": {"x": 0, "y": 0, "z": 10}})
        })
        .collect();
    json!({
        "parts": [{"name": "Cube", "primitive": {"type": "cube", "size": {"x": 2, "y": 2, "z": 2}}}],
        "assembly": {"instances": instances, "joints": []}
    })
    .to_string()
}

/// A floor and `heights.len()` free 10 mm cubes above it, one on another's column (their
/// lowest faces at the heights given, mm); with a fluid, every substep is a pipeline step.
fn falling_cubes(heights: &[f64], fluid: bool) -> String {
    let mut instances = vec![json!({"part": "Floor", "name": "floor"})];
    for (i, z) in heights.iter().enumerate() {
        instances.push(json!({"part": "Cube", "name": format!("cube{i}"),
                              "position": {"x": -5, "y": -5, "z": z}}));
    }
    let mut doc: Value = json!({
        "parts": [
            {"name": "Floor", "primitive": {"type": "plane"}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}}
        ],
        "assembly": {"instances": instances, "joints": []}
    });
    if fluid {
        doc["simulation"] = json!({"fluid": {"density": 1.2, "viscosity": 0.0}});
    }
    doc.to_string()
}

fn env(doc: &str, limit: usize) -> RobotEnv {
    let mut env = RobotEnv::from_json(
        doc,
        EnvConfig {
            max_steps: 100_000,
            ..EnvConfig::default()
        },
    )
    .expect("env");
    env.set_contact_work_limit(limit);
    env
}

fn flat(env: &RobotEnv) -> Vec<u32> {
    let mut out = vec![0.0; env.spec().observation_dim];
    env.observe_into(&mut out);
    out.iter().map(|v| v.to_bits()).collect()
}

/// Steps until the limit stops a step (at most `max` steps); the overload and the steps
/// taken before it.
fn step_until_refused(env: &mut RobotEnv, max: usize) -> (gymfleet_physics::ContactOverload, u32) {
    for _ in 0..max {
        match env.step(ActionType::Torque, &[]) {
            Ok(_) => continue,
            Err(EnvError::ContactWork(overload)) => return (overload, env.elapsed_steps()),
            Err(other) => panic!("unexpected error {other}"),
        }
    }
    panic!("no step was refused in {max} steps");
}

#[test]
fn the_first_steps_contact_work_is_estimated_before_stepping() {
    let env = env(&cube_pile(300), 0);
    let (load, work) = env.initial_contact_work();
    // Every pair of the 300 overlapping cubes touches, in four points.
    assert_eq!(
        (load.pairs, load.manifolds, load.points),
        (44_850, 44_850, 179_400)
    );
    assert_eq!(work, 179_400 * 5, "points × the default 5 substeps");
    // Apart, the cubes of a falling column touch nothing yet.
    let apart = env_of_column();
    assert_eq!(apart.initial_contact_work().1, 0);
}

fn env_of_column() -> RobotEnv {
    env(&falling_cubes(&[20.0, 40.0], false), 0)
}

#[test]
fn a_step_over_the_limit_stops_before_its_solver_and_leaves_the_env_as_it_was() {
    // A cube landing on the floor touches it in four points: 20 point-substeps at the
    // default 5 substeps, over a limit of 19.
    let doc = falling_cubes(&[20.0], false);
    let mut limited = env(&doc, 19);
    let mut free = env(&doc, 0);
    let (overload, steps) = step_until_refused(&mut limited, 400);
    assert_eq!(
        (
            overload.pairs,
            overload.points,
            overload.substeps,
            overload.work,
            overload.max
        ),
        (1, 4, 5, 20, 19)
    );
    assert_eq!(overload.substeps_done, 0);
    assert!(steps > 0, "the cube fell some steps first");
    let before = flat(&limited);
    let message = limited
        .step(ActionType::Torque, &[])
        .expect_err("the same state is refused again")
        .to_string();
    assert_eq!(
        message,
        "the step found 1 contact pairs with 4 contact points: 20 contact point-substeps \
         (4 points × 5 substeps), over the limit of 19 per env step; the env was left where \
         its last step left it (reset it, or set another state)"
    );
    assert_eq!(flat(&limited), before, "a refused step moves nothing");
    assert_eq!(limited.elapsed_steps(), steps, "nor counts as a step");

    // The unlimited twin reaches the same state in as many steps, and from there both
    // step alike once the limit is lifted.
    for _ in 0..steps {
        free.step(ActionType::Torque, &[]).expect("free step");
    }
    assert_eq!(flat(&free), before);
    limited.set_contact_work_limit(20);
    for _ in 0..50 {
        limited
            .step(ActionType::Torque, &[])
            .expect("within the limit");
        free.step(ActionType::Torque, &[]).expect("free step");
    }
    assert_eq!(
        flat(&limited),
        flat(&free),
        "the refused steps changed nothing"
    );

    // A reset is always possible.
    limited.set_contact_work_limit(19);
    limited.reset(None);
    assert_eq!(limited.elapsed_steps(), 0);
    limited
        .step(ActionType::Torque, &[])
        .expect("in the air again");
}

#[test]
fn a_substepped_step_over_the_limit_goes_back_to_where_it_started() {
    // In a fluid every substep detects its own contacts. The lower cube rests on the floor
    // (4 points, past half of a budget of 7 a substep: the step keeps a copy); the upper
    // one, from 32 mm, lands on it in the fifth substep of a step (as found by tracing),
    // and that step goes back.
    let doc = falling_cubes(&[0.0, 32.0], true);
    let mut limited = env(&doc, 7 * 5 + 4);
    let mut free = env(&doc, 0);
    let (overload, steps) = step_until_refused(&mut limited, 400);
    assert_eq!(overload.substeps_done, 0, "{overload:?}");
    assert!(overload.points > 7, "{overload:?}");
    let before = flat(&limited);
    for _ in 0..steps {
        free.step(ActionType::Torque, &[]).expect("free step");
    }
    assert_eq!(before, flat(&free), "the refused step was undone");
    limited.set_contact_work_limit(0);
    for _ in 0..50 {
        limited.step(ActionType::Torque, &[]).expect("no limit");
        free.step(ActionType::Torque, &[]).expect("free step");
    }
    assert_eq!(flat(&limited), flat(&free), "and left nothing behind");
}

#[test]
fn contacts_that_grow_past_the_limit_within_a_substepped_step_need_a_reset() {
    // Nothing touches before the landing step, so no copy is kept: a landing detected past
    // the step's first substep stops the step where it is, and the env must be reset.
    let mut env = env(&falling_cubes(&[20.0], true), 5);
    let (overload, _) = step_until_refused(&mut env, 400);
    assert!(overload.substeps_done > 0, "{overload:?}");
    let message = env.step(ActionType::Torque, &[]).unwrap_err();
    assert_eq!(message, EnvError::NeedsReset);
    env.reset(None);
    env.step(ActionType::Torque, &[]).expect("after a reset");
}
