//! Every error path: the status class (as the typed client error) and the message text.

use std::time::Duration;

use gymfleet_client::{ActionType, BatchOptions, ClientError, EnvOptions};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};
use gymfleet_proto::v1 as pb;
use gymfleet_server::ServerConfig;
use tonic::Code;

use crate::{assert_mentions, assert_not_found};

fn limited() -> ServerConfig {
    ServerConfig {
        threads: 2,
        max_envs: 20,
        max_batch_size: 16,
        max_document_bytes: 4096,
        idle_ttl: Duration::ZERO,
        ..ServerConfig::default()
    }
}

#[track_caller]
fn assert_invalid(err: &ClientError, needles: &[&str]) {
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "expected INVALID_ARGUMENT, got {err:?}"
    );
    assert_mentions(err, needles);
}

#[track_caller]
fn assert_exhausted(err: &ClientError, needles: &[&str]) {
    assert!(
        matches!(err, ClientError::ResourceExhausted { .. }),
        "expected RESOURCE_EXHAUSTED, got {err:?}"
    );
    assert_mentions(err, needles);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_documents_and_configs_are_invalid_arguments_with_paths() {
    let server = TestServer::start(limited()).await;
    let client = server.client().await;

    let typo = PENDULUM.replace(r#""child": "arm""#, r#""child": "arn""#);
    assert_ne!(typo, PENDULUM, "the fixture has a child to misspell");
    let err = client
        .create_env(EnvOptions::new(typo).end_effectors(["arm"]))
        .await
        .unwrap_err();
    assert_invalid(
        &err,
        &["assembly.joints[0].child", "unknown instance \"arn\""],
    );

    let err = client
        .create_env(EnvOptions::new("{ not json"))
        .await
        .unwrap_err();
    assert_invalid(&err, &["document", "expected a JSON document"]);

    let err = client
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm", "hand"]))
        .await
        .unwrap_err();
    assert_invalid(&err, &["end_effector_ids[1]", "unknown instance \"hand\""]);

    let err = client
        .create_env(EnvOptions::new(PENDULUM).dt(-1.0))
        .await
        .unwrap_err();
    assert_invalid(&err, &["dt:", "-1"]);

    let err = client
        .create_env(EnvOptions::new(PENDULUM).reset_noise(-2.0))
        .await
        .unwrap_err();
    assert_eq!(
        err.message(),
        "reset_noise: expected a finite half-width >= 0 (deg or mm), got -2"
    );

    let err = client
        .create_batch(BatchOptions::new(ARM2, 0))
        .await
        .unwrap_err();
    assert_invalid(&err, &["n_envs", "at least 1"]);

    // Nothing was half-created.
    let info = client.server_info().await.expect("info");
    assert_eq!((info.envs, info.batches, info.batch_envs), (0, 0, 0));
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn unknown_ids_are_not_found_naming_the_id() {
    let server = TestServer::start(limited()).await;
    let mut raw = pb::simulator_client::SimulatorClient::connect(server.url())
        .await
        .expect("raw client");
    let status = raw
        .step(pb::StepRequest {
            env_id: "sim_424242".into(),
            action_type: pb::ActionType::Torque as i32,
            values: vec![0.0],
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::NotFound);
    let err = ClientError::from(status);
    assert_not_found(&err, &["sim_424242"]);

    let status = raw
        .observe_batch(pb::BatchRef {
            batch_id: "batch_777".into(),
        })
        .await
        .unwrap_err();
    assert_not_found(&ClientError::from(status), &["batch", "batch_777"]);

    let status = raw
        .close_batch(pb::BatchRef {
            batch_id: "sim_1".into(),
        })
        .await
        .unwrap_err();
    assert_not_found(&ClientError::from(status), &["sim_1"]);
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_actions_are_invalid_arguments_expected_vs_got() {
    let server = TestServer::start(limited()).await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await
        .expect("create env");
    let batch = client
        .create_batch(BatchOptions::new(ARM2, 16).end_effectors(["forearm"]))
        .await
        .expect("create batch");

    let err = env.step(ActionType::Torque, &[1.0, 2.0]).await.unwrap_err();
    assert_invalid(&err, &["expected 1", "got 2"]);
    let err = env.step(ActionType::Torque, &[f32::NAN]).await.unwrap_err();
    assert_invalid(&err, &["values[0]", "finite", "NaN"]);

    let err = batch.step(ActionType::Torque, &[0.0; 3]).await.unwrap_err();
    assert_invalid(&err, &["expected 32", "16 envs × 2 DOF", "got 3"]);
    let mut acts = vec![0.0_f32; 32];
    acts[7] = f32::INFINITY;
    let err = batch.step(ActionType::Velocity, &acts).await.unwrap_err();
    assert_invalid(&err, &["actions[7]", "env 3", "finite", "inf"]);

    // The client's ActionType cannot say "unspecified": use the raw stub.
    let mut raw = pb::simulator_client::SimulatorClient::connect(server.url())
        .await
        .expect("raw client");
    let status = raw
        .step(pb::StepRequest {
            env_id: env.id().to_string(),
            action_type: pb::ActionType::Unspecified as i32,
            values: vec![0.0],
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::InvalidArgument);
    assert!(
        status.message().contains("action_type"),
        "{}",
        status.message()
    );
    assert!(
        status.message().contains("ACTION_TYPE_UNSPECIFIED"),
        "{}",
        status.message()
    );
    let status = raw
        .step_batch(pb::StepBatchRequest {
            batch_id: batch.id().to_string(),
            action_type: 42,
            actions: vec![0.0; 32],
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::InvalidArgument);
    assert!(
        status.message().contains("unknown value 42"),
        "{}",
        status.message()
    );

    // Rejected actions stepped nothing: both still at the start.
    let obs = env.observe().await.expect("observe");
    assert_eq!(obs.joint_positions, [0.0]);
    let step = batch
        .step(ActionType::Torque, &[0.0; 32])
        .await
        .expect("valid step");
    assert_eq!(step.step_index(), 1);
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn limits_are_resource_exhausted_and_say_how_to_raise_them() {
    let server = TestServer::start(limited()).await;
    let client = server.client().await;

    let err = client
        .create_batch(BatchOptions::new(ARM2, 17).end_effectors(["forearm"]))
        .await
        .unwrap_err();
    assert_exhausted(
        &err,
        &[
            "17",
            "max batch size of 16",
            "--max-batch-size",
            "GYMFLEET_MAX_BATCH_SIZE",
        ],
    );

    let big = format!("{PENDULUM}{}", " ".repeat(5000));
    let err = client.create_env(EnvOptions::new(big)).await.unwrap_err();
    assert_exhausted(
        &err,
        &[
            "document_json",
            "limit of 4096 bytes",
            "--max-document-bytes",
        ],
    );

    // 16 + 4 = 20 envs fill the server; the 21st is refused, whatever its kind.
    let batch = client
        .create_batch(BatchOptions::new(ARM2, 16).end_effectors(["forearm"]))
        .await
        .expect("batch of 16");
    let mut envs = Vec::new();
    for _ in 0..4 {
        envs.push(
            client
                .create_env(EnvOptions::new(PENDULUM))
                .await
                .expect("env"),
        );
    }
    let err = client
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .unwrap_err();
    assert_exhausted(
        &err,
        &[
            "too many environments",
            "limit of 20",
            "--max-envs",
            "GYMFLEET_MAX_ENVS",
        ],
    );
    let err = client
        .create_batch(BatchOptions::new(ARM2, 2))
        .await
        .unwrap_err();
    assert_exhausted(&err, &["needs 2 more", "--max-envs"]);

    let info = client.server_info().await.expect("info");
    assert_eq!(
        (info.envs, info.batches, info.batch_envs),
        (4, 1, 16),
        "refusals created nothing"
    );

    // Closing frees capacity.
    envs.pop().expect("an env").close().await.expect("close");
    client
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("room again");
    batch.close().await.expect("close batch");
    let info = client.server_info().await.expect("info");
    assert_eq!((info.envs, info.batches, info.batch_envs), (4, 0, 0));
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_oversized_message_is_refused_and_the_server_keeps_serving() {
    let server = TestServer::start(ServerConfig {
        max_message_bytes: 64 * 1024,
        max_document_bytes: 0,
        idle_ttl: Duration::ZERO,
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let big = format!("{PENDULUM}{}", " ".repeat(100 * 1024));
    let err = client.create_env(EnvOptions::new(big)).await.unwrap_err();
    assert_exhausted(&err, &["message length too large"]);

    // The connection and the server are fine: the next call succeeds.
    let env = client
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("a normal document after the refusal");
    let info = client.server_info().await.expect("info");
    assert_eq!(info.envs, 1, "the refused call created nothing");
    env.close().await.expect("close");
    server.stop().await.expect("clean shutdown");
}
