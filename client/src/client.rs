//! [`Client`]: one connection to a gymfleet server.

use std::future::Future;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use gymfleet_proto::v1 as pb;
use pb::simulator_client::SimulatorClient;
use tonic::metadata::{Ascii, MetadataValue};
use tonic::service::interceptor::InterceptedService;
use tonic::service::Interceptor;
use tonic::transport::{Certificate, ClientTlsConfig, Endpoint, Identity};
use tonic::{Request, Status};

use crate::error::{ClientError, Result};
use crate::types::ServerInfo;

/// Largest message the client decodes or encodes by default: 64 MiB, like the server.
pub const DEFAULT_MAX_MESSAGE_BYTES: usize = 64 * 1024 * 1024;
/// Default time to establish a connection: 10 s.
pub const DEFAULT_CONNECT_TIMEOUT: Duration = Duration::from_secs(10);
/// Default interval between HTTP/2 keepalive pings: 5 s.
pub const DEFAULT_KEEPALIVE_INTERVAL: Duration = Duration::from_secs(5);
/// Default wait for a keepalive ping's answer before the connection counts as dead: 10 s.
pub const DEFAULT_KEEPALIVE_TIMEOUT: Duration = Duration::from_secs(10);

/// What a [`Client`] sends its calls through: a network channel, or a simulator service
/// running in this process ([`ClientBuilder::in_process`]).
pub type Transport = tower::util::BoxCloneSyncService<
    tonic::codegen::http::Request<tonic::body::Body>,
    tonic::codegen::http::Response<tonic::body::Body>,
    TransportError,
>;

/// Why a [`Transport`] failed a call (tonic makes a status of it). A named type rather
/// than a boxed error so that the futures around it stay provably `Send`.
#[derive(Debug)]
pub struct TransportError(Box<dyn std::error::Error + Send + Sync>);

impl std::fmt::Display for TransportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for TransportError {
    /// The transport's own error (tonic finds a status in this chain, e.g. a deadline's).
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&*self.0)
    }
}

/// What a [`Transport`] can be made of: a service that answers gRPC calls over HTTP
/// request and reply values (a channel, or a simulator service in this process).
pub trait CallService:
    tower::Service<
        tonic::codegen::http::Request<tonic::body::Body>,
        Response = tonic::codegen::http::Response<tonic::body::Body>,
        Error: Into<Box<dyn std::error::Error + Send + Sync>>,
        Future: Send + 'static,
    > + Clone
    + Send
    + Sync
    + 'static
{
}

impl<S> CallService for S where
    S: tower::Service<
            tonic::codegen::http::Request<tonic::body::Body>,
            Response = tonic::codegen::http::Response<tonic::body::Body>,
            Error: Into<Box<dyn std::error::Error + Send + Sync>>,
            Future: Send + 'static,
        > + Clone
        + Send
        + Sync
        + 'static
{
}

/// `service` as a [`Transport`].
fn transport<S: CallService>(service: S) -> Transport {
    Transport::new(tower::ServiceExt::map_err(service, |e: S::Error| {
        TransportError(e.into())
    }))
}

/// The generated client with this crate's per-call metadata (token, deadline).
pub(crate) type Rpc = SimulatorClient<InterceptedService<Transport, CallMetadata>>;

/// A connection to a gymfleet server. Cloning is cheap and shares the connection.
///
/// ```no_run
/// use gymfleet_client::{ActionType, Client, EnvOptions};
///
/// # async fn demo() -> gymfleet_client::Result<()> {
/// let client = Client::connect("127.0.0.1:50051").await?;
/// let document = std::fs::read_to_string("models/pendulum.json").expect("model");
/// let env = client
///     .create_env(EnvOptions::new(document).end_effectors(["arm"]))
///     .await?;
/// let first = env.reset(Some(0)).await?;
/// let step = env.step(ActionType::Torque, &[2.0]).await?;
/// assert!(step.observation.joint_positions[0] > first.joint_positions[0]);
/// env.close().await?;
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone)]
pub struct Client {
    inner: Rpc,
    addr: Arc<str>,
    /// The largest message this client encodes (0: tonic's default).
    max_message_bytes: usize,
}

