//! [`Client`]: one connection to a gymfleet server.

use std::sync::Arc;

use gymfleet_proto::v1 as pb;
use pb::simulator_client::SimulatorClient;
use tonic::transport::{Channel, Endpoint};

use crate::error::{ClientError, Result};
use crate::types::ServerInfo;

/// Largest message the client decodes or encodes by default: 64 MiB, like the server.
pub const DEFAULT_MAX_MESSAGE_BYTES: usize = 64 * 1024 * 1024;

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
    inner: SimulatorClient<Channel>,
    addr: Arc<str>,
}

impl Client {
    /// Connects to `addr`, given as `"host:port"`, `"http://host:port"`, or
    /// `"unix:/path/to/socket"` for a server listening on a Unix-domain socket.
    pub async fn connect(addr: impl Into<String>) -> Result<Self> {
        Self::connect_with_limit(addr, DEFAULT_MAX_MESSAGE_BYTES).await
    }

    /// [`Client::connect`], decoding and encoding messages of up to `max_message_bytes`.
    pub async fn connect_with_limit(
        addr: impl Into<String>,
        max_message_bytes: usize,
    ) -> Result<Self> {
        let addr = addr.into();
        let uri = if addr.contains("://") || addr.starts_with("unix:") {
            addr.clone()
        } else {
            format!("http://{addr}")
        };
        let connect_error = |reason: String| ClientError::Connect {
            addr: addr.clone(),
            reason,
        };
        let endpoint = Endpoint::from_shared(uri)
            .map_err(|e| connect_error(error_chain(&e)))?
            .tcp_nodelay(true);
        let channel = endpoint
            .connect()
            .await
            .map_err(|e| connect_error(error_chain(&e)))?;
        let inner = SimulatorClient::new(channel)
            .max_decoding_message_size(max_message_bytes)
            .max_encoding_message_size(max_message_bytes);
        Ok(Client {
            inner,
            addr: addr.into(),
        })
    }

    /// The address this client was connected to, as given to [`Client::connect`].
    pub fn addr(&self) -> &str {
        &self.addr
    }

    pub(crate) fn rpc(&self) -> SimulatorClient<Channel> {
        self.inner.clone()
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
mod tests {
    use super::*;

    #[tokio::test]
    async fn unreachable_servers_are_connect_errors() {
        // A port that was just free: nothing listens on it.
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        drop(listener);
        let err = Client::connect(addr.clone()).await.unwrap_err();
        assert!(
            matches!(&err, ClientError::Connect { addr: a, .. } if *a == addr),
            "{err:?}"
        );
        let text = err.to_string();
        assert!(text.contains("refused"), "{text}");
        assert!(
            !text.contains("tcp connect error: tcp connect error"),
            "each cause once: {text}"
        );
        let err = Client::connect("http://[not an address").await.unwrap_err();
        assert!(matches!(err, ClientError::Connect { .. }), "{err:?}");
    }
}
