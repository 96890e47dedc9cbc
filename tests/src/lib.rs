//! The harness of gymfleet's end-to-end tests and benchmarks. This crate owns
//! [`TestServer`]: a real `gymfleet-server` started in-process on `127.0.0.1:0` (the
//! server crate's `LocalServer`), plus the seed models. The tests in
//! `tests/e2e/` drive it over the network with `gymfleet-client`, and `benches/`
//! compares remote and in-process stepping. It holds no product code.
//!
//! # What the tests cover
//!
//! - `tests/e2e/`: a real server on `127.0.0.1:0` driven by the client: the seed
//!   walkthrough, the 2-DOF arm, batches, every error path, stream against unary,
//!   concurrency, idle TTL on a manual clock, UDS against TCP, auth, tenants, TLS and
//!   metrics (`security.rs`), the hostile-request suite (`adversarial.rs`), and a fleet
//!   partition behind `PartitionableProxy` (`fleet.rs`). `regressions.rs` replays inputs
//!   that once crashed a server. `render.rs` tests `Render` and `GetScene`. `replay.rs`
//!   records a swinging pendulum's HTML replay into `target/tmp/replay/pendulum.html`,
//!   which `tests/browser/replay.test.mjs` (playwright-core from npm, pinned by its lock
//!   file) opens in Debian's headless Chromium with software WebGL: no console errors, a
//!   canvas that is not blank, two frames that differ where the arm is, working controls;
//!   `.ci/run` installs chromium and runs it after `cargo test`. `dashboard.rs` tests the
//!   dashboard's API over plain HTTP (tenants, sessions and cookies, the 401s, escaping,
//!   counts and rates on a manual clock, the loopback rule);
//!   `tests/browser/dashboard.test.mjs` drives the page against
//!   `examples/dashboard_fixture.rs` (a server with auth and a batch whose instance is
//!   named `<script>alert(1)</script>`, stepped on request): no console errors, the batch
//!   listed, the 3D view changing as the env steps, a wrong token seeing nothing.
//! - `benches/remote_vs_local.rs`: the remote-against-in-process benchmark;
//!   `examples/fairness.rs`: tenant fairness (I1).
//! - `tests/fuzz_corpora.rs` replays the fuzz corpora through the fuzz targets' own bodies,
//!   as an ordinary test. `tests/alloc_bounds.rs` (its own binary: a counting global
//!   allocator, dhat's) states and checks what the costliest inputs of the largest accepted
//!   size may allocate (peak, bytes in all, allocations) through `DirectService`.
//! - `tests/tidy/` checks the source tree itself: no crate's modules import each other in a
//!   loop (`main.rs`), every cited Markdown file is in the repository (`citations.rs`), and
//!   no non-test function passes 80 lines but the listed ones, which may only shrink
//!   (`functions.rs`).
//!
//! Tests never sleep through idle time: clocks are injected, and the idle sweeper sweeps
//! whenever a manual clock moves, with `Clock::swept` waiting for that sweep
//! (`lifecycle.rs`, `dashboard.rs`). Deadlines are tested with the server's test gate
//! (`ServerConfig::job_gate`, debug builds only): a held job makes the deadline pass on any
//! machine, and the test waits until the job has seen its caller gone (`security.rs`). The
//! pool's fairness test holds its chunks at a gate instead of sleeping in them. What still
//! leans on time are hang guards only: a minute's bound on `swept`, and `fleet.rs`'s 60 s
//! on a keepalive failure. Tests that read `GYMFLEET_*` defaults clear those variables
//! first.

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
