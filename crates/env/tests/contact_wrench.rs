//! The contact wrench on groups of instances (`contact_wrench`, MuJoCo's `cfrc_ext`) and the
//! contact cost: a cube resting on a plane is held up by its weight, about the robot's
//! centre of mass; what the cube gets, the plane gets back.

mod common;

use common::env_with;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, TaskKind, TaskSpec, TermsTask, Units};
use serde_json::json;

/// A 20 mm cube (8 g at 1000 kg/m³) 1 mm above a plane.
fn cube_doc() -> serde_json::Value {
    json!({
        "parts": [
            {"name": "Ground", "primitive": {"type": "plane"}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}
        ],
        "assembly": {"instances": [
            {"part": "Ground", "name": "ground"},
            {"part": "Cube", "name": "cube", "position": {"x": -10, "y": -10, "z": 1}}
        ]}
    })
}

/// The cube dropped onto the plane, with a terms task.
fn cube_on_plane(task: &str) -> RobotEnv {
    let doc = cube_doc();
    let config = EnvConfig {
        units: Units::Si,
        task: Some(TaskSpec {
            kind: TaskKind::Terms(TermsTask::from_json(task).expect("a terms task")),
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    env_with(&doc, config)
}

fn component(name: &str, instances: &str, k: usize) -> String {
    format!(
        r#"{{"name": "{name}", "weight": 0, "value": {{"contact_wrench": [{instances}], "component": {k}}}}}"#
    )
}

#[test]
fn a_resting_cube_is_held_up_by_its_weight_and_the_plane_gets_it_back() {
    let mut terms: Vec<String> = (0..6)
        .map(|k| component(&format!("cube{k}"), "\"cube\"", k))
        .collect();
    terms.extend((0..6).map(|k| component(&format!("ground{k}"), "\"ground\"", k)));
    terms.push(
        r#"{"name": "cost", "weight": -2, "contact_cost": {"groups": [["cube"]], "min": -0.05, "max": 0.05}}"#
            .to_string(),
    );
    let task = format!(r#"{{"terms": [{}]}}"#, terms.join(", "));
    let mut env = cube_on_plane(&task);
    let weight = 0.008 * 9.81;
    // Zero until the cube lands; a reset starts from zero again.
    env.step(ActionType::Torque, &[]).expect("steps");
    assert!(env.term_values()[..6].iter().all(|v| *v == 0.0));
    let mut reward = 0.0;
    for _ in 0..240 {
        reward = env
            .step(ActionType::Torque, &[])
            .expect("steps")
            .flags
            .reward;
    }
    let v: Vec<f64> = env.term_values().iter().map(|&v| f64::from(v)).collect();
    assert!(
        (v[5] - weight).abs() < 0.01 * weight,
        "the plane holds the cube up with {} N, its weight is {weight} N",
        v[5]
    );
    for k in [3, 4] {
        assert!(v[k].abs() < 1e-3 * weight, "sideways force {k}: {}", v[k]);
    }
    // About the robot's centre of mass, the cube's own: a symmetric support, no torque.
    for (k, torque) in v[..3].iter().enumerate() {
        assert!(torque.abs() < 1e-5, "torque {k}: {torque} N·m");
    }
    // The plane gets the opposite force (the robot's centre of mass is the cube's: the
    // torque about it is the same point's, opposite).
    for k in 0..6 {
        assert!(
            (v[k] + v[6 + k]).abs() < 1e-6,
            "component {k}: {} vs {}",
            v[k],
            v[6 + k]
        );
    }
    // The cost: each component clipped to ±0.05, squared, summed.
    let cost: f64 = v[..6].iter().map(|c| c.clamp(-0.05, 0.05).powi(2)).sum();
    assert!((v[12] - cost).abs() < 1e-7, "{} vs {cost}", v[12]);
    assert!((f64::from(reward) + 2.0 * v[12]).abs() < 1e-6);
    env.reset(Some(0));
    env.step(ActionType::Torque, &[]).expect("steps");
    assert!(env.term_values()[..6].iter().all(|v| *v == 0.0));
}

#[test]
fn a_contact_costs_sum_is_clipped_at_sum_max() {
    // Unclipped components: the sum is (m·g)²; `sum_max` at half of it caps it there.
    let weight: f64 = 0.008 * 9.81;
    let cap = weight * weight / 2.0;
    let task = format!(
        r#"{{"terms": [
            {{"name": "open", "weight": 0, "contact_cost": {{"groups": [["cube"]], "min": -1e9, "max": 1e9}}}},
            {{"name": "capped", "weight": -1, "contact_cost": {{"groups": [["cube"]], "min": -1e9, "max": 1e9, "sum_max": {cap}}}}}
        ]}}"#
    );
    let mut env = cube_on_plane(&task);
    let mut reward = 0.0;
    for _ in 0..240 {
        reward = env
            .step(ActionType::Torque, &[])
            .expect("steps")
            .flags
            .reward;
    }
    let v = env.term_values();
    let open = f64::from(v[0]);
    assert!(
        (open / (weight * weight) - 1.0).abs() < 0.02,
        "{open} vs {}",
        weight * weight
    );
    assert!((f64::from(v[1]) - cap).abs() < 1e-9, "{} vs {cap}", v[1]);
    assert!((f64::from(reward) + cap).abs() < 1e-7);
}

#[test]
fn bad_contact_terms_get_their_own_errors() {
    for (json, expected) in [
        (
            r#"{"terms": [{"name": "a", "value": {"contact_wrench": ["cube"]}}]}"#,
            "task.terms.terms[0].value.component: expected a component 0 to 5 (torque x, y, z, force x, y, z), got none",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"contact_wrench": ["cube"], "component": 6}}]}"#,
            "task.terms.terms[0].value.component: expected a component 0 to 5 (torque x, y, z, force x, y, z), got 6",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"joint_velocity": "x", "component": 1}}]}"#,
            "task.terms.terms[0].value.component: a component belongs to a contact_wrench, body_inertia, body_velocity or sensor",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"contact_wrench": ["cube", "cube"], "component": 1}}]}"#,
            "task.terms.terms[0].value.contact_wrench[1]: the instance is listed twice",
        ),
        (
            r#"{"terms": [{"name": "a", "value": {"contact_wrench": ["foot"], "component": 1}}]}"#,
            "task.terms.terms[0].value.contact_wrench[0]: unknown instance \"foot\" (known: \"ground\", \"cube\")",
        ),
        (
            r#"{"terms": [{"name": "a", "contact_cost": {"groups": [["cube"]], "min": 1, "max": -1}}]}"#,
            "task.terms.terms[0].contact_cost.max: expected max >= min = 1, got -1",
        ),
        (
            r#"{"terms": [{"name": "a", "contact_cost": {"groups": [["cube"], ["cube"], ["cube"]], "min": -1, "max": 1}}]}"#,
            "task.terms.terms[0].contact_cost.groups: expected at most the number of instances (2) groups, got 3",
        ),
    ] {
        let err = common::with_terms(&cube_doc().to_string(), json, EnvConfig::default())
            .err()
            .expect("refused")
            .to_string();
        assert_eq!(err, expected);
    }
}

