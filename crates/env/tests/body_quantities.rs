//! Body-level quantities as MuJoCo defines them, read as terms: a body's inertia about the
//! robot's centre of mass (`body_inertia`, MuJoCo's `cinert`), its velocity at that point
//! (`body_velocity`, `cvel`) and a joint's actuator force (`actuator_force`,
//! `qfrc_actuator`), checked against closed forms.

mod common;

use common::env_with;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, TaskKind, TaskSpec, TermsTask, Units};
use serde_json::{json, Value};

fn with_task(doc: &Value, terms: Vec<Value>, units: Units) -> RobotEnv {
    let task = json!({"terms": terms}).to_string();
    env_with(
        doc,
        EnvConfig {
            dt: 0.01,
            substeps: 10,
            units,
            task: Some(TaskSpec {
                kind: TaskKind::Terms(TermsTask::from_json(&task).expect("a terms task")),
                action_cost: 0.0,
            }),
            ..EnvConfig::default()
        },
    )
}

fn components(field: &str, group: &[&str], n: usize) -> Vec<Value> {
    (0..n)
        .map(|k| json!({"name": format!("{field}{k}"), "weight": 0, "value": {field: group, "component": k}}))
        .collect()
}

/// A free 100×100×20 mm slab with a 20 mm cube welded on its top corner region, no
/// gravity: one body of two instances.
fn slab_and_cube() -> Value {
    json!({
        "floating_base": true,
        "simulation": {"gravity": {"x": 0, "y": 0, "z": 0}},
        "parts": [
            {"name": "Slab", "primitive": {"type": "cube", "size": {"x": 100, "y": 100, "z": 20}}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Slab", "name": "slab", "position": {"x": 0, "y": 0, "z": 0}},
                {"part": "Cube", "name": "cube", "position": {"x": 60, "y": 20, "z": 20}}
            ],
            "joints": [{"type": "fixed", "name": "weld", "parent": "slab", "child": "cube"}]
        }
    })
}

/// A box's inertia about its centre (kg·m²) and its mass, edges in m, 1000 kg/m³.
fn box_inertia(a: f64, b: f64, c: f64) -> ([f64; 3], f64) {
    let m = 1000.0 * a * b * c;
    (
        [
            m * (b * b + c * c) / 12.0,
            m * (a * a + c * c) / 12.0,
            m * (a * a + b * b) / 12.0,
        ],
        m,
    )
}

#[test]
fn a_bodys_inertia_is_its_instances_summed_about_the_robots_centre_of_mass() {
    let mut env = with_task(
        &slab_and_cube(),
        components("body_inertia", &["slab", "cube"], 10),
        Units::Document,
    );
    env.step(ActionType::Torque, &[]).expect("steps");
    let got: Vec<f64> = env.term_values().iter().map(|&v| f64::from(v)).collect();
    // Centres (m) and the robot's centre of mass, about which cinert is taken.
    let (slab_i, slab_m) = box_inertia(0.1, 0.1, 0.02);
    let (cube_i, cube_m) = box_inertia(0.02, 0.02, 0.02);
    let centres = [[0.05, 0.05, 0.01], [0.07, 0.03, 0.03]];
    let masses = [slab_m, cube_m];
    let total = slab_m + cube_m;
    let com: Vec<f64> = (0..3)
        .map(|k| (slab_m * centres[0][k] + cube_m * centres[1][k]) / total)
        .collect();
    let mut expected = [0.0; 10];
    for (b, own) in [slab_i, cube_i].iter().enumerate() {
        let d: Vec<f64> = (0..3).map(|k| centres[b][k] - com[k]).collect();
        let m = masses[b];
        expected[0] += own[0] + m * (d[1] * d[1] + d[2] * d[2]);
        expected[1] += own[1] + m * (d[0] * d[0] + d[2] * d[2]);
        expected[2] += own[2] + m * (d[0] * d[0] + d[1] * d[1]);
        expected[3] -= m * d[0] * d[1];
        expected[4] -= m * d[0] * d[2];
        expected[5] -= m * d[1] * d[2];
        for k in 0..3 {
            expected[6 + k] += m * d[k];
        }
        expected[9] += m;
    }
    let scale = expected[0].abs();
    for k in 0..6 {
        assert!(
            (got[k] - expected[k]).abs() < 1e-4 * scale,
            "inertia {k}: {} vs {}",
            got[k],
            expected[k]
        );
    }
    for (k, offset) in got.iter().enumerate().take(9).skip(6) {
        assert!(
            offset.abs() < 1e-7,
            "the group is the whole robot: mass × offset {k} = {offset}"
        );
    }
    assert!(
        (got[9] / total - 1.0).abs() < 1e-5,
        "mass {} vs {total}",
        got[9]
    );
    // One instance alone: its own inertia shifted to the robot's centre of mass.
    let mut env = with_task(
        &slab_and_cube(),
        components("body_inertia", &["cube"], 10),
        Units::Si,
    );
    env.step(ActionType::Torque, &[]).expect("steps");
    let got = env.term_values();
    let d: Vec<f64> = (0..3).map(|k| centres[1][k] - com[k]).collect();
    for k in 0..3 {
        let want = cube_m * d[k];
        assert!(
            (f64::from(got[6 + k]) - want).abs() < 1e-6 * cube_m,
            "offset {k}: {} vs {want}",
            got[6 + k]
        );
    }
}

