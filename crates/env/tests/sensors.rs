//! Sensors (`assembly.sensors`, MJCF's `<sensor>`): MuJoCo's readings on the world's
//! state, checked here against closed forms (a cube resting on a touch pad, one falling
//! freely, a cantilever's root force and torque), read through `RobotEnv::bodies` and as a
//! terms task's observed terms, and each bad sensor's error.

mod common;

use gymfleet_env::{
    ActionType, EnvConfig, EnvError, RobotEnv, TaskKind, TaskSpec, TermsTask, Units,
};
use serde_json::{json, Value};

use common::G;
/// A 20 mm cube of water density.
const CUBE_MASS: f64 = 0.02 * 0.02 * 0.02 * 1000.0;

/// A fixed 200 × 200 × 20 mm table (top at z = 20 mm) with a pad site at its top centre,
/// a cube `rest` resting on it, and a cube `fall` far off the table's side, falling; the
/// cubes have sites at their bottom centres, `fall`'s turned to look down.
fn scene(sensors: Value) -> Value {
    json!({
        "parts": [
            {"name": "Anchor", "primitive": {"type": "sphere", "radius": 1}},
            {"name": "Top", "primitive": {"type": "cube", "size": {"x": 200, "y": 200, "z": 20}}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Anchor", "name": "anchor", "position": {"x": -500, "y": -500, "z": -500},
                 "collision": {"group": 0, "mask": 0}},
                {"part": "Top", "name": "table", "position": {"x": -100, "y": -100, "z": 0}, "fixed": true},
                {"part": "Cube", "name": "rest", "position": {"x": -10, "y": -10, "z": 20}},
                {"part": "Cube", "name": "fall", "position": {"x": 2000, "y": 0, "z": 5000}}
            ],
            "joints": [],
            "sites": [
                {"name": "pad", "instance": "table", "point": {"x": 100, "y": 100, "z": 20}},
                {"name": "pad_zone", "instance": "table", "point": {"x": 100, "y": 100, "z": 20},
                 "volume": {"type": "box", "size": {"x": 15, "y": 15, "z": 2}}},
                {"name": "pad_corner", "instance": "table", "point": {"x": 10, "y": 10, "z": 20},
                 "volume": {"type": "sphere", "size": {"x": 5, "y": 5, "z": 5}}},
                {"name": "rest_bottom", "instance": "rest", "point": {"x": 10, "y": 10, "z": 0}},
                {"name": "rest_top", "instance": "rest", "point": {"x": 10, "y": 10, "z": 20}},
                {"name": "fall_bottom", "instance": "fall", "point": {"x": 10, "y": 10, "z": 0},
                 "rotation": {"x": 180, "y": 0, "z": 0}}
            ],
            "sensors": sensors
        }
    })
}

fn env(doc: &Value) -> RobotEnv {
    let config = EnvConfig {
        units: Units::Si,
        ..EnvConfig::default()
    };
    RobotEnv::from_json(&doc.to_string(), config).expect("builds")
}

fn run(env: &mut RobotEnv, seconds: f64) {
    let steps = (seconds / env.spec().dt).round() as usize;
    let zeros = vec![0.0; env.spec().action_dim];
    for _ in 0..steps {
        env.step(ActionType::Torque, &zeros).expect("steps");
    }
}

/// The readings of sensor `name`.
fn reading(env: &RobotEnv, name: &str) -> Vec<f64> {
    let bodies = env.bodies();
    let mut at = 0;
    for (n, _, dim) in &bodies.sensors {
        if n == name {
            return bodies.sensor_data[at..at + dim].to_vec();
        }
        at += dim;
    }
    panic!("no sensor {name}");
}

fn close(got: &[f64], want: &[f64], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= tol,
            "{what}[{k}]: {g}, expected {w} (all: {got:?})"
        );
    }
}

