//! [`EmbeddedServer`] (feature `embedded`): a gymfleet server run inside this process on
//! `127.0.0.1:0`, for load runs with no `--server`. It has no env or batch limits and
//! no idle TTL: it exists only for this run.

use std::net::SocketAddr;
use std::time::Duration;

use gymfleet_server::ServerConfig;
use tokio::net::TcpListener;
use tokio::sync::oneshot;
use tokio::task::JoinHandle;

use crate::error::{LoadError, Result};

/// A server serving on an ephemeral loopback port until [`EmbeddedServer::stop`].
#[derive(Debug)]
pub struct EmbeddedServer {
    addr: SocketAddr,
    stop: oneshot::Sender<()>,
    task: JoinHandle<gymfleet_server::Result<()>>,
}

impl EmbeddedServer {
    /// Binds `127.0.0.1:0` and serves on it with a step pool of `threads` threads (0:
    /// one per core). Clients can connect as soon as this returns. Must be called
    /// within a tokio runtime.
    pub async fn start(threads: usize) -> Result<Self> {
        let listener = TcpListener::bind("127.0.0.1:0")
            .await
            .map_err(|e| LoadError::setup("embedded server: bind 127.0.0.1:0", e))?;
        let addr = listener
            .local_addr()
            .map_err(|e| LoadError::setup("embedded server: bound address", e))?;
        let config = ServerConfig {
            threads,
            max_envs: 0,
            max_batch_size: 0,
            idle_ttl: Duration::ZERO,
            ..ServerConfig::default()
        };
        let (stop, stopped) = oneshot::channel::<()>();
        let task = tokio::spawn(gymfleet_server::serve(listener, config, async move {
            // A dropped sender stops the server too.
            let _ = stopped.await;
        }));
        Ok(EmbeddedServer { addr, stop, task })
    }

    /// The bound address, `127.0.0.1:<port>`.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Shuts the server down and waits for it.
    pub async fn stop(self) -> Result<()> {
        let _ = self.stop.send(());
        match self.task.await {
            Ok(Ok(())) => Ok(()),
            Ok(Err(e)) => Err(LoadError::setup("embedded server", e)),
            Err(e) => Err(LoadError::setup("embedded server task", e)),
        }
    }
}
