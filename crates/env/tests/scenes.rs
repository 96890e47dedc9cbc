//! Scenes (issue Z1): static geometry, free bodies observed as MuJoCo observes a free
//! joint, contact exclusions and explicit pairs, ellipsoids, and mocap targets in saved
//! states.

use gymfleet_env::{ActionType, EnvConfig, RobotEnv, SavedState, Units};
use serde_json::{json, Value};

/// A 200 × 200 × 20 mm table top at z ∈ [0, 20] mm, fixed where it is (not the first
/// instance), and `objects` above it. Gravity is MuJoCo's.
fn on_a_table(objects: Value, extra: Value) -> Value {
    let mut instances = vec![
        json!({"part": "Anchor", "name": "anchor", "position": {"x": -500, "y": -500, "z": -500},
               "collision": {"group": 0, "mask": 0}}),
        json!({"part": "Top", "name": "table", "position": {"x": -100, "y": -100, "z": 0}, "fixed": true}),
    ];
    instances.extend(objects.as_array().expect("objects").iter().cloned());
    let mut doc = json!({
        "parts": [
            {"name": "Anchor", "primitive": {"type": "sphere", "radius": 1}},
            {"name": "Top", "primitive": {"type": "cube", "size": {"x": 200, "y": 200, "z": 20}}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}},
            {"name": "Egg", "primitive": {"type": "ellipsoid", "radii": {"x": 30, "y": 20, "z": 10}}}
        ],
        "assembly": {"instances": instances, "joints": []}
    });
    if let Some(contacts) = extra.get("contacts") {
        doc["assembly"]["contacts"] = contacts.clone();
    }
    doc
}

fn cube(name: &str, at: [f64; 3]) -> Value {
    json!({"part": "Cube", "name": name, "position": {"x": at[0], "y": at[1], "z": at[2]},
           "body_frame": {"position": {"x": 10, "y": 10, "z": 10}}})
}

fn env(doc: &Value, units: Units) -> RobotEnv {
    let config = EnvConfig {
        units,
        ..EnvConfig::default()
    };
    RobotEnv::from_json(&doc.to_string(), config).expect("builds")
}

fn run(env: &mut RobotEnv, seconds: f64) -> Vec<f32> {
    let steps = (seconds / env.spec().dt).round() as usize;
    let mut obs = Vec::new();
    for _ in 0..steps {
        let r = env.step(ActionType::Torque, &[]).expect("steps");
        obs = r.observation.to_flat();
    }
    obs
}

#[test]
fn free_objects_fall_as_free_joints_report_it_and_rest_on_static_geometry() {
    let doc = on_a_table(json!([cube("a", [-10.0, -10.0, 120.0])]), json!({}));
    let mut env = env(&doc, Units::Si);
    assert_eq!(env.spec().free_bodies, ["a"]);
    let layout: Vec<_> = env
        .spec()
        .observation_layout
        .iter()
        .map(|s| (s.name, s.size))
        .collect();
    assert_eq!(
        layout,
        [
            ("joint_positions", 0),
            ("joint_velocities", 0),
            ("free_body_poses", 7),
            ("free_body_velocities", 6),
            ("end_effector_poses", 0)
        ]
    );
    let start = env.reset(None);
    // The body frame: the cube's centre (its corner plus 10 mm), m.
    assert_eq!(start.free_body_poses, [0.0, 0.0, 0.13, 1.0, 0.0, 0.0, 0.0]);
    // In free fall for 0.1 s (before it meets the table): v = −g·t, z = z0 − g·t²/2.
    let obs = run(&mut env, 0.1);
    let (pose, velocity) = (&obs[0..7], &obs[7..13]);
    let g = 9.81f32;
    assert!((velocity[2] + g * 0.1).abs() < 1e-3, "{velocity:?}");
    // Semi-implicit Euler at substeps of h = 1/1200 s falls g·t·h/2 further.
    let h = 1.0 / 1200.0;
    let fallen = g * 0.01 / 2.0 + g * 0.1 * h / 2.0;
    assert!((pose[2] - (0.13 - fallen)).abs() < 1e-5, "{pose:?}");
    // At rest on the table: its centre 10 mm above the top.
    let obs = run(&mut env, 1.0);
    assert!((obs[2] - 0.03).abs() < 2e-4, "rests at z = {}", obs[2]);
    assert!(
        obs[7..13].iter().all(|v| v.abs() < 1e-3),
        "{:?}",
        &obs[7..13]
    );
}

