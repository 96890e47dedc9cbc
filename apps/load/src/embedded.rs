//! [`EmbeddedServer`] (feature `embedded`): a gymfleet server run inside this process on
//! `127.0.0.1:0` (the server crate's `LocalServer`), for load runs with no `--server`. It
//! has no env or batch limits and no idle TTL: it exists only for this run.

use std::time::Duration;

use gymfleet_server::{LocalServer, ServerConfig};

use crate::error::{LoadError, Result};

/// A server serving on an ephemeral loopback port until [`EmbeddedServer::stop`].
#[derive(Debug)]
pub struct EmbeddedServer {
    server: LocalServer,
}

impl EmbeddedServer {
    /// Binds `127.0.0.1:0` and serves on it with a step pool of `threads` threads (0:
    /// one per core). Clients can connect as soon as this returns. Must be called
    /// within a tokio runtime.
    pub async fn start(threads: usize) -> Result<Self> {
        let config = ServerConfig {
            threads,
            max_envs: 0,
            max_batch_size: 0,
            idle_ttl: Duration::ZERO,
            ..ServerConfig::default()
        };
        let server = LocalServer::start(config)
            .await
            .map_err(|e| LoadError::setup("embedded server", e))?;
        Ok(EmbeddedServer { server })
    }

    /// The address clients connect to, `127.0.0.1:<port>`.
    pub fn addr(&self) -> String {
        self.server.client_addr()
    }

    /// Shuts the server down and waits for it.
    pub async fn stop(self) -> Result<()> {
        self.server
            .stop()
            .await
            .map_err(|e| LoadError::setup("embedded server", e))
    }
}
