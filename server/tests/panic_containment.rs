//! A panic inside a pool job (here injected with `ServerConfig::panic_on_action`, which only
//! debug builds have) must not kill the server: the call gets INTERNAL with the panic
//! message, the env or batch it ran on is closed, and everyone else is still served.

// These requests are built in the flat form (`CreateEnvRequest.document_json`, …): the
// proto deprecates it for `options`, and the server still reads it (`server/src/convert/create.rs`).
#![allow(deprecated)]
#![cfg(debug_assertions)]

use gymfleet_proto::v1 as pb;
use gymfleet_server::{LocalServer, ServerConfig};
use pb::simulator_client::SimulatorClient;
use tonic::Code;

const PENDULUM: &str = include_str!("../../models/pendulum.json");
const POISON: f32 = 1234.5;

fn create(n: u32) -> pb::CreateBatchRequest {
    pb::CreateBatchRequest {
        document_json: PENDULUM.to_string(),
        end_effector_ids: vec!["arm".into()],
        n_envs: n,
        ..Default::default()
    }
}

fn step(env_id: &str, value: f32) -> pb::StepRequest {
    pb::StepRequest {
        env_id: env_id.to_string(),
        action_type: pb::ActionType::Torque as i32,
        values: vec![value],
        ..Default::default()
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_panicking_step_is_contained() {
    let config = ServerConfig {
        threads: 2,
        panic_on_action: Some(POISON),
        ..ServerConfig::default()
    };
    let server = LocalServer::start(config).await.unwrap();
    let mut client = SimulatorClient::connect(format!("http://{}", server.client_addr()))
        .await
        .unwrap();

    let create_env = pb::CreateEnvRequest {
        document_json: PENDULUM.to_string(),
        end_effector_ids: vec!["arm".into()],
        ..Default::default()
    };
    let victim = client
        .create_env(create_env.clone())
        .await
        .unwrap()
        .into_inner()
        .env_id;
    let bystander = client
        .create_env(create_env.clone())
        .await
        .unwrap()
        .into_inner()
        .env_id;

    let status = client.step(step(&victim, POISON)).await.unwrap_err();
    assert_eq!(status.code(), Code::Internal);
    let message = status.message();
    assert!(message.contains("Step on"), "{message}");
    assert!(message.contains("injected panic"), "{message}");
    assert!(
        message.contains(&format!("{victim} was closed")),
        "{message}"
    );

    // The entry was removed, not left half-stepped.
    let status = client
        .observe(pb::EnvRef {
            env_id: victim.clone(),
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::NotFound);

    // Everyone else is still served, and new work is accepted.
    let ok = client
        .step(step(&bystander, 1.0))
        .await
        .unwrap()
        .into_inner();
    assert_eq!(ok.episode_step, 1);
    client.create_env(create_env).await.unwrap();

    // The same for a batch.
    let batch_id = client
        .create_batch(create(4))
        .await
        .unwrap()
        .into_inner()
        .batch_id;
    let status = client
        .step_batch(pb::StepBatchRequest {
            batch_id: batch_id.clone(),
            action_type: pb::ActionType::Torque as i32,
            actions: vec![POISON, 0.0, 0.0, 0.0],
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::Internal);
    assert!(
        status.message().contains("StepBatch on"),
        "{}",
        status.message()
    );
    let status = client
        .observe_batch(pb::BatchRef { batch_id })
        .await
        .unwrap_err();
    assert_eq!(status.code(), Code::NotFound);

    let info = client
        .get_server_info(pb::GetServerInfoRequest {})
        .await
        .unwrap()
        .into_inner();
    assert_eq!((info.envs, info.batches, info.batch_envs), (2, 0, 0));

    server.stop().await.unwrap();
}

/// The same on a thread that runs its own calls' pool jobs (`run_jobs_here`, how the Python
/// package calls its embedded server in process): the step runs on the caller's thread,
/// and its panic is still an INTERNAL status that closes the env or batch, not an unwinding
/// of the caller.
#[test]
fn a_panicking_step_run_on_the_callers_thread_is_contained() {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    let config = ServerConfig {
        threads: 2,
        panic_on_action: Some(POISON),
        ..ServerConfig::default()
    };
    let server = runtime.block_on(LocalServer::start(config)).unwrap();
    let mut client = SimulatorClient::new(server.in_process());
    fn on<F: std::future::Future>(runtime: &tokio::runtime::Runtime, future: F) -> F::Output {
        gymfleet_server::run_jobs_here(|| runtime.block_on(future))
    }

    let create_env = pb::CreateEnvRequest {
        document_json: PENDULUM.to_string(),
        end_effector_ids: vec!["arm".into()],
        ..Default::default()
    };
    let victim = on(&runtime, client.create_env(create_env.clone()))
        .unwrap()
        .into_inner()
        .env_id;
    let status = on(&runtime, client.step(step(&victim, POISON))).unwrap_err();
    assert_eq!(status.code(), Code::Internal);
    assert!(
        status.message().contains("injected panic"),
        "{}",
        status.message()
    );
    let status = on(&runtime, client.observe(pb::EnvRef { env_id: victim })).unwrap_err();
    assert_eq!(status.code(), Code::NotFound);

    // A batch of one chunk (stepped on this thread) and one of several (on the pool).
    for n_envs in [1, 16] {
        let batch_id = on(&runtime, client.create_batch(create(n_envs)))
            .unwrap()
            .into_inner()
            .batch_id;
        let mut actions = vec![0.5; n_envs as usize];
        let ok = on(
            &runtime,
            client.step_batch(pb::StepBatchRequest {
                batch_id: batch_id.clone(),
                action_type: pb::ActionType::Torque as i32,
                actions: actions.clone(),
                ..Default::default()
            }),
        )
        .unwrap()
        .into_inner();
        assert_eq!(ok.rewards.len(), n_envs as usize);
        actions[0] = POISON;
        let status = on(
            &runtime,
            client.step_batch(pb::StepBatchRequest {
                batch_id: batch_id.clone(),
                action_type: pb::ActionType::Torque as i32,
                actions,
                ..Default::default()
            }),
        )
        .unwrap_err();
        assert_eq!(status.code(), Code::Internal, "{n_envs} envs");
        let status = on(&runtime, client.observe_batch(pb::BatchRef { batch_id })).unwrap_err();
        assert_eq!(status.code(), Code::NotFound, "{n_envs} envs");
    }
    let info = on(
        &runtime,
        client.get_server_info(pb::GetServerInfoRequest {}),
    )
    .unwrap()
    .into_inner();
    assert_eq!((info.envs, info.batches), (0, 0));
    runtime.block_on(server.stop()).unwrap();
}
