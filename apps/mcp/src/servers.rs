//! [`Servers`]: where the simulator runs. Either the gymfleet servers named with
//! `--server`, or, with no address and the `embedded` feature (on by default), a
//! gymfleet server started inside this process on 127.0.0.1 with a free port, which the
//! adapter still reaches over loopback gRPC like any other.

use crate::cli::Cli;
use crate::errors::Result;

/// The servers in use, and the embedded one to stop at the end, if any.
#[derive(Debug)]
pub(crate) struct Servers {
    addrs: Vec<String>,
    #[cfg(feature = "embedded")]
    embedded: Option<embedded::EmbeddedServer>,
}

impl Servers {
    /// The servers of `cli`: its `--server` addresses, or an embedded server.
    pub(crate) async fn start(cli: &Cli) -> Result<Self> {
        let addrs = cli.server_addrs();
        if !addrs.is_empty() {
            tracing::info!(servers = ?addrs, "using gymfleet servers");
            return Ok(Servers {
                addrs,
                #[cfg(feature = "embedded")]
                embedded: None,
            });
        }
        #[cfg(feature = "embedded")]
        {
            let server =
                embedded::EmbeddedServer::start(cli.threads, cli.models.as_deref()).await?;
            Ok(Servers {
                addrs: vec![server.addr()],
                embedded: Some(server),
            })
        }
        #[cfg(not(feature = "embedded"))]
        Err(crate::errors::McpError::startup(
            "no gymfleet server given: pass --server HOST:PORT (or set GYMFLEET_SERVER). \
             This build has no embedded server (it was built without the `embedded` feature).",
        ))
    }

    /// The server addresses, in the order given.
    pub(crate) fn addrs(&self) -> Vec<String> {
        self.addrs.clone()
    }

    /// Stops the embedded server, if there is one.
    pub(crate) async fn stop(self) {
        #[cfg(feature = "embedded")]
        if let Some(server) = self.embedded {
            server.stop().await;
        }
    }
}

#[cfg(feature = "embedded")]
mod embedded {
    use std::time::Duration;

    use gymfleet_server::{LocalServer, ServerConfig};

    /// A gymfleet server serving on loopback inside this process (the server crate's
    /// `LocalServer`).
    #[derive(Debug)]
    pub(super) struct EmbeddedServer {
        server: LocalServer,
    }

    impl EmbeddedServer {
        /// Binds 127.0.0.1:0 and serves there with `threads` pool threads (0 = one per
        /// core). It never reclaims idle envs: they live as long as this process, which
        /// closes them at exit.
        pub(super) async fn start(
            threads: usize,
            models: Option<&std::path::Path>,
        ) -> crate::errors::Result<Self> {
            let models = match models {
                Some(dir) => Some(std::sync::Arc::new(
                    gymfleet_server::ModelLibrary::load(dir)
                        .map_err(|e| crate::errors::McpError::startup(format!("--models: {e}")))?,
                )),
                None => None,
            };
            let config = ServerConfig {
                threads,
                idle_ttl: Duration::ZERO,
                models,
                ..ServerConfig::default()
            };
            let server = LocalServer::start(config)
                .await
                .map_err(|e| crate::errors::McpError::startup(format!("embedded server: {e}")))?;
            tracing::info!(addr = %server.client_addr(), "started the embedded gymfleet server");
            Ok(EmbeddedServer { server })
        }

        /// The address clients connect to.
        pub(super) fn addr(&self) -> String {
            self.server.client_addr()
        }

        /// Stops it and waits for in-flight calls to finish.
        pub(super) async fn stop(self) {
            match self.server.stop().await {
                Ok(()) => tracing::debug!("embedded server stopped"),
                Err(err) => tracing::warn!("embedded server: {err}"),
            }
        }
    }
}