fn scene_sensors() -> Value {
    json!([
        {"name": "pad_touch", "type": "touch", "site": "pad"},
        {"name": "pad_capped", "type": "touch", "site": "pad", "cutoff": 0.05},
        {"name": "pad_zone", "type": "touch", "site": "pad_zone"},
        {"name": "pad_corner", "type": "touch", "site": "pad_corner"},
        {"name": "rest_touch", "type": "touch", "site": "rest_bottom"},
        {"name": "fall_touch", "type": "touch", "site": "fall_bottom"},
        {"name": "rest_acc", "type": "accelerometer", "site": "rest_bottom", "noise": 0.01},
        {"name": "fall_acc", "type": "accelerometer", "site": "fall_bottom"},
        {"name": "fall_linacc", "type": "framelinacc", "site": "fall_bottom"},
        {"name": "fall_angacc", "type": "frameangacc", "site": "fall_bottom"},
        {"name": "fall_range", "type": "rangefinder", "site": "fall_bottom"},
        {"name": "rest_range", "type": "rangefinder", "site": "rest_top"},
        {"name": "fall_pos", "type": "framepos", "site": "fall_bottom"},
        {"name": "fall_quat", "type": "framequat", "site": "fall_bottom"},
        {"name": "fall_z", "type": "framezaxis", "site": "fall_bottom"},
        {"name": "fall_vel", "type": "velocimeter", "site": "fall_bottom"},
        {"name": "fall_linvel", "type": "framelinvel", "site": "fall_bottom"},
        {"name": "fall_gyro", "type": "gyro", "site": "fall_bottom"},
        {"name": "fall_mag", "type": "magnetometer", "site": "fall_bottom"},
        {"name": "fall_from_rest", "type": "framepos", "site": "fall_bottom",
         "reference": {"instance": "rest"}},
        {"name": "fall_com", "type": "subtreecom", "instance": "fall"},
        {"name": "fall_comvel", "type": "subtreelinvel", "instance": "fall"},
        {"name": "fall_angmom", "type": "subtreeangmom", "instance": "fall"}
    ])
}

#[test]
fn a_resting_cube_weighs_on_its_pad_and_a_falling_one_reads_free_fall() {
    let mut env = env(&scene(scene_sensors()));
    let spec_names: Vec<&str> = env.spec().sensors.iter().map(|s| s.0.as_str()).collect();
    assert_eq!(spec_names.len(), 23);
    assert_eq!(env.spec().sensors[0], ("pad_touch".to_string(), "touch", 1));
    assert_eq!(
        env.spec().sensors[13],
        ("fall_quat".to_string(), "framequat", 4)
    );
    // After a reset no contact has acted and nothing has accelerated: the accelerometers
    // read −gravity.
    close(
        &reading(&env, "pad_touch"),
        &[0.0],
        0.0,
        "touch after reset",
    );
    close(
        &reading(&env, "fall_acc"),
        &[0.0, 0.0, -G],
        1e-5,
        "fall_acc after reset",
    );
    run(&mut env, 0.5);
    let weight = CUBE_MASS * G;
    close(
        &reading(&env, "pad_touch"),
        &[weight],
        0.02 * weight,
        "pad touch",
    );
    close(
        &reading(&env, "rest_touch"),
        &[weight],
        0.02 * weight,
        "rest touch",
    );
    close(
        &reading(&env, "pad_capped"),
        &[0.05],
        1e-12,
        "touch cut off at 0.05 N",
    );
    // A pad's volume counts the contacts inside it: all of the cube's, or none.
    close(
        &reading(&env, "pad_zone"),
        &[weight],
        0.02 * weight,
        "the cube is on the zone",
    );
    close(
        &reading(&env, "pad_corner"),
        &[0.0],
        0.0,
        "nothing in the table's corner",
    );
    close(
        &reading(&env, "fall_touch"),
        &[0.0],
        0.0,
        "nothing touches the falling cube",
    );
    // At rest the accelerometer reads the support's push, +g up; in free fall, nothing.
    close(
        &reading(&env, "rest_acc"),
        &[0.0, 0.0, G],
        0.02 * G,
        "resting accelerometer",
    );
    // The falling site looks down (turned 180° about x): its axes are (x, −y, −z).
    close(
        &reading(&env, "fall_acc"),
        &[0.0; 3],
        1e-3,
        "accelerometer in free fall",
    );
    close(
        &reading(&env, "fall_linacc"),
        &[0.0, 0.0, -G],
        1e-3,
        "free fall's acceleration",
    );
    close(
        &reading(&env, "fall_angacc"),
        &[0.0; 3],
        1e-3,
        "no angular acceleration",
    );
    let pos = reading(&env, "fall_pos");
    let t = env.elapsed_steps() as f64 * env.spec().dt;
    // Semi-implicit Euler falls a little further than ½·g·t² (by ½·g·t·h per substep h).
    close(
        &pos,
        &[2.01, 0.01, 5.0 - 0.5 * G * t * t],
        5e-3,
        "the falling site",
    );
    // The ground is the table only: the falling cube is off its side; the resting cube's
    // top site looks up (its +z) into open air.
    close(
        &reading(&env, "fall_range"),
        &[-1.0],
        0.0,
        "nothing below the falling cube",
    );
    close(
        &reading(&env, "rest_range"),
        &[-1.0],
        0.0,
        "nothing above the resting one",
    );
    let q = reading(&env, "fall_quat");
    close(&q, &[0.0, 1.0, 0.0, 0.0], 1e-5, "turned 180° about x");
    close(
        &reading(&env, "fall_z"),
        &[0.0, 0.0, -1.0],
        1e-5,
        "looking down",
    );
    let v = G * t;
    close(
        &reading(&env, "fall_linvel"),
        &[0.0, 0.0, -v],
        1e-3,
        "world velocity",
    );
    close(
        &reading(&env, "fall_vel"),
        &[0.0, 0.0, v],
        1e-3,
        "velocity in the site's axes",
    );
    close(&reading(&env, "fall_gyro"), &[0.0; 3], 1e-6, "no spin");
    close(
        &reading(&env, "fall_mag"),
        &[0.0, 0.5, 0.0],
        1e-6,
        "MuJoCo's field in its axes",
    );
    let from_rest = reading(&env, "fall_from_rest");
    close(
        &from_rest,
        &[2.02, 0.02, pos[2] - 0.02],
        2e-3,
        "relative to the resting cube",
    );
    let com = reading(&env, "fall_com");
    close(
        &com,
        &[pos[0], pos[1], pos[2] + 0.01],
        1e-5,
        "the cube's centre",
    );
    close(
        &reading(&env, "fall_comvel"),
        &[0.0, 0.0, -v],
        1e-3,
        "its velocity",
    );
    close(
        &reading(&env, "fall_angmom"),
        &[0.0; 3],
        1e-9,
        "no angular momentum",
    );
}

