//! Heightfields in the assembly JSON (`{"type": "heightfield", ...}`, MJCF's `hfield`): a
//! ball dropped on terrain comes to rest on it where its heights put it, a replaced terrain
//! takes over at once, and bad heightfields are refused with their paths.

mod common;

use common::env_with;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv, Units};
use serde_json::{json, Value};

/// A 3 × 3 heightfield 400 × 400 mm, 100 mm at height 1, its centre point at `centre`,
/// the rest at 0; a 20 mm ball above the centre on a free body.
fn terrain(centre: f64, primitive_extra: Value) -> Value {
    let mut primitive = json!({
        "type": "heightfield", "rows": 3, "columns": 3,
        "size": {"x": 200, "y": 200, "z": 100},
        "heights": [0, 0, 0, 0, centre, 0, 0, 0, 0]
    });
    for (k, v) in primitive_extra.as_object().expect("fields") {
        primitive[k] = v.clone();
    }
    json!({
        "parts": [
            {"name": "Ground", "primitive": primitive},
            {"name": "Ball", "primitive": {"type": "sphere", "radius": 20}}
        ],
        "assembly": {
            "instances": [
                {"part": "Ground", "name": "ground"},
                {"part": "Ball", "name": "ball", "position": {"x": 0, "y": 0, "z": 200}}
            ]
        }
    })
}

fn env(doc: &Value) -> RobotEnv {
    env_with(
        doc,
        EnvConfig {
            dt: 0.005,
            units: Units::Si,
            ..EnvConfig::default()
        },
    )
}

/// The ball's height (m) after 1.5 s.
fn rest_height(e: &mut RobotEnv) -> f64 {
    for _ in 0..300 {
        e.step(ActionType::Torque, &[]).expect("steps");
    }
    f64::from(e.observe().free_body_poses[2])
}

#[test]
fn a_ball_comes_to_rest_on_the_terrains_peak() {
    // On the peak (a vertex, the terrain's highest point): its height plus the radius.
    let mut e = env(&terrain(0.5, json!({})));
    let z = rest_height(&mut e);
    assert!((z - (0.05 + 0.02)).abs() < 1e-3, "rests at {z} m");
    // The terrain raised to its full height (between episodes: a surface raised through a
    // body resting on it would leave the body beneath): the ball rests higher, episode
    // after episode.
    e.set_heightfield("ground", &[0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
        .expect("new heights");
    for episode in 0..2 {
        e.reset(Some(episode));
        let z = rest_height(&mut e);
        assert!(
            (z - (0.1 + 0.02)).abs() < 1e-3,
            "episode {episode}: rests at {z} m after the change"
        );
    }
}

#[test]
fn a_bad_heightfield_is_refused_with_its_path() {
    let cases = [
        (
            json!({"rows": 1}),
            "parts[0].primitive.rows: expected 2 to 1024 rows, got 1",
        ),
        (
            json!({"heights": [0, 0, 0]}),
            "parts[0].primitive.heights: expected rows × columns = 9 heights, got 3",
        ),
        (
            json!({"heights": [0, 0, 0, 0, 2, 0, 0, 0, 0]}),
            "parts[0].primitive.heights: height 4 is 2; heights are in [0, 1]",
        ),
        (
            json!({"size": {"x": 0, "y": 200, "z": 100}}),
            "parts[0].primitive.size.x: expected a positive length in mm, got 0",
        ),
        (
            json!({"file": "terrain.png"}),
            "parts[0].primitive.file: the heightfield's file \"terrain.png\" is read from the request's assets; none came with it",
        ),
    ];
    for (extra, expected) in cases {
        common::assert_refused(&terrain(0.5, extra), expected);
    }
    let mut e = env(&terrain(0.5, json!({})));
    let message = e
        .set_heightfield("ball", &[0.0; 9])
        .expect_err("not a heightfield")
        .to_string();
    assert_eq!(message, "unknown heightfield \"ball\" (known: \"ground\")");
}