tokio::task_local! {
    /// The deadline [`with_deadline`] set for the calls of the current task.
    static CALL_DEADLINE: Instant;
}

/// Runs `future` so that every call it makes (on this task) carries a deadline `timeout`
/// from now, sent as `grpc-timeout`: a server does not start work for it once the
/// deadline has passed. The earlier of this and [`ClientBuilder::timeout`] applies. It
/// does not stop `future` itself (wrap it in `tokio::time::timeout` for that), and calls
/// a fleet fans out to other tasks do not see it.
///
/// ```no_run
/// # async fn demo(env: gymfleet_client::Env) -> gymfleet_client::Result<()> {
/// use std::time::Duration;
/// let step = gymfleet_client::with_deadline(Duration::from_secs(2), env.observe()).await?;
/// # Ok(())
/// # }
/// ```
pub async fn with_deadline<F: Future>(timeout: Duration, future: F) -> F::Output {
    CALL_DEADLINE.scope(Instant::now() + timeout, future).await
}

/// Adds the bearer token and the call deadline to every request (shared: cloned with
/// every call).
#[derive(Debug, Clone, Default)]
pub(crate) struct CallMetadata(Arc<CallSettings>);

#[derive(Debug, Default)]
struct CallSettings {
    authorization: Option<MetadataValue<Ascii>>,
    deadline: Option<Duration>,
}

impl Interceptor for CallMetadata {
    fn call(&mut self, mut request: Request<()>) -> Result<Request<()>, Status> {
        if let Some(value) = &self.0.authorization {
            request
                .metadata_mut()
                .insert("authorization", value.clone());
        }
        let scoped = CALL_DEADLINE
            .try_with(|at| at.saturating_duration_since(Instant::now()))
            .ok();
        let deadline = match (self.0.deadline, scoped) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        if let Some(deadline) = deadline {
            // Sent as `grpc-timeout`: the server stops waiting for a caller that has gone.
            request.set_timeout(deadline);
        }
        Ok(request)
    }
}

/// PEM text, given directly or read from a file when connecting.
#[derive(Clone)]
enum Pem {
    Text(Vec<u8>),
    File(PathBuf),
}

impl Pem {
    fn read(&self, what: &str) -> std::result::Result<Vec<u8>, String> {
        match self {
            Pem::Text(pem) => Ok(pem.clone()),
            Pem::File(path) => {
                std::fs::read(path).map_err(|e| format!("{what} {}: {e}", path.display()))
            }
        }
    }
}

impl std::fmt::Debug for Pem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Pem::Text(pem) => write!(f, "Pem({} bytes)", pem.len()),
            Pem::File(path) => write!(f, "Pem({})", path.display()),
        }
    }
}

/// How to connect: timeouts, keepalive, TLS, token. Made by [`Client::builder`];
/// `Clone`, so one builder can connect a whole fleet ([`crate::Fleet::connect_with`]).
///
/// ```no_run
/// use std::time::Duration;
/// use gymfleet_client::Client;
///
/// # async fn demo() -> gymfleet_client::Result<()> {
/// let client = Client::builder("sim.example.org:50051")
///     .tls_ca_file("ca.pem")
///     .token("team-a-0123456789abcdef")
///     .timeout(Duration::from_secs(30))
///     .connect()
///     .await?;
/// # Ok(())
/// # }
/// ```
#[derive(Clone)]
pub struct ClientBuilder {
    addr: String,
    max_message_bytes: usize,
    connect_timeout: Option<Duration>,
    timeout: Option<Duration>,
    keepalive: Option<(Duration, Duration)>,
    token: Option<String>,
    tls_ca: Option<Pem>,
    tls_identity: Option<(Pem, Pem)>,
    tls_domain: Option<String>,
    lazy: bool,
}

