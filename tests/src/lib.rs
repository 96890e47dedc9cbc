//! The harness of gymfleet's end-to-end tests and benchmarks. This crate owns
//! [`TestServer`]: a real `gymfleet-server` started in-process on `127.0.0.1:0` (the
//! server crate's `LocalServer`), plus the seed models. The tests in
//! `tests/e2e/` drive it over the network with `gymfleet-client`, and `benches/`
//! compares remote and in-process stepping. It holds no product code.

use std::net::SocketAddr;

use gymfleet_client::Client;
use gymfleet_server::{ListenAddr, LocalServer, ServerConfig};

/// The seed's 1-DOF pendulum (end effector `"arm"`).
pub const PENDULUM: &str = include_str!("../../models/pendulum.json");
/// The seed's 2-DOF arm (end effector `"forearm"`).
pub const ARM2: &str = include_str!("../../models/arm2.json");

/// A server running in this process on an ephemeral loopback port: the server crate's
/// [`LocalServer`], with the conveniences the tests share.
#[derive(Debug)]
pub struct TestServer {
    server: LocalServer,
}

impl TestServer {
    /// Binds `127.0.0.1:0` and serves `config` on it. The listener is bound before this
    /// returns, so clients can connect at once.
    pub async fn start(config: ServerConfig) -> TestServer {
        let server = LocalServer::start(config)
            .await
            .expect("start a server on 127.0.0.1:0");
        TestServer { server }
    }

    /// A server with default limits and a two-thread pool.
    pub async fn start_default() -> TestServer {
        Self::start(ServerConfig {
            threads: 2,
            ..ServerConfig::default()
        })
        .await
    }

    /// The bound address.
    pub fn addr(&self) -> SocketAddr {
        match self.server.addr() {
            ListenAddr::Tcp(addr) => *addr,
            ListenAddr::Unix(path) => unreachable!("bound on TCP, not {}", path.display()),
        }
    }

    /// `http://127.0.0.1:<port>`.
    pub fn url(&self) -> String {
        format!("http://{}", self.addr())
    }

    /// A new client connection (given as `host:port`, without a scheme).
    pub async fn client(&self) -> Client {
        Client::connect(self.server.client_addr())
            .await
            .expect("connect to the test server")
    }

    /// Asks the server to shut down and waits for `serve` to return.
    pub async fn stop(self) -> gymfleet_server::Result<()> {
        self.server.stop().await
    }
}
