//! Inputs that once crashed the server, replayed against a real one. Each input is kept
//! in a fuzz corpus too (`fuzz/corpus/`), so `fuzz_corpora.rs` and every fuzzing run
//! start from it.

// These requests are built in the flat form (`CreateEnvRequest.document_json`, …): the
// proto deprecates it for `options`, and the server still reads it (`server/src/convert/create.rs`).
#![allow(deprecated)]

use gymfleet_e2e::{TestServer, PENDULUM};
use gymfleet_proto::v1 as pb;
use gymfleet_server::ServerConfig;
use pb::simulator_client::SimulatorClient;
use tonic::Code;

/// An MJCF model whose bodies nest `depth` deep, each with a sphere; the outermost
/// hangs on a hinge, the others are welded to their parents.
fn nested_bodies(depth: usize) -> String {
    format!(
        r#"<mujoco><worldbody><body pos="0 0 1"><joint name="hinge" type="hinge" axis="0 1 0"/><geom type="sphere" size="0.01"/>{}{}</body></worldbody><actuator><motor joint="hinge" gear="1"/></actuator></mujoco>"#,
        r#"<body pos="0 0 0.01"><geom type="sphere" size="0.01"/>"#.repeat(depth - 1),
        "</body>".repeat(depth - 1)
    )
}

fn create(document: String) -> pb::CreateEnvRequest {
    pb::CreateEnvRequest {
        document_json: document,
        max_steps: 2,
        ..Default::default()
    }
}

/// Found while bounding the work of a deep MJCF tree (issue R2): the converter recursed
/// once per nested `<body>`, so 400 nested bodies (13 KB) overflowed a 2 MiB pool thread
/// of a debug server, and a 2.6 MB document any build, aborting the whole process. Now
/// bodies nest at most `MAX_BODY_DEPTH` (512) deep, and the pool's threads have 16 MiB
/// stacks, so the deepest accepted tree converts and builds.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn mjcf_bodies_nested_past_the_bound_are_refused_not_a_stack_overflow() {
    let server = TestServer::start(ServerConfig {
        threads: 1,
        max_instances: 0,
        ..ServerConfig::default()
    })
    .await;
    let mut raw = SimulatorClient::connect(server.url())
        .await
        .expect("connect")
        .max_decoding_message_size(64 << 20);

    for depth in [gymfleet_import::MAX_BODY_DEPTH + 1, 100_000] {
        let refused = raw
            .create_env(create(nested_bodies(depth)))
            .await
            .expect_err("too deep");
        assert_eq!(refused.code(), Code::InvalidArgument, "{refused:?}");
        assert!(
            refused
                .message()
                .contains("bodies nested more than 512 deep are not supported"),
            "{}",
            refused.message()
        );
    }

    let deepest = raw
        .create_env(create(nested_bodies(gymfleet_import::MAX_BODY_DEPTH)))
        .await
        .expect("the deepest accepted tree converts and builds")
        .into_inner();
    raw.step(pb::StepRequest {
        env_id: deepest.env_id,
        action_type: pb::ActionType::Torque as i32,
        values: vec![0.0; deepest.action_dim as usize],
        ..Default::default()
    })
    .await
    .expect("and steps");

    // The server is still serving.
    raw.create_env(create(PENDULUM.to_string()))
        .await
        .expect("a pendulum after the refusals");
}

/// Found by the `assets_archive` fuzz target (issue R2): a COLLADA mesh whose `<p>` indices
/// point past its positions made mesh-loader index out of bounds while building the mesh
/// (a panic on the pool: INTERNAL, where the document is at fault). The vendored
/// mesh-loader (`vendor/mesh-loader/PATCHES.md` §1) checks every index read from the
/// document and answers with an error naming the index.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_collada_index_past_its_positions_is_a_bad_mesh_not_a_panic() {
    let archive = std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fuzz/corpus/assets_archive/collada_index_out_of_range.tar"),
    )
    .expect("the fuzzer's input, kept in the corpus");
    let server = TestServer::start_default().await;
    let mut raw = SimulatorClient::connect(server.url())
        .await
        .expect("connect");
    // The `assets_archive` target's URDF model, whose link's mesh is the archive's DAE.
    let urdf = include_str!("../../../fuzz/src/assets.urdf");
    let refused = raw
        .create_env(pb::CreateEnvRequest {
            document_json: urdf.to_string(),
            assets: archive,
            ..Default::default()
        })
        .await
        .expect_err("a broken mesh");
    assert_eq!(refused.code(), Code::InvalidArgument, "{refused:?}");
    assert_eq!(
        refused.message(),
        "document_json: parts[1].primitive.file: \"package://p/meshes/c.dae\" is not a readable \
         mesh: position index 2 is out of range: the geometry has 2 positions"
    );
    // The server is still serving.
    raw.create_env(create(PENDULUM.to_string()))
        .await
        .expect("a pendulum after the refusal");
}