impl std::fmt::Debug for ClientBuilder {
    // The token stays out of logs.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ClientBuilder")
            .field("addr", &self.addr)
            .field("max_message_bytes", &self.max_message_bytes)
            .field("connect_timeout", &self.connect_timeout)
            .field("timeout", &self.timeout)
            .field("keepalive", &self.keepalive)
            .field("token", &self.token.as_ref().map(|_| "(set)"))
            .field("tls_ca", &self.tls_ca)
            .field("tls_identity", &self.tls_identity.as_ref().map(|_| "(set)"))
            .field("tls_domain", &self.tls_domain)
            .field("lazy", &self.lazy)
            .finish()
    }
}

impl ClientBuilder {
    fn new(addr: String) -> Self {
        ClientBuilder {
            addr,
            max_message_bytes: DEFAULT_MAX_MESSAGE_BYTES,
            connect_timeout: Some(DEFAULT_CONNECT_TIMEOUT),
            timeout: None,
            keepalive: Some((DEFAULT_KEEPALIVE_INTERVAL, DEFAULT_KEEPALIVE_TIMEOUT)),
            token: None,
            tls_ca: None,
            tls_identity: None,
            tls_domain: None,
            lazy: false,
        }
    }

    /// The same settings for another address (how a fleet connects each server).
    pub fn for_addr(&self, addr: impl Into<String>) -> Self {
        ClientBuilder {
            addr: addr.into(),
            ..self.clone()
        }
    }

    /// Largest message decoded or encoded (default 64 MiB, like the server's).
    pub fn max_message_bytes(mut self, bytes: usize) -> Self {
        self.max_message_bytes = bytes;
        self
    }

    /// How long establishing the connection may take (default 10 s); `None` waits for
    /// the operating system to give up.
    pub fn connect_timeout(mut self, timeout: Option<Duration>) -> Self {
        self.connect_timeout = timeout;
        self
    }

    /// Every call's deadline (default none): a call without an answer by then fails
    /// with [`ClientError::DeadlineExceeded`], and the server is told (`grpc-timeout`)
    /// so it does not start work for a caller that has gone. Mind large batch steps: the
    /// deadline covers the whole call.
    pub fn timeout(mut self, timeout: Duration) -> Self {
        self.timeout = Some(timeout);
        self
    }

    /// HTTP/2 keepalive: a ping every `interval`, and a connection whose ping is not
    /// answered within `timeout` is dead, so calls on a partitioned server fail within
    /// seconds, however long a legitimate step takes (default 5 s and 10 s). `None`
    /// turns pings off.
    pub fn keepalive(mut self, interval_and_timeout: Option<(Duration, Duration)>) -> Self {
        self.keepalive = interval_and_timeout;
        self
    }

    /// Sends `authorization: Bearer <token>` with every call (servers run with
    /// `--auth-tokens`).
    pub fn token(mut self, token: impl Into<String>) -> Self {
        self.token = Some(token.into());
        self
    }

    /// Connects with TLS, trusting the CA certificate(s) in this PEM text.
    pub fn tls_ca_pem(mut self, pem: impl Into<Vec<u8>>) -> Self {
        self.tls_ca = Some(Pem::Text(pem.into()));
        self
    }

    /// Connects with TLS, trusting the CA certificate(s) in this PEM file (read when
    /// connecting).
    pub fn tls_ca_file(mut self, path: impl Into<PathBuf>) -> Self {
        self.tls_ca = Some(Pem::File(path.into()));
        self
    }

    /// Presents this client certificate and key (PEM files) to a server that asks for
    /// one (mutual TLS, `--tls-client-ca`).
    pub fn tls_identity_files(mut self, cert: impl Into<PathBuf>, key: impl Into<PathBuf>) -> Self {
        self.tls_identity = Some((Pem::File(cert.into()), Pem::File(key.into())));
        self
    }

    /// [`ClientBuilder::tls_identity_files`] from PEM text.
    pub fn tls_identity_pem(mut self, cert: impl Into<Vec<u8>>, key: impl Into<Vec<u8>>) -> Self {
        self.tls_identity = Some((Pem::Text(cert.into()), Pem::Text(key.into())));
        self
    }