/// Two spheres on vertical hinges through their centres, 200 mm apart, no gravity: the
/// robot's centre of mass stays midway.
fn turntables() -> Value {
    json!({
        "simulation": {"gravity": {"x": 0, "y": 0, "z": 0}},
        "parts": [
            {"name": "Post", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": 50}}
        ],
        "assembly": {
            "instances": [
                {"part": "Post", "name": "post", "position": {"x": -5, "y": -5, "z": -200}},
                {"part": "Ball", "name": "a", "position": {"x": 0, "y": 0, "z": 0}},
                {"part": "Ball", "name": "b", "position": {"x": 200, "y": 0, "z": 0}}
            ],
            "joints": [
                {"type": "revolute", "name": "spin_a", "parent": "post", "child": "a", "gear": 2, "max_effort": 0.01,
                 "anchor": {"x": 0, "y": 0, "z": 0}, "axis": {"x": 0, "y": 0, "z": 1}},
                {"type": "revolute", "name": "spin_b", "parent": "post", "child": "b", "actuated": false,
                 "anchor": {"x": 200, "y": 0, "z": 0}, "axis": {"x": 0, "y": 0, "z": 1}}
            ]
        }
    })
}

#[test]
fn a_bodys_velocity_is_taken_at_the_robots_centre_of_mass() {
    let mut env = with_task(
        &turntables(),
        components("body_velocity", &["a"], 6),
        Units::Document,
    );
    for _ in 0..20 {
        env.step(ActionType::Torque, &[0.002]).expect("steps");
    }
    let w = f64::from(env.observe().joint_velocities[0]).to_radians();
    assert!(w > 0.1, "it spins: {w} rad/s");
    let got: Vec<f64> = env.term_values().iter().map(|&v| f64::from(v)).collect();
    // ω ẑ, and the velocity of a's point at (0.1, 0, 0): ω ẑ × (0.1, 0, 0) = (0, 0.1·ω, 0).
    let expected = [0.0, 0.0, w, 0.0, 0.1 * w, 0.0];
    for k in 0..6 {
        assert!(
            (got[k] - expected[k]).abs() < 1e-4 * w,
            "component {k}: {} vs {}",
            got[k],
            expected[k]
        );
    }
}

#[test]
fn the_actuator_force_is_gear_times_the_action_within_max_effort() {
    let terms = vec![
        json!({"name": "fa", "weight": 0, "value": {"actuator_force": "spin_a"}}),
        json!({"name": "fb", "weight": 0, "value": {"actuator_force": "spin_b"}}),
    ];
    let mut env = with_task(&turntables(), terms.clone(), Units::Document);
    for (action, expected) in [
        (0.002f32, 0.004),
        (-0.003, -0.006),
        (0.5, 0.01),
        (-0.5, -0.01),
    ] {
        env.step(ActionType::Torque, &[action]).expect("steps");
        let got = env.term_values();
        assert!(
            (f64::from(got[0]) - expected).abs() < 1e-7,
            "{action}: {} vs {expected}",
            got[0]
        );
        assert_eq!(got[1], 0.0, "a passive joint has no actuator force");
    }
    // Under position targets Rapier's motors do the work: reported as 0.
    env.step(ActionType::Position, &[10.0]).expect("steps");
    assert_eq!(env.term_values()[0], 0.0);
}

#[test]
fn bad_body_terms_get_their_own_errors() {
    let refused = |term: Value| {
        let task = json!({"terms": [term]}).to_string();
        common::with_terms(&turntables().to_string(), &task, EnvConfig::default())
            .err()
            .expect("refused")
            .to_string()
    };
    let cases = [
        (
            json!({"name": "x", "value": {"body_inertia": ["a"], "component": 10}}),
            "task.terms.terms[0].value.component: expected a component 0 to 9 (inertia (xx, yy, zz, xy, xz, yz), mass × offset (x, y, z), mass), got 10",
        ),
        (
            json!({"name": "x", "value": {"body_velocity": ["a"]}}),
            "task.terms.terms[0].value.component: expected a component 0 to 5 (angular velocity (x, y, z), linear velocity (x, y, z)), got none",
        ),
        (
            json!({"name": "x", "value": {"body_velocity": ["zz"], "component": 0}}),
            "task.terms.terms[0].value.body_velocity[0]: unknown instance \"zz\"",
        ),
        (
            json!({"name": "x", "value": {"actuator_force": "nope"}}),
            "task.terms.terms[0].value.actuator_force: unknown joint \"nope\"",
        ),
        (
            json!({"name": "x", "value": {"joint": "spin_a", "component": 1}}),
            "task.terms.terms[0].value.component: a component belongs to a contact_wrench, body_inertia, body_velocity or sensor",
        ),
    ];
    for (term, expected) in cases {
        let message = refused(term);
        assert!(
            message.contains(expected),
            "{message}\nexpected: {expected}"
        );
    }
}

#[test]
fn observed_terms_are_the_observations_terms_segment_at_resets_and_steps() {
    let mut terms = components("body_velocity", &["a"], 6);
    for t in terms.iter_mut() {
        t["observe"] = json!(true);
    }
    terms.insert(
        0,
        json!({"name": "spin", "weight": 1, "velocity": {"joint": "spin_a"}}),
    );
    terms.push(json!({"name": "mass", "weight": 0, "observe": true, "value": {"body_inertia": ["a"], "component": 9}}));
    let mut env = with_task(&turntables(), terms, Units::Si);
    let spec = env.spec();
    assert_eq!(
        spec.observation_layout.last().map(|s| (s.name, s.size)),
        Some(("terms", 7))
    );
    // At a reset: read from the state (at rest: no velocity; the mass is there).
    let o = env.reset(Some(0));
    let mass = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.05f64.powi(3);
    assert_eq!(&o.task[..6], &[0.0; 6]);
    assert!(
        (f64::from(o.task[6]) / mass - 1.0).abs() < 1e-5,
        "{:?}",
        o.task
    );
    assert!(
        env.term_values().iter().all(|v| *v == 0.0),
        "term values stay 0 until a step"
    );
    // After a step: the step's term values, in term order.
    for _ in 0..5 {
        let r = env.step(ActionType::Torque, &[0.002]).expect("steps");
        assert_eq!(r.observation.task, env.term_values()[1..]);
    }
    // Only value terms can be observed.
    let bad = json!({"terms": [{"name": "x", "observe": true, "velocity": {"joint": "spin_a"}}]})
        .to_string();
    let message = common::with_terms(&turntables().to_string(), &bad, EnvConfig::default())
        .err()
        .expect("refused")
        .to_string();
    assert!(
        message.contains("task.terms.terms[0].observe: only a value term can be observed (its coordinate is read from the state)"),
        "{message}"
    );
}
