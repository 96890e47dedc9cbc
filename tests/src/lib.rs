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

    /// Serves `config` on `addr` (a port a test reserved, e.g. one a fleet was given while
    /// nothing listened there).
    pub async fn start_at(addr: SocketAddr, config: ServerConfig) -> TestServer {
        let server = LocalServer::bind(&ListenAddr::Tcp(addr), config)
            .await
            .expect("start a server on the reserved port");
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
    pub async fn stop(self) -> Result<(), gymfleet_server::StartupError> {
        self.server.stop().await
    }
}

/// A TCP proxy in front of a server that can be partitioned: until
/// [`PartitionableProxy::partition`] it forwards bytes both ways; after it, it keeps
/// every connection open (and accepts new ones) but forwards nothing, as a network
/// partition looks to a client: no reset, no close, only silence.
#[derive(Debug)]
pub struct PartitionableProxy {
    addr: SocketAddr,
    partitioned: std::sync::Arc<std::sync::atomic::AtomicBool>,
    task: tokio::task::JoinHandle<()>,
}

impl PartitionableProxy {
    /// Listens on `127.0.0.1:0` and forwards to `target`.
    pub async fn start(target: SocketAddr) -> PartitionableProxy {
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
            .await
            .expect("bind the proxy");
        let addr = listener.local_addr().expect("proxy address");
        let partitioned = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&partitioned);
        let task = tokio::spawn(async move {
            // Dropped with this task (on the proxy's drop): that aborts every connection.
            let mut connections = tokio::task::JoinSet::new();
            while let Ok((client, _)) = listener.accept().await {
                let flag = Arc::clone(&flag);
                connections.spawn(async move {
                    let Ok(server) = tokio::net::TcpStream::connect(target).await else {
                        return;
                    };
                    let (client_rx, client_tx) = client.into_split();
                    let (server_rx, server_tx) = server.into_split();
                    let up = forward(client_rx, server_tx, Arc::clone(&flag));
                    let down = forward(server_rx, client_tx, flag);
                    tokio::join!(up, down);
                });
            }
        });
        PartitionableProxy {
            addr,
            partitioned,
            task,
        }
    }

    /// The address clients connect to.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// From now on nothing gets through, and nothing is closed.
    pub fn partition(&self) {
        self.partitioned
            .store(true, std::sync::atomic::Ordering::SeqCst);
    }
}

impl Drop for PartitionableProxy {
    fn drop(&mut self) {
        self.task.abort();
    }
}

/// Copies `from` to `to` until either closes or the partition starts; then holds both
/// open, silent, forever.
async fn forward(
    mut from: tokio::net::tcp::OwnedReadHalf,
    mut to: tokio::net::tcp::OwnedWriteHalf,
    partitioned: std::sync::Arc<std::sync::atomic::AtomicBool>,
) {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let mut buffer = vec![0u8; 64 * 1024];
    loop {
        let n = match from.read(&mut buffer).await {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        if partitioned.load(std::sync::atomic::Ordering::SeqCst) {
            break;
        }
        if to.write_all(&buffer[..n]).await.is_err() {
            return;
        }
    }
    // Partitioned: keep the sockets, drop what arrives.
    loop {
        match from.read(&mut buffer).await {
            Ok(0) | Err(_) => std::future::pending::<()>().await,
            Ok(_) => {}
        }
    }
}