    /// The name the server's certificate must carry, when it differs from the
    /// address's host (e.g. connecting by IP address).
    pub fn tls_domain(mut self, name: impl Into<String>) -> Self {
        self.tls_domain = Some(name.into());
        self
    }

    /// Returns at once and connects on the first call (default: connect now, so a
    /// wrong address fails here).
    pub fn lazy(mut self, lazy: bool) -> Self {
        self.lazy = lazy;
        self
    }

    fn tls(&self) -> std::result::Result<Option<ClientTlsConfig>, String> {
        if self.tls_ca.is_none() && self.tls_identity.is_none() && self.tls_domain.is_none() {
            return Ok(None);
        }
        let mut tls = ClientTlsConfig::new();
        if let Some(ca) = &self.tls_ca {
            tls = tls.ca_certificate(Certificate::from_pem(ca.read("TLS CA file")?));
        }
        if let Some((cert, key)) = &self.tls_identity {
            tls = tls.identity(Identity::from_pem(
                cert.read("TLS client certificate")?,
                key.read("TLS client key")?,
            ));
        }
        if let Some(domain) = &self.tls_domain {
            tls = tls.domain_name(domain.clone());
        }
        Ok(Some(tls))
    }

    fn endpoint(&self) -> std::result::Result<Endpoint, String> {
        let tls = self.tls()?;
        let addr = &self.addr;
        let uri = if addr.contains("://") || addr.starts_with("unix:") {
            addr.clone()
        } else if tls.is_some() {
            format!("https://{addr}")
        } else {
            format!("http://{addr}")
        };
        let mut endpoint = Endpoint::from_shared(uri)
            .map_err(|e| error_chain(&e))?
            .tcp_nodelay(true);
        if let Some(timeout) = self.connect_timeout {
            endpoint = endpoint.connect_timeout(timeout);
        }
        if let Some(timeout) = self.timeout {
            endpoint = endpoint.timeout(timeout);
        }
        if let Some((interval, timeout)) = self.keepalive {
            endpoint = endpoint
                .http2_keep_alive_interval(interval)
                .keep_alive_timeout(timeout)
                .keep_alive_while_idle(true);
        }
        if let Some(tls) = tls {
            endpoint = endpoint.tls_config(tls).map_err(|e| error_chain(&e))?;
        }
        Ok(endpoint)
    }

    /// Connects (or, with [`ClientBuilder::lazy`], prepares to).
    pub async fn connect(self) -> Result<Client> {
        let authorization = self.authorization()?;
        let endpoint = self.endpoint().map_err(|reason| ClientError::Setting {
            addr: self.addr.clone(),
            reason,
        })?;
        let channel = if self.lazy {
            endpoint.connect_lazy()
        } else {
            endpoint.connect().await.map_err(|e| ClientError::Connect {
                addr: self.addr.clone(),
                reason: error_chain(&e),
            })?
        };
        self.over(transport(channel), authorization)
    }

    /// A client that calls `service`, a `gymfleet.v1.Simulator` service running in this
    /// process (the server crate's `LocalServer::in_process`), with no socket or HTTP/2
    /// framing between them: requests and replies are still encoded, checked and limited
    /// as over a network. The token, the message limit and the per-call deadline apply
    /// (a call past it fails with DEADLINE_EXCEEDED and is dropped, so the server drops
    /// its work as for a caller gone); TLS, keepalive and the connect settings have
    /// nothing to do. [`Client::addr`] is this builder's address.
    pub fn in_process(self, service: impl CallService) -> Result<Client> {
        let authorization = self.authorization()?;
        match self.timeout {
            // No network layer enforces the deadline here: this side does, as a channel
            // would, with the server's status for it.
            Some(deadline) => {
                let timed = tower::timeout::Timeout::new(service, deadline);
                let timed = tower::ServiceExt::map_err(timed, move |err| {
                    if err.is::<tower::timeout::error::Elapsed>() {
                        Box::new(Status::deadline_exceeded(format!(
                            "the call took longer than its deadline of {deadline:?}"
                        ))) as Box<dyn std::error::Error + Send + Sync>
                    } else {
                        err
                    }
                });
                self.over(transport(timed), authorization)
            }
            None => self.over(transport(service), authorization),
        }
    }

