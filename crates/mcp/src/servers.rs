//! [`Servers`]: where the simulator runs. Either the gymfleet servers named with
//! `--server`, or, with no address and the `embedded` feature (on by default), a
//! gymfleet server started inside this process on 127.0.0.1 with a free port, which the
//! adapter still reaches over loopback gRPC like any other.

use crate::cli::Cli;

/// The servers in use, and the embedded one to stop at the end, if any.
#[derive(Debug)]
pub(crate) struct Servers {
    addrs: Vec<String>,
    #[cfg(feature = "embedded")]
    embedded: Option<embedded::EmbeddedServer>,
}

impl Servers {
    /// The servers of `cli`: its `--server` addresses, or an embedded server.
    pub(crate) async fn start(cli: &Cli) -> Result<Self, String> {
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
            let server = embedded::EmbeddedServer::start(cli.threads).await?;
            Ok(Servers {
                addrs: vec![server.addr.to_string()],
                embedded: Some(server),
            })
        }
        #[cfg(not(feature = "embedded"))]
        Err(
            "no gymfleet server given: pass --server HOST:PORT (or set GYMFLEET_SERVER). \
             This build has no embedded server (it was built without the `embedded` feature)."
                .to_string(),
        )
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
    use std::net::SocketAddr;
    use std::time::Duration;

    use gymfleet_server::{ServerConfig, ServerError};
    use tokio::net::TcpListener;
    use tokio::sync::oneshot;
    use tokio::task::JoinHandle;

    /// A gymfleet server serving on loopback inside this process.
    #[derive(Debug)]
    pub(super) struct EmbeddedServer {
        pub(super) addr: SocketAddr,
        stop: oneshot::Sender<()>,
        task: JoinHandle<Result<(), ServerError>>,
    }

    impl EmbeddedServer {
        /// Binds 127.0.0.1:0 and serves there with `threads` pool threads (0 = one per
        /// core). It never reclaims idle envs: they live as long as this process, which
        /// closes them at exit.
        pub(super) async fn start(threads: usize) -> Result<Self, String> {
            let listener = TcpListener::bind("127.0.0.1:0")
                .await
                .map_err(|e| format!("embedded server: cannot bind 127.0.0.1:0: {e}"))?;
            let addr = listener
                .local_addr()
                .map_err(|e| format!("embedded server: {e}"))?;
            let config = ServerConfig {
                threads,
                idle_ttl: Duration::ZERO,
                ..ServerConfig::default()
            };
            let (stop, stopped) = oneshot::channel::<()>();
            let task = tokio::spawn(gymfleet_server::serve(listener, config, async {
                stopped.await.ok();
            }));
            tracing::info!(%addr, "started the embedded gymfleet server");
            Ok(EmbeddedServer { addr, stop, task })
        }

        /// Stops it and waits for in-flight calls to finish.
        pub(super) async fn stop(self) {
            let _ = self.stop.send(());
            match self.task.await {
                Ok(Ok(())) => tracing::debug!("embedded server stopped"),
                Ok(Err(err)) => tracing::warn!("embedded server: {err}"),
                Err(err) => tracing::warn!("embedded server task: {err}"),
            }
        }
    }
}
