//! The plaintext health listener (`--health-listen`): what a kubelet's gRPC probe reaches
//! while the main listener serves TLS (deploy/k8s/overlays/secure).

use gymfleet_client::Client;
use gymfleet_e2e::TestServer;
use gymfleet_proto::v1 as pb;
use gymfleet_server::{ServerConfig, TlsConfig};
use tonic_health::pb::health_check_response::ServingStatus;
use tonic_health::pb::health_client::HealthClient;
use tonic_health::pb::HealthCheckRequest;

use crate::security::pki;

fn free_port() -> std::net::SocketAddr {
    let free = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    free.local_addr().unwrap()
}

async fn plaintext(addr: std::net::SocketAddr) -> tonic::transport::Channel {
    tonic::transport::Channel::from_shared(format!("http://{addr}"))
        .unwrap()
        .connect()
        .await
        .expect("a plaintext connection to the health listener")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn health_answers_in_plaintext_beside_a_tls_listener_and_nothing_else_does() {
    let pki = pki();
    let health_addr = free_port();
    let server = TestServer::start(ServerConfig {
        threads: 1,
        tls: Some(TlsConfig {
            cert_pem: pki.server_cert.clone().into_bytes(),
            key_pem: pki.server_key.clone().into_bytes(),
            client_ca_pem: None,
        }),
        health_listen: Some(health_addr),
        ..ServerConfig::default()
    })
    .await;

    let channel = plaintext(health_addr).await;
    for service in ["gymfleet.v1.Simulator", ""] {
        let reply = HealthClient::new(channel.clone())
            .check(HealthCheckRequest {
                service: service.into(),
            })
            .await
            .expect("health in plaintext")
            .into_inner();
        assert_eq!(reply.status(), ServingStatus::Serving, "{service:?}");
    }
    // The simulator is not served there: only health is.
    let err = pb::simulator_client::SimulatorClient::new(channel)
        .get_server_info(pb::GetServerInfoRequest::default())
        .await
        .unwrap_err();
    assert_eq!(err.code(), tonic::Code::Unimplemented, "{err:?}");

    // The main listener still serves TLS, and the simulator on it.
    let client = Client::builder(server.addr().to_string())
        .tls_ca_pem(pki.ca.clone())
        .tls_domain("localhost")
        .connect()
        .await
        .expect("TLS connect");
    client.server_info().await.expect("info over TLS");
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_health_address_in_use_stops_the_start_with_its_address() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = taken.local_addr().unwrap();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let err = gymfleet_server::serve(
        listener,
        ServerConfig {
            threads: 1,
            health_listen: Some(addr),
            ..ServerConfig::default()
        },
        std::future::pending(),
    )
    .await
    .unwrap_err();
    let text = err.to_string();
    assert!(
        text.starts_with(&format!("cannot listen on {addr}: ")),
        "{text}"
    );
}