#[test]
fn a_rangefinder_sees_the_table_below_and_its_reading_tracks_the_fall() {
    let mut doc = scene(json!([
        {"name": "range", "type": "rangefinder", "site": "fall_bottom"},
        {"name": "pos", "type": "framepos", "site": "fall_bottom"}
    ]));
    // Over the table this time, and over the resting cube (its top at z = 40 mm).
    doc["assembly"]["instances"][3]["position"] = json!({"x": -10, "y": -10, "z": 520});
    let mut env = env(&doc);
    for _ in 0..3 {
        run(&mut env, 0.05);
        let z = reading(&env, "pos")[2];
        close(
            &reading(&env, "range"),
            &[z - 0.04],
            1e-5,
            "height over the resting cube",
        );
    }
}

/// A grounded post and a 100 × 10 × 10 mm beam welded to its side, along +x from the
/// weld at (0, 0, 100) mm: a cantilever, with a site at the beam's root.
fn cantilever() -> Value {
    json!({
        "parts": [
            {"name": "Post", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 100}}},
            {"name": "Beam", "primitive": {"type": "cube", "size": {"x": 100, "y": 10, "z": 10}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Post", "name": "post", "position": {"x": -10, "y": -5, "z": 0}},
                {"part": "Beam", "name": "beam", "position": {"x": 0, "y": -5, "z": 95}}
            ],
            "joints": [{"type": "fixed", "parent": "post", "child": "beam"}],
            "sites": [{"name": "root", "instance": "beam", "point": {"x": 0, "y": 5, "z": 5}}],
            "sensors": [
                {"name": "root_force", "type": "force", "site": "root"},
                {"name": "root_torque", "type": "torque", "site": "root"}
            ]
        }
    })
}

