//! The server around the simulator: server info, health, reflection, idle reclaiming and
//! graceful shutdown.

use std::time::Duration;

use gymfleet_client::{ActionType, BatchOptions, ClientError, EnvOptions};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};
use gymfleet_server::{Clock, ServerConfig};
use tokio_stream::StreamExt;

use crate::assert_not_found;

/// A plain channel to the server, for the generated health and reflection stubs.
async fn channel(server: &TestServer) -> tonic::transport::Channel {
    tonic::transport::Channel::from_shared(server.url())
        .expect("valid url")
        .connect()
        .await
        .expect("connect")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn server_info_reports_version_threads_counts_and_limits() {
    let server = TestServer::start(ServerConfig {
        threads: 2,
        max_envs: 123,
        max_batch_size: 45,
        max_document_bytes: 6789,
        max_message_bytes: 1 << 20,
        idle_ttl: Duration::from_secs(77),
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let info = client.server_info().await.expect("info");
    assert_eq!(info.version, env!("CARGO_PKG_VERSION"));
    assert_eq!(info.threads, 2);
    assert_eq!((info.envs, info.batches, info.batch_envs), (0, 0, 0));
    let l = info.limits;
    assert_eq!(
        (
            l.max_envs,
            l.max_batch_size,
            l.max_document_bytes,
            l.max_message_bytes,
            l.idle_ttl_seconds
        ),
        (123, 45, 6789, 1 << 20, 77)
    );

    client
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("env");
    client
        .create_batch(BatchOptions::new(ARM2, 5))
        .await
        .expect("batch");
    let info = client.server_info().await.expect("info");
    assert_eq!((info.envs, info.batches, info.batch_envs), (1, 1, 5));
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn health_reports_serving() {
    use tonic_health::pb::health_check_response::ServingStatus;
    use tonic_health::pb::health_client::HealthClient;
    use tonic_health::pb::HealthCheckRequest;

    let server = TestServer::start_default().await;
    let mut health = HealthClient::new(channel(&server).await);
    for service in ["gymfleet.v1.Simulator", ""] {
        let reply = health
            .check(HealthCheckRequest {
                service: service.to_string(),
            })
            .await
            .expect("health check")
            .into_inner();
        assert_eq!(
            reply.status(),
            ServingStatus::Serving,
            "service {service:?}"
        );
    }
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn reflection_v1_and_v1alpha_list_the_simulator() {
    let server = TestServer::start_default().await;

    {
        use tonic_reflection::pb::v1::server_reflection_client::ServerReflectionClient;
        use tonic_reflection::pb::v1::server_reflection_request::MessageRequest;
        use tonic_reflection::pb::v1::server_reflection_response::MessageResponse;
        use tonic_reflection::pb::v1::ServerReflectionRequest;

        let mut client = ServerReflectionClient::new(channel(&server).await);
        let request = ServerReflectionRequest {
            host: String::new(),
            message_request: Some(MessageRequest::ListServices(String::new())),
        };
        let mut replies = client
            .server_reflection_info(tokio_stream::iter([request]))
            .await
            .expect("v1 reflection")
            .into_inner();
        let reply = replies.next().await.expect("a reply").expect("ok reply");
        let Some(MessageResponse::ListServicesResponse(list)) = reply.message_response else {
            panic!("unexpected v1 reply {reply:?}");
        };
        let names: Vec<_> = list.service.iter().map(|s| s.name.as_str()).collect();
        assert!(names.contains(&"gymfleet.v1.Simulator"), "{names:?}");
        assert!(names.contains(&"grpc.health.v1.Health"), "{names:?}");
    }
    {
        use tonic_reflection::pb::v1alpha::server_reflection_client::ServerReflectionClient;
        use tonic_reflection::pb::v1alpha::server_reflection_request::MessageRequest;
        use tonic_reflection::pb::v1alpha::server_reflection_response::MessageResponse;
        use tonic_reflection::pb::v1alpha::ServerReflectionRequest;

        let mut client = ServerReflectionClient::new(channel(&server).await);
        let request = ServerReflectionRequest {
            host: String::new(),
            message_request: Some(MessageRequest::FileContainingSymbol(
                "gymfleet.v1.Simulator".to_string(),
            )),
        };
        let mut replies = client
            .server_reflection_info(tokio_stream::iter([request]))
            .await
            .expect("v1alpha reflection")
            .into_inner();
        let reply = replies.next().await.expect("a reply").expect("ok reply");
        let Some(MessageResponse::FileDescriptorResponse(files)) = reply.message_response else {
            panic!("unexpected v1alpha reply {reply:?}");
        };
        assert!(!files.file_descriptor_proto.is_empty());
    }
    server.stop().await.expect("clean shutdown");
}

/// How many single envs and batches the server holds.
async fn held(client: &gymfleet_client::Client) -> (u64, u64, u64) {
    let info = client.server_info().await.expect("info");
    (info.envs, info.batches, info.batch_envs)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn idle_ttl_reclaims_abandoned_envs_and_batches() {
    // Idleness is measured on a clock the test moves, and the sweeper sweeps whenever it
    // moves (`Clock::swept` waits for that sweep): nothing depends on time passing.
    let clock = Clock::manual();
    let server = TestServer::start(ServerConfig {
        threads: 2,
        idle_ttl: Duration::from_secs(60),
        clock: clock.clone(),
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("env");
    let batch = client
        .create_batch(BatchOptions::new(ARM2, 3))
        .await
        .expect("batch");
    let kept = client
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("env");

    // A sweep before the clock moves finds nothing idle.
    clock.advance(Duration::ZERO);
    crate::swept(&clock).await;
    assert_eq!(held(&client).await, (2, 1, 3));
    clock.advance(Duration::from_secs(59));
    crate::swept(&clock).await;
    assert_eq!(held(&client).await, (2, 1, 3), "59 s is not idle enough");
    kept.observe().await.expect("a call touches the env");
    clock.advance(Duration::from_secs(1));
    crate::swept(&clock).await;
    // Now `env` and `batch` have been idle 60 s, `kept` only 1 s.
    assert_eq!(held(&client).await, (1, 0, 0));
    assert_not_found(&env.observe().await.unwrap_err(), &[env.id()]);
    assert_not_found(&batch.observe().await.unwrap_err(), &[batch.id()]);
    kept.observe().await.expect("the touched env is kept");
    clock.advance(Duration::from_secs(60));
    crate::swept(&clock).await;
    assert_eq!(held(&client).await, (0, 0, 0));
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn shutdown_ends_open_streams_and_serve_returns() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client
        .create_batch(BatchOptions::new(ARM2, 4).end_effectors(["forearm"]))
        .await
        .expect("batch");
    let mut stream = batch.stream().await.expect("stream");
    stream
        .step(ActionType::Torque, &[0.0; 8])
        .await
        .expect("a step before shutdown");
    // The client keeps its stream open; shutdown must still complete, and the stream
    // learns that the server is going away.
    let stopping = tokio::spawn(server.stop());
    let ended = async {
        loop {
            if let Err(err) = stream.step(ActionType::Torque, &[0.0; 8]).await {
                break err;
            }
        }
    };
    let err = tokio::time::timeout(Duration::from_secs(30), ended)
        .await
        .expect("the stream ends once the server shuts down");
    assert!(matches!(err, ClientError::Unavailable { .. }), "{err:?}");
    drop(stream);
    stopping
        .await
        .expect("stop task")
        .expect("serve returned cleanly");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_restarted_server_is_told_apart_by_its_instance_id() {
    let first = TestServer::start_default().await;
    let client = first.client().await;
    let id = client.server_info().await.expect("info").instance_id;
    assert_eq!(id.len(), 32, "{id}");
    assert!(id.chars().all(|c| c.is_ascii_hexdigit()), "{id}");
    // Stable for the process's life, whoever asks.
    assert_eq!(client.server_info().await.expect("info").instance_id, id);
    assert_eq!(
        first
            .client()
            .await
            .server_info()
            .await
            .expect("info")
            .instance_id,
        id
    );
    first.stop().await.expect("stop");
    // A new process (here: a new server) has a new id.
    let second = TestServer::start_default().await;
    let other = second.client().await.server_info().await.expect("info");
    assert_ne!(other.instance_id, id);
    assert_eq!(other.instance_id.len(), 32);
}