    /// The token as the `authorization` metadata value, if there is one.
    fn authorization(&self) -> Result<Option<MetadataValue<Ascii>>> {
        let Some(token) = &self.token else {
            return Ok(None);
        };
        format!("Bearer {token}")
            .parse::<MetadataValue<Ascii>>()
            .map(Some)
            .map_err(|_| ClientError::Setting {
                addr: self.addr.clone(),
                reason: "the token must be printable ASCII without spaces".into(),
            })
    }

    fn over(
        self,
        transport: Transport,
        authorization: Option<MetadataValue<Ascii>>,
    ) -> Result<Client> {
        let metadata = CallMetadata(Arc::new(CallSettings {
            authorization,
            deadline: self.timeout,
        }));
        let inner = SimulatorClient::with_interceptor(transport, metadata)
            .max_decoding_message_size(self.max_message_bytes)
            .max_encoding_message_size(self.max_message_bytes);
        Ok(Client {
            inner,
            addr: self.addr.into(),
            max_message_bytes: self.max_message_bytes,
        })
    }
}

impl Client {
    /// Connects to `addr`, given as `"host:port"`, `"http://host:port"`, or
    /// `"unix:/path/to/socket"` for a server listening on a Unix-domain socket, with the
    /// default settings. [`Client::builder`] sets timeouts, TLS and a token.
    pub async fn connect(addr: impl Into<String>) -> Result<Self> {
        Self::builder(addr).connect().await
    }

    /// [`Client::connect`], decoding and encoding messages of up to `max_message_bytes`.
    pub async fn connect_with_limit(
        addr: impl Into<String>,
        max_message_bytes: usize,
    ) -> Result<Self> {
        Self::builder(addr)
            .max_message_bytes(max_message_bytes)
            .connect()
            .await
    }

    /// Settings for a connection to `addr` (`host:port`, `http://` or `https://host:port`,
    /// or `unix:/path`): connect timeout, per-call deadline, keepalive, TLS, token, lazy
    /// connect.
    pub fn builder(addr: impl Into<String>) -> ClientBuilder {
        ClientBuilder::new(addr.into())
    }

    /// The address this client was connected to, as given to [`Client::connect`].
    pub fn addr(&self) -> &str {
        &self.addr
    }

    pub(crate) fn rpc(&self) -> Rpc {
        self.inner.clone()
    }

    /// Refuses a request whose encoding would exceed the message limit, naming its parts,
    /// before anything is sent (over the limit, the transport would only say that the
    /// stream broke).
    pub(crate) fn check_request_size(
        &self,
        request: &impl prost::Message,
        document: usize,
        assets: usize,
    ) -> Result<()> {
        let bytes = request.encoded_len();
        let max = self.max_message_bytes;
        if max == 0 || bytes <= max {
            return Ok(());
        }
        Err(crate::error::ClientError::InvalidArgument {
            reason: crate::ErrorReason::InvalidDocument,
            message: format!(
                "request: {bytes} bytes ({document} of document, {assets} of assets) is over the \
                 message limit of {max} bytes; send only the files the description references \
                 (its own package folder), or raise the server's --max-message-bytes and \
                 ClientBuilder::max_message_bytes together"
            ),
        })
    }

    /// The server's version, thread count, load and limits.
    pub async fn server_info(&self) -> Result<ServerInfo> {
        let info = self
            .rpc()
            .get_server_info(pb::GetServerInfoRequest {})
            .await?;
        Ok(info.into_inner().into())
    }
}

/// An error and its sources, joined (tonic's transport errors say little on their own).
fn error_chain(err: &(dyn std::error::Error + 'static)) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(s) = source {
        // hyper and tonic often repeat their source's text in their own message
        // ("tcp connect error: tcp connect error: ..."): add only what is new.
        let part = s.to_string();
        if !text.ends_with(&part) {
            text.push_str(": ");
            text.push_str(&part);
        }
        source = s.source();
    }
    text
}

#[cfg(test)]
mod tests;