#[test]
fn a_cantilever_root_carries_the_beams_weight_and_moment() {
    let mut env = env(&cantilever());
    run(&mut env, 0.05);
    let m = 0.1 * 0.01 * 0.01 * 1000.0;
    // The post holds the beam up with m·g, and against its moment about the root:
    // (0.05, 0, 0) × (0, 0, m·g).
    close(
        &reading(&env, "root_force"),
        &[0.0, 0.0, m * G],
        1e-6,
        "root force",
    );
    close(
        &reading(&env, "root_torque"),
        &[0.0, -0.05 * m * G, 0.0],
        1e-6,
        "root torque",
    );
}

#[test]
fn a_hanging_pendulum_is_held_up_and_its_joint_sensors_read_the_state() {
    let mut doc = common::hanging_pendulum(json!({"name": "pivot", "max_effort": 1}));
    doc["assembly"]["sites"] =
        json!([{"name": "top", "instance": "arm", "point": {"x": 2, "y": 2, "z": 40}}]);
    doc["assembly"]["sensors"] = json!([
        {"name": "angle", "type": "jointpos", "joint": "pivot"},
        {"name": "rate", "type": "jointvel", "joint": "pivot"},
        {"name": "drive", "type": "actuatorfrc", "actuator": "pivot"},
        {"name": "hold", "type": "force", "site": "top"}
    ]);
    let mut env = env(&doc);
    run(&mut env, 0.2);
    let m = 0.004 * 0.004 * 0.04 * 1000.0;
    close(
        &reading(&env, "hold"),
        &[0.0, 0.0, m * G],
        1e-3 * m * G,
        "the pivot holds it",
    );
    close(&reading(&env, "angle"), &[0.0], 1e-6, "hanging straight");
    // A torque turns it: the sensors read the observation's joint state, and the drive.
    env.step(ActionType::Torque, &[0.001]).expect("steps");
    let obs = env.observe().to_flat();
    let (angle, rate) = (reading(&env, "angle")[0], reading(&env, "rate")[0]);
    close(
        &[angle, rate],
        &[f64::from(obs[0]), f64::from(obs[1])],
        1e-7,
        "joint state",
    );
    assert!(rate > 0.0, "turning: {rate}");
    close(&reading(&env, "drive"), &[0.001], 1e-9, "the drive's force");
}

