//! The Unix-domain socket listener: a trainer on the server's host connects with
//! `unix:/path`, and gets bitwise the same results as over TCP.

use gymfleet_client::{ActionType, BatchOptions, Client, EnvOptions};
use gymfleet_e2e::{TestServer, ARM2};
use gymfleet_server::{ListenAddr, Listener, ServerConfig};

use crate::{actions, bits};

/// Steps a 2-env arm2 batch and a single arm2 env 30 times; returns every observation.
async fn rollout(client: &Client) -> Vec<Vec<f32>> {
    let batch = client
        .create_batch(
            BatchOptions::new(ARM2, 2)
                .end_effectors(["forearm"])
                .seed(3),
        )
        .await
        .expect("create batch");
    let env = client
        .create_env(EnvOptions::new(ARM2).end_effectors(["forearm"]).seed(3))
        .await
        .expect("create env");
    let layout = env.info().observation_layout.clone();
    let mut rows = Vec::new();
    for k in 0..30u64 {
        let step = batch
            .step(ActionType::Torque, &actions(k, 4, 2e-3))
            .await
            .expect("batch step");
        rows.push(step.observations().to_vec());
        let single = env
            .step(ActionType::Torque, &actions(k, 2, 2e-3))
            .await
            .expect("env step");
        rows.push(single.observation.to_flat(&layout));
    }
    batch.close().await.expect("close batch");
    env.close().await.expect("close env");
    rows
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_unix_socket_serves_the_same_results_as_tcp_and_is_removed_at_shutdown() {
    let dir = std::env::temp_dir().join(format!("gymfleet-e2e-uds-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("gymfleet.sock");
    let addr = ListenAddr::Unix(path.clone());
    let listener = Listener::bind(&addr).await.expect("bind the socket");
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(gymfleet_server::serve(
        listener,
        ServerConfig {
            threads: 2,
            ..ServerConfig::default()
        },
        async move {
            let _ = stopped.await;
        },
    ));

    let over_uds = Client::connect(addr.to_string())
        .await
        .expect("connect over unix:");
    assert_eq!(over_uds.addr(), format!("unix:{}", path.display()));
    let info = over_uds.server_info().await.expect("server info");
    assert_eq!(info.threads, 2);
    let uds_rows = rollout(&over_uds).await;

    let tcp = TestServer::start_default().await;
    let tcp_rows = rollout(&tcp.client().await).await;
    tcp.stop().await.expect("tcp server stops");
    assert_eq!(
        uds_rows.iter().map(|r| bits(r)).collect::<Vec<_>>(),
        tcp_rows.iter().map(|r| bits(r)).collect::<Vec<_>>(),
        "the transport changes nothing"
    );

    let _ = stop.send(());
    server.await.expect("server task").expect("serve");
    assert!(
        !path.exists(),
        "the socket file is removed when the server stops"
    );
    std::fs::remove_dir_all(&dir).expect("remove temp dir");
}

/// A client in the server's own process (the Python package's embedded server) calls the
/// service with no socket between: the same results bit for bit, the same refusals, and
/// the same authenticator in front.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_in_process_client_gets_what_a_tcp_client_gets() {
    use gymfleet_server::{LocalServer, TokenTable};

    let server = LocalServer::start(ServerConfig {
        threads: 2,
        auth_tokens: Some(std::sync::Arc::new(
            TokenTable::parse("team-a team-a-token-0123456789\n").expect("tokens"),
        )),
        ..ServerConfig::default()
    })
    .await
    .expect("start");
    let in_process = Client::builder(server.client_addr())
        .token("team-a-token-0123456789")
        .in_process(server.in_process())
        .expect("in-process client");
    assert_eq!(in_process.addr(), server.client_addr());
    let info = in_process.server_info().await.expect("server info");
    assert_eq!((info.threads, info.tenant.as_str()), (2, "team-a"));
    let over_tcp = Client::builder(server.client_addr())
        .token("team-a-token-0123456789")
        .connect()
        .await
        .expect("tcp client");
    assert_eq!(
        rollout(&in_process)
            .await
            .iter()
            .map(|r| bits(r))
            .collect::<Vec<_>>(),
        rollout(&over_tcp)
            .await
            .iter()
            .map(|r| bits(r))
            .collect::<Vec<_>>(),
        "the transport changes nothing"
    );

    // The server's refusals, word for word.
    let env = in_process
        .create_env(EnvOptions::new(ARM2))
        .await
        .expect("env");
    let refused = env.step(ActionType::Torque, &[0.0; 3]).await.unwrap_err();
    let tcp_env = over_tcp
        .create_env(EnvOptions::new(ARM2))
        .await
        .expect("env");
    let over_tcp_refused = tcp_env
        .step(ActionType::Torque, &[0.0; 3])
        .await
        .unwrap_err();
    assert_eq!(refused.to_string(), over_tcp_refused.to_string());
    assert!(
        matches!(
            refused,
            gymfleet_client::ClientError::InvalidArgument { .. }
        ),
        "{refused:?}"
    );
    // The authenticator is in front of it too.
    let anonymous = Client::builder(server.client_addr())
        .in_process(server.in_process())
        .expect("in-process client");
    let err = anonymous.server_info().await.unwrap_err();
    assert!(
        matches!(err, gymfleet_client::ClientError::Unauthenticated { .. }),
        "{err:?}"
    );
    server.stop().await.expect("stops");
}
