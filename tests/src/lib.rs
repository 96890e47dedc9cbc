//! The harness of gymfleet's end-to-end tests and benchmarks. This crate owns
//! [`TestServer`]: a real `gymfleet-server` started in-process on `127.0.0.1:0` with
//! `gymfleet_server::serve` and a oneshot shutdown, plus the seed models. The tests in
//! `tests/e2e/` drive it over the network with `gymfleet-client`, and `benches/`
//! compares remote and in-process stepping. It holds no product code.

use std::net::SocketAddr;

use gymfleet_client::Client;
use gymfleet_server::ServerConfig;
use tokio::net::TcpListener;
use tokio::sync::oneshot;
use tokio::task::JoinHandle;

/// The seed's 1-DOF pendulum (end effector `"arm"`).
pub const PENDULUM: &str = include_str!("../../models/pendulum.json");
/// The seed's 2-DOF arm (end effector `"forearm"`).
pub const ARM2: &str = include_str!("../../models/arm2.json");

/// A server running in this process on an ephemeral loopback port.
#[derive(Debug)]
pub struct TestServer {
    addr: SocketAddr,
    stop: Option<oneshot::Sender<()>>,
    task: JoinHandle<gymfleet_server::Result<()>>,
}

impl TestServer {
    /// Binds `127.0.0.1:0` and serves `config` on it. The listener is bound before this
    /// returns, so clients can connect at once.
    pub async fn start(config: ServerConfig) -> TestServer {
        let listener = TcpListener::bind("127.0.0.1:0")
            .await
            .expect("bind 127.0.0.1:0");
        let addr = listener.local_addr().expect("bound address");
        let (stop, stopped) = oneshot::channel::<()>();
        let task = tokio::spawn(gymfleet_server::serve(listener, config, async move {
            // A dropped sender also stops the server.
            let _ = stopped.await;
        }));
        TestServer {
            addr,
            stop: Some(stop),
            task,
        }
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
        self.addr
    }

    /// `http://127.0.0.1:<port>`.
    pub fn url(&self) -> String {
        format!("http://{}", self.addr)
    }

    /// A new client connection (given as `host:port`, without a scheme).
    pub async fn client(&self) -> Client {
        Client::connect(self.addr.to_string())
            .await
            .expect("connect to the test server")
    }

    /// Asks the server to shut down and waits for `serve` to return.
    pub async fn stop(mut self) -> gymfleet_server::Result<()> {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        (&mut self.task).await.expect("server task panicked")
    }
}
