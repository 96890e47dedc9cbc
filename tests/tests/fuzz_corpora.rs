//! The fuzz corpora (`fuzz/corpus/<target>/`, issue R2) replayed through the fuzz targets'
//! own bodies (`fuzz/src/targets.rs`) as an ordinary test: a regression on a known input is
//! caught without a fuzzing build. Prints how far the inputs of each corpus got.

// These requests are built in the flat form (`CreateEnvRequest.document_json`, …): the
// proto deprecates it for `options`, and the server still reads it (`server/src/convert/create.rs`).
#![allow(deprecated)]

#[path = "../../fuzz/src/targets.rs"]
#[allow(dead_code, unreachable_pub)]
mod targets;

#[path = "../../fuzz/src/requests.rs"]
#[allow(dead_code, unreachable_pub)]
mod requests;

#[path = "../../fuzz/src/mcp.rs"]
#[allow(dead_code, unreachable_pub)]
mod mcp;

use std::collections::BTreeMap;
use std::path::Path;

use targets::Reached;

/// Replays `fuzz/corpus/<target>/` (or `$GYMFLEET_FUZZ_CORPORA/<target>/`, e.g. a fuzzing
/// run's working corpus, to measure how far its inputs get).
fn replay(target: &str, run: fn(&[u8]) -> Reached) {
    let root = std::env::var_os("GYMFLEET_FUZZ_CORPORA").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus"),
        std::path::PathBuf::from,
    );
    let dir = root.join(target);
    let mut reached: BTreeMap<Reached, usize> = BTreeMap::new();
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("entry").path())
        .collect();
    paths.sort();
    for path in &paths {
        let data = std::fs::read(path).expect("read");
        // On a thread with the server's pool stack: that is where requests are
        // converted, and a debug build's MJCF conversion needs about 3 MiB at the deepest
        // body tree accepted (`gymfleet_import::MAX_BODY_DEPTH`).
        let got = std::thread::scope(|scope| {
            std::thread::Builder::new()
                .stack_size(gymfleet_batch::POOL_STACK_BYTES)
                .spawn_scoped(scope, || run(&data))
                .expect("a replay thread")
                .join()
        })
        .unwrap_or_else(|_| panic!("{target}: {} failed", path.display()));
        *reached.entry(got).or_default() += 1;
    }
    println!("{target}: {} inputs, reached {reached:?}", paths.len());
    assert!(!paths.is_empty(), "{target}: an empty corpus");
}

#[test]
fn the_assembly_document_corpus_replays() {
    replay("assembly_document", targets::assembly_document);
}

#[test]
fn the_mjcf_corpus_replays() {
    replay("mjcf", targets::mjcf);
}

#[test]
fn the_urdf_corpus_replays() {
    replay("urdf", targets::urdf);
}

#[test]
fn the_saved_state_corpus_replays() {
    replay("saved_state", targets::saved_state);
}

#[test]
fn the_saved_state_fields_corpus_replays() {
    replay("saved_state_fields", targets::saved_state_fields);
}

#[test]
fn the_assets_archive_corpus_replays() {
    replay("assets_archive", targets::assets_archive);
}

#[test]
fn the_create_env_request_corpus_replays() {
    replay("create_env_request", requests::create_env_request);
}

#[test]
fn the_step_batch_request_corpus_replays() {
    replay("step_batch_request", requests::step_batch_request);
}

#[test]
fn the_mcp_message_corpus_replays() {
    replay("mcp_message", mcp::mcp_message);
}

/// Writes the saved-state seeds (each model's env after a few driven steps) when
/// `GYMFLEET_WRITE_STATE_SEEDS` is set; a no-op otherwise.
#[test]
fn write_saved_state_seeds() {
    if std::env::var_os("GYMFLEET_WRITE_STATE_SEEDS").is_none() {
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus/saved_state");
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models");
    for entry in std::fs::read_dir(models).expect("models") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("read");
        let mut env = gymfleet_env::RobotEnv::from_json(&text, gymfleet_env::EnvConfig::default())
            .expect("env");
        let ones = vec![1e-3f32; env.spec().action_dim];
        for _ in 0..10 {
            env.step(gymfleet_env::ActionType::Torque, &ones)
                .expect("step");
        }
        let bytes = env.save().expect("save").encode();
        let name = path
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .to_string();
        std::fs::write(dir.join(format!("{name}.state")), bytes).expect("write");
    }
}