#[test]
fn a_terms_task_observes_and_rewards_sensor_components() {
    let task = r#"{"terms": [
        {"name": "acc_z", "weight": 2, "value": {"sensor": "rest_acc", "component": 2}, "observe": true},
        {"name": "touch", "weight": 0, "value": {"sensor": "pad_touch"}, "observe": true}
    ]}"#;
    let config = EnvConfig {
        units: Units::Si,
        task: Some(TaskSpec {
            kind: TaskKind::Terms(TermsTask::from_json(task).expect("task")),
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    let mut env = RobotEnv::from_json(&scene(scene_sensors()).to_string(), config).expect("env");
    let mut result = None;
    for _ in 0..(0.5 / env.spec().dt) as usize {
        result = Some(env.step(ActionType::Torque, &[]).expect("steps"));
    }
    let result = result.expect("stepped");
    let flat = result.observation.to_flat();
    let observed = &flat[flat.len() - 2..];
    let acc = reading(&env, "rest_acc")[2];
    let touch = reading(&env, "pad_touch")[0];
    close(
        &[f64::from(observed[0]), f64::from(observed[1])],
        &[acc, touch],
        1e-5,
        "observed terms",
    );
    let reward = f64::from(result.flags.reward);
    assert!((reward - 2.0 * acc).abs() < 1e-4, "reward {reward}");
}

fn scene_error(sensors: Value) -> String {
    let config = EnvConfig::default();
    match RobotEnv::from_json(&scene(sensors).to_string(), config) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted"),
    }
}

#[test]
fn each_bad_sensor_gets_its_own_error() {
    for (sensor, expected) in [
        (
            json!({"name": "s", "type": "touch", "site": "nowhere"}),
            "assembly.sensors[0].site: unknown site \"nowhere\" (known: \"pad\", \"pad_zone\", \"pad_corner\", \"rest_bottom\", \"rest_top\", \"fall_bottom\")",
        ),
        (
            json!({"name": "s", "type": "touch", "instance": "rest"}),
            "assembly.sensors[0].instance: a touch sensor reads a site, not a instance",
        ),
        (
            json!({"name": "s", "type": "framepos"}),
            "assembly.sensors[0]: a framepos sensor needs exactly one site or one instance",
        ),
        (
            json!({"name": "s", "type": "jointpos", "joint": "hinge"}),
            "assembly.sensors[0].joint: unknown joint \"hinge\" (known: none)",
        ),
        (
            json!({"name": "s", "type": "accelerometer", "site": "pad", "reference": {"site": "pad"}}),
            "assembly.sensors[0].reference: a accelerometer sensor has no reference frame",
        ),
        (
            json!({"name": "s", "type": "framelinvel", "site": "pad", "reference": {}}),
            "assembly.sensors[0].reference: expected exactly one of site or instance",
        ),
        (
            json!({"name": "s", "type": "gyro", "site": "pad", "cutoff": -1}),
            "assembly.sensors[0].cutoff: expected a number in [0, 1e12], got -1",
        ),
        (
            json!({"name": "s", "type": "actuatorfrc", "actuator": "x"}),
            "assembly.sensors[0].actuator: unknown actuator \"x\" (actuators and directly actuated joints: none)",
        ),
        (
            json!({"name": "s", "type": "framelinacc", "site": "pad", "reference": {"site": "pad"}}),
            "assembly.sensors[0].reference: a framelinacc sensor has no reference frame",
        ),
        (
            json!({"name": "s", "type": "subtreecom", "instance": "ghost"}),
            "assembly.sensors[0].instance: unknown instance \"ghost\"",
        ),
    ] {
        let error = scene_error(json!([sensor]));
        assert!(error.contains(expected), "{error}\nexpected: {expected}");
    }
    let twice = scene_error(json!([
        {"name": "s", "type": "touch", "site": "pad"},
        {"name": "s", "type": "gyro", "site": "pad"}
    ]));
    assert!(
        twice.contains("assembly.sensors[1].name: \"s\" names an earlier sensor too"),
        "{twice}"
    );
}

#[test]
fn a_task_names_a_sensor_and_its_component_or_gets_an_error() {
    for (term, expected) in [
        (
            r#"{"sensor": "nope"}"#,
            "task.terms.terms[0].value.sensor: unknown sensor \"nope\"",
        ),
        (
            r#"{"sensor": "rest_acc"}"#,
            "task.terms.terms[0].value.component: sensor \"rest_acc\" (accelerometer) reports 3 values: expected a component 0 to 2, got none",
        ),
        (
            r#"{"sensor": "fall_quat", "component": 4}"#,
            "task.terms.terms[0].value.component: sensor \"fall_quat\" (framequat) reports 4 values: expected a component 0 to 3, got 4",
        ),
        (
            r#"{"sensor": "pad_touch", "axis": "x"}"#,
            "task.terms.terms[0].value: a sensor takes no axis or point",
        ),
    ] {
        let task = format!(r#"{{"terms": [{{"name": "a", "value": {term}}}]}}"#);
        match common::with_terms(
            &scene(scene_sensors()).to_string(),
            &task,
            EnvConfig::default(),
        ) {
            Err(e @ EnvError::BadTask { .. }) => {
                let e = e.to_string();
                assert!(e.contains(expected), "{e}\nexpected: {expected}");
            }
            Err(other) => panic!("not a task error: {other}"),
            Ok(_) => panic!("accepted: {term}"),
        }
    }
}

#[test]
fn readings_are_bit_equal_across_a_clone_and_a_saved_state_after_the_next_step() {
    let mut env = env(&scene(scene_sensors()));
    run(&mut env, 0.2);
    // Saving re-seats the env from its state (as a load does): a clone taken after it
    // continues alike.
    let saved = env.save().expect("saves");
    let mut copy = env.clone();
    let mut restored = RobotEnv::from_state(&saved).expect("restores");
    // The kinematic readings come back at once; the accelerations after the next step.
    assert_eq!(reading(&restored, "fall_pos"), reading(&env, "fall_pos"));
    for _ in 0..5 {
        for e in [&mut env, &mut copy, &mut restored] {
            e.step(ActionType::Torque, &[]).expect("steps");
        }
    }
    let bits = |e: &RobotEnv| {
        e.bodies()
            .sensor_data
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&copy), bits(&env));
    assert_eq!(bits(&restored), bits(&env));
}