/// Two overlapping bars in zero gravity: `a` on a hinge to the ground, `b` hinged to `a`
/// through a helper (1 mg, colliding with nothing when `helper_collides` is false), as an
/// MJCF body with two joints becomes. `a` also carries a welded cube that `b` overlaps.
fn overlapping(helper_collides: bool) -> serde_json::Value {
    let helper_collision = if helper_collides {
        json!({"group": 1, "mask": 1})
    } else {
        json!({"group": 0, "mask": 0})
    };
    json!({
        "simulation": {"gravity": {"x": 0, "y": 0, "z": 0}},
        "parts": [
            {"name": "Ground", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}},
            {"name": "Bar", "primitive": {"type": "cube", "size": {"x": 100, "y": 20, "z": 20}}},
            {"name": "Dot", "primitive": {"type": "sphere", "radius": 1}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Ground", "name": "ground", "position": {"x": -5, "y": -5, "z": -200}},
                {"part": "Bar", "name": "a", "position": {"x": 0, "y": 0, "z": 0}},
                {"part": "Cube", "name": "a_cube", "position": {"x": 80, "y": 0, "z": 10}},
                {"part": "Dot", "name": "helper", "position": {"x": 50, "y": 10, "z": 10},
                 "collision": helper_collision, "inertial": {"mass": 1e-6}},
                {"part": "Bar", "name": "b", "position": {"x": 40, "y": 0, "z": 10}}
            ],
            "joints": [
                {"type": "revolute", "name": "root", "parent": "ground", "child": "a",
                 "anchor": {"x": 0, "y": 10, "z": 10}, "axis": {"x": 0, "y": 0, "z": 1}},
                {"type": "fixed", "name": "weld", "parent": "a", "child": "a_cube"},
                {"type": "revolute", "name": "j1", "parent": "a", "child": "helper",
                 "anchor": {"x": 50, "y": 10, "z": 10}, "axis": {"x": 0, "y": 0, "z": 1}},
                {"type": "revolute", "name": "j2", "parent": "helper", "child": "b",
                 "anchor": {"x": 50, "y": 10, "z": 10}, "axis": {"x": 0, "y": 1, "z": 0}}
            ]
        }
    })
}

#[test]
fn a_body_does_not_collide_with_its_parent_through_helpers_nor_its_welded_parts() {
    let task = format!(
        r#"{{"terms": [{}]}}"#,
        (0..6)
            .map(|k| component(&format!("b{k}"), "\"b\"", k))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let run = |helper_collides: bool| -> f64 {
        let config = EnvConfig {
            units: Units::Si,
            task: Some(TaskSpec {
                kind: TaskKind::Terms(TermsTask::from_json(&task).expect("a terms task")),
                action_cost: 0.0,
            }),
            ..EnvConfig::default()
        };
        let mut env = env_with(&overlapping(helper_collides), config);
        let mut most = 0.0f64;
        for _ in 0..20 {
            env.step(ActionType::Torque, &[0.0, 0.0, 0.0])
                .expect("steps");
            most = env
                .term_values()
                .iter()
                .fold(most, |m, v| m.max(f64::from(v.abs())));
        }
        most
    };
    // MuJoCo's rule: b's parent body is a (the helper between them collides with
    // nothing), so b touches neither a nor a's welded cube.
    assert_eq!(run(false), 0.0, "b is kept apart from its parent body");
    // A helper that collides makes b a grandchild: then they collide (the control).
    assert!(
        run(true) > 0.0,
        "b and a collide when they are not parent and child"
    );
}