#[test]
fn an_exclusion_lets_an_object_through_the_table_and_a_pair_sets_its_friction() {
    let objects = json!([cube("a", [-10.0, -10.0, 100.0])]);
    let falls = on_a_table(
        objects.clone(),
        json!({"contacts": {"exclude": [{"a": "table", "b": "a"}]}}),
    );
    let obs = run(&mut env(&falls, Units::Si), 0.5);
    assert!(
        obs[2] < -0.1,
        "excluded from the table, it falls through: z = {}",
        obs[2]
    );

    // An object that collides with nothing meets the table all the same through a pair.
    let mut ghost = objects.clone();
    ghost[0]["collision"] = json!({"group": 0, "mask": 0});
    let passes = on_a_table(ghost.clone(), json!({}));
    assert!(run(&mut env(&passes, Units::Si), 0.5)[2] < -0.1);
    let paired = on_a_table(
        ghost,
        json!({"contacts": {"pairs": [{"a": "table", "b": "a"}]}}),
    );
    let obs = run(&mut env(&paired, Units::Si), 1.0);
    assert!(
        (obs[2] - 0.03).abs() < 2e-4,
        "the pair holds it on the table: z = {}",
        obs[2]
    );

    // On a ground plane tilted 20° about x (tan 20° = 0.36): a frictionless pair lets the
    // cube slide down at g·sin 20°, a rough one (friction 1) holds it.
    let slide = |pair: Value| {
        let doc = json!({
            "parts": [
                {"name": "Ramp", "primitive": {"type": "plane"}},
                {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}
            ],
            "assembly": {
                "instances": [
                    {"part": "Ramp", "name": "ramp", "rotation": {"x": 20, "y": 0, "z": 0}},
                    {"part": "Cube", "name": "a", "rotation": {"x": 20, "y": 0, "z": 0},
                     "position": {"x": -10, "y": 0, "z": 0.05},
                     "collision": {"group": 0, "mask": 0}}
                ],
                "joints": [],
                "contacts": {"pairs": [pair]}
            }
        });
        let mut env = env(&doc, Units::Si);
        let obs = run(&mut env, 0.5);
        obs[7..10].iter().map(|v| v * v).sum::<f32>().sqrt()
    };
    let frictionless = slide(json!({"a": "ramp", "b": "a", "condim": 1}));
    let rough = slide(json!({"a": "ramp", "b": "a", "friction": 1.0}));
    let expected = 9.81 * 20f32.to_radians().sin() * 0.5;
    assert!(
        (frictionless / expected - 1.0).abs() < 0.05,
        "slides at {frictionless} m/s, frictionless {expected}"
    );
    assert!(rough < 1e-2, "held: {rough} m/s");
}

#[test]
fn an_ellipsoid_rests_on_its_flat_side() {
    let egg = json!([{"part": "Egg", "name": "egg", "position": {"x": 0, "y": 0, "z": 60}}]);
    let doc = on_a_table(egg, json!({}));
    let mut env = env(&doc, Units::Si);
    // Its mass is the ellipsoid's, at the default density of 1000 kg/m³.
    let exact = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.03 * 0.02 * 0.01;
    assert!(
        (env.spec().moving_mass / exact - 1.0).abs() < 1e-6,
        "{}",
        env.spec().moving_mass / exact
    );
    let obs = run(&mut env, 1.5);
    // Its centre 10 mm (its z semi-axis) above the top, within the polyhedron's 1 %.
    assert!((obs[2] - 0.03).abs() < 1.5e-4, "rests at z = {}", obs[2]);
}

#[test]
fn a_mocap_target_travels_in_a_saved_state() {
    let doc = json!({
        "parts": [
            {"name": "Anchor", "primitive": {"type": "sphere", "radius": 1}},
            {"name": "Paddle", "primitive": {"type": "cube", "size": {"x": 40, "y": 40, "z": 10}}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}
        ],
        "assembly": {"instances": [
            {"part": "Anchor", "name": "anchor", "collision": {"group": 0, "mask": 0}},
            {"part": "Paddle", "name": "paddle", "position": {"x": -20, "y": -20, "z": 0}, "mocap": true},
            {"part": "Cube", "name": "box", "position": {"x": -10, "y": -10, "z": 10}}
        ], "joints": []}
    });
    let mut a = env(&doc, Units::Document);
    a.reset(None);
    // The paddle lifts the box 50 mm over 0.25 s (its reference frame is its centre,
    // 5 mm up); the state is saved half way, its last target set.
    let lift = |a: &mut RobotEnv, k: usize| {
        let z = 5.0 + 50.0 * k as f32 / 60.0;
        a.set_mocap_pose("paddle", [0.0, 0.0, z, 1.0, 0.0, 0.0, 0.0])
            .unwrap();
        a.step(ActionType::Torque, &[]).unwrap();
    };
    for k in 1..=30 {
        lift(&mut a, k);
    }
    let bytes = a.save().expect("saves").encode();
    let mut b = env(&doc, Units::Document);
    b.load(&SavedState::decode(&bytes).unwrap()).expect("loads");
    for k in 31..=120 {
        lift(&mut a, k.min(60));
        lift(&mut b, k.min(60));
        assert_eq!(
            a.observe().to_flat(),
            b.observe().to_flat(),
            "the two envs part"
        );
    }
    let paddle = b.mocap_poses();
    assert!((paddle[2] - 55.0).abs() < 1e-3, "{paddle:?}");
    // The box's centre 10 mm above the paddle's top (60 mm).
    let resting = b.observe().free_body_poses;
    assert!(
        (resting[2] - 70.0).abs() < 0.2,
        "the box rides on the paddle: {resting:?}"
    );
}
