//! [`LocalServer`]: the one way to run a gymfleet server inside another program — the MCP
//! adapter's and the load client's embedded server, and every test's.
//! It serves on loopback (`127.0.0.1:0`) or on a Unix-domain socket, and clients reach it
//! over gRPC like any other server, or, in the same process, through
//! [`LocalServer::in_process`] without a socket.

use std::convert::Infallible;

use tokio::sync::oneshot;
use tokio::task::JoinHandle;
use tonic::body::Body;
use tonic::codegen::http::{Request, Response};
use tonic::codegen::Service;

use crate::config::ServerConfig;
use crate::error::StartupError;

type Result<T, E = StartupError> = std::result::Result<T, E>;
use crate::listen::{ListenAddr, Listener};

/// A gymfleet server running on a task of the current tokio runtime until
/// [`LocalServer::stop`] (or until it is dropped, which asks it to stop without waiting).
///
/// ```no_run
/// # async fn demo() -> Result<(), gymfleet_server::StartupError> {
/// let server = gymfleet_server::LocalServer::start(gymfleet_server::ServerConfig::default()).await?;
/// let addr = server.client_addr(); // "127.0.0.1:<port>"
/// // ... connect gymfleet-client to `addr` ...
/// server.stop().await?;
/// # Ok(())
/// # }
/// ```
pub struct LocalServer {
    addr: ListenAddr,
    dashboard: Option<std::net::SocketAddr>,
    stop: Option<oneshot::Sender<()>>,
    task: Option<JoinHandle<Result<()>>>,
    in_process: crate::serve::InProcess,
}

impl LocalServer {
    /// Binds `127.0.0.1:0` and serves `config` there. The listener is bound when this
    /// returns, so clients can connect at once. Must be called within a tokio runtime.
    pub async fn start(config: ServerConfig) -> Result<LocalServer> {
        let any_port = ListenAddr::Tcp(std::net::SocketAddr::from(([127, 0, 0, 1], 0)));
        Self::bind(&any_port, config).await
    }

    /// Binds `addr` (`127.0.0.1:0` for a free port, or a Unix-domain socket) and serves
    /// `config` there.
    pub async fn bind(addr: &ListenAddr, config: ServerConfig) -> Result<LocalServer> {
        let listener = Listener::bind(addr).await.map_err(|e| StartupError::Bind {
            addr: addr.to_string(),
            reason: e.to_string(),
        })?;
        let addr = listener.local_addr()?;
        // Bound here, so that its address is known before serving starts.
        let dashboard_listener = crate::dashboard::bind(&config).await?;
        let dashboard = dashboard_listener
            .as_ref()
            .map(tokio::net::TcpListener::local_addr)
            .transpose()?;
        let (stop, stopped) = oneshot::channel::<()>();
        let (ready, service) = oneshot::channel();
        let serving = crate::serve::serve_bound(
            listener,
            dashboard_listener,
            config,
            async move {
                // A dropped sender stops the server too.
                let _ = stopped.await;
            },
            Some(ready),
        );
        let task = tokio::spawn(serving);
        let in_process = match service.await {
            Ok(service) => service,
            // It failed before serving: its error says why.
            Err(_) => {
                return Err(task
                    .await
                    .map_err(|e| StartupError::Panicked(e.to_string()))?
                    .err()
                    .unwrap_or(StartupError::Stopped))
            }
        };
        Ok(LocalServer {
            addr,
            dashboard,
            stop: Some(stop),
            task: Some(task),
            in_process,
        })
    }

    /// Where it listens.
    pub fn addr(&self) -> &ListenAddr {
        &self.addr
    }

    /// Where the dashboard listens (`ServerConfig::dashboard_listen`, its port resolved
    /// when it was 0), if it is on.
    pub fn dashboard_addr(&self) -> Option<std::net::SocketAddr> {
        self.dashboard
    }

    /// The simulator service itself, for a client in this process to call without a
    /// socket (`gymfleet_client::ClientBuilder::in_process`): the same service the
    /// listener serves, behind the same authenticator and message limits, so every call
    /// is what it would be over the network, less the transport. For a server that lives
    /// as long as the clients made this way (the Python package's embedded server):
    /// after [`LocalServer::stop`] their calls still reach the simulation.
    pub fn in_process(
        &self,
    ) -> impl Service<
        Request<Body>,
        Response = Response<Body>,
        Error = Infallible,
        Future: Send + 'static,
    > + Clone
           + Send
           + Sync
           + 'static {
        // The authenticator wraps reply bodies in its own type; a client wants tonic's.
        tower::ServiceExt::<Request<Body>>::map_response(
            self.in_process.clone(),
            |reply: Response<_>| reply.map(Body::new),
        )
    }

    /// The address a client connects to: `127.0.0.1:<port>` or `unix:/path`.
    pub fn client_addr(&self) -> String {
        self.addr.to_string()
    }

    /// Asks the server to stop, and waits for in-flight calls to finish and `serve` to
    /// return.
    pub async fn stop(mut self) -> Result<()> {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        match self.task.take() {
            Some(task) => task
                .await
                .map_err(|e| StartupError::Panicked(e.to_string()))?,
            None => Ok(()),
        }
    }
}

impl std::fmt::Debug for LocalServer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LocalServer")
            .field("addr", &self.addr)
            .field("dashboard", &self.dashboard)
            .finish_non_exhaustive()
    }
}

impl Drop for LocalServer {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
    }
}