/// Writes the request and MCP seeds when `GYMFLEET_WRITE_REQUEST_SEEDS` is set; a no-op
/// otherwise. (The assets seeds are made by `fuzz/make_asset_seeds.py`.)
#[test]
fn write_request_seeds() {
    use gymfleet_proto::v1 as pb;
    use prost::Message;

    if std::env::var_os("GYMFLEET_WRITE_REQUEST_SEEDS").is_none() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus");
    let write = |target: &str, name: &str, bytes: Vec<u8>| {
        let dir = root.join(target);
        std::fs::create_dir_all(&dir).expect("mkdir");
        std::fs::write(dir.join(name), bytes).expect("write");
    };
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models");
    let pendulum = std::fs::read_to_string(models.join("pendulum.json")).expect("pendulum");
    for entry in std::fs::read_dir(&models).expect("models") {
        let path = entry.expect("entry").path();
        let request = pb::CreateEnvRequest {
            document_json: std::fs::read_to_string(&path).expect("read"),
            max_steps: 5,
            ..Default::default()
        };
        let stem = path
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .to_string();
        write(
            "create_env_request",
            &format!("{stem}.pb"),
            request.encode_to_vec(),
        );
    }
    let reach = pb::CreateEnvRequest {
        document_json: std::fs::read_to_string(models.join("arm2.json")).expect("arm2"),
        dt: 0.01,
        substeps: 2,
        seed: Some(7),
        reset_noise: Some(0.01),
        task: Some(pb::Task {
            kind: Some(pb::task::Kind::Reach(pb::ReachTask {
                target: Some(pb::Vec3 {
                    x: 100.0,
                    y: 0.0,
                    z: 50.0,
                }),
                ..Default::default()
            })),
            action_cost: 0.01,
        }),
        ..Default::default()
    };
    write("create_env_request", "arm2_reach.pb", reach.encode_to_vec());
    let mjcf = pb::CreateEnvRequest {
        document_json: r#"<mujoco><worldbody><body pos="0 0 1"><joint type="hinge" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05"/></body></worldbody></mujoco>"#.into(),
        ..Default::default()
    };
    write(
        "create_env_request",
        "mjcf_pendulum.pb",
        mjcf.encode_to_vec(),
    );
    let model = pb::CreateEnvRequest {
        model: "pendulum".into(),
        ..Default::default()
    };
    write(
        "create_env_request",
        "library_model.pb",
        model.encode_to_vec(),
    );

    let steps: [(&str, i32, Vec<f32>); 6] = [
        (
            "torque.pb",
            pb::ActionType::Torque as i32,
            vec![0.1, -0.1, 0.0, 1.0],
        ),
        (
            "position.pb",
            pb::ActionType::Position as i32,
            vec![10.0, -10.0, 0.0, 90.0],
        ),
        ("velocity.pb", pb::ActionType::Velocity as i32, vec![1.0; 4]),
        ("short.pb", pb::ActionType::Torque as i32, vec![0.0; 3]),
        (
            "nan.pb",
            pb::ActionType::Torque as i32,
            vec![f32::NAN, 0.0, 0.0, 0.0],
        ),
        ("huge.pb", pb::ActionType::Torque as i32, vec![1e30; 4]),
    ];
    for (name, action_type, actions) in steps {
        let request = pb::StepBatchRequest {
            batch_id: String::new(),
            action_type,
            actions,
            ..Default::default()
        };
        write("step_batch_request", name, request.encode_to_vec());
    }
    let unknown = pb::StepBatchRequest {
        batch_id: "batch_9".into(),
        action_type: pb::ActionType::Torque as i32,
        actions: vec![0.0; 4],
        ..Default::default()
    };
    write(
        "step_batch_request",
        "unknown_batch.pb",
        unknown.encode_to_vec(),
    );

    let call = |id: u32, tool: &str, arguments: serde_json::Value| {
        serde_json::json!({"jsonrpc": "2.0", "id": id, "method": "tools/call",
            "params": {"name": tool, "arguments": arguments}})
        .to_string()
    };
    let document: serde_json::Value = serde_json::from_str(&pendulum).expect("json");
    let sessions: [(&str, Vec<String>); 5] = [
        (
            "list.jsonl",
            vec![r#"{"jsonrpc":"2.0","id":1,"method":"tools/list"}"#.into()],
        ),
        (
            "env_session.jsonl",
            vec![
                call(
                    1,
                    "create_robot_env",
                    serde_json::json!({"document": document, "max_steps": 20}),
                ),
                call(
                    2,
                    "gym_reset",
                    serde_json::json!({"env_id": "sim_1", "seed": 3}),
                ),
                call(
                    3,
                    "gym_step",
                    serde_json::json!({"env_id": "sim_1", "action_type": "torque", "values": [0.001]}),
                ),
                call(4, "gym_observe", serde_json::json!({"env_id": "sim_1"})),
                call(5, "gym_save_state", serde_json::json!({"env_id": "sim_1"})),
                call(6, "gym_close", serde_json::json!({"env_id": "sim_1"})),
            ],
        ),
        (
            "batch_session.jsonl",
            vec![
                call(
                    1,
                    "batch_create_envs",
                    serde_json::json!({"document": document, "n_envs": 3, "max_steps": 5}),
                ),
                call(
                    2,
                    "batch_step",
                    serde_json::json!({"batch_id": "batch_1", "action_type": "torque", "actions": [[0.001], [0.0], [-0.001]]}),
                ),
                call(
                    3,
                    "batch_reset",
                    serde_json::json!({"batch_id": "batch_1", "seed": 1}),
                ),
                call(4, "batch_close", serde_json::json!({"batch_id": "batch_1"})),
            ],
        ),
        (
            "refusals.jsonl",
            vec![
                call(
                    1,
                    "gym_step",
                    serde_json::json!({"env_id": "sim_404", "action_type": "torque", "values": [0.0]}),
                ),
                call(2, "no_such_tool", serde_json::json!({})),
                call(
                    3,
                    "create_robot_env",
                    serde_json::json!({"document": {"parts": []}}),
                ),
                r#"{"jsonrpc":"2.0","id":4,"method":"no/such/method"}"#.into(),
            ],
        ),
        (
            "garbage.jsonl",
            vec![
                "not json at all".into(),
                r#"{"jsonrpc":"2.0","id":1,"method":"ping"}"#.into(),
                r#"{"jsonrpc":"2.0","method":"notifications/cancelled","params":{"requestId":1}}"#
                    .into(),
            ],
        ),
    ];
    for (name, lines) in sessions {
        write("mcp_message", name, lines.join("\n").into_bytes());
    }
}
