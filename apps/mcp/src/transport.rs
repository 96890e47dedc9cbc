//! How MCP reaches the tools: stdio (the default; stdout carries JSON-RPC only) or
//! streamable HTTP on a loopback address at path `/mcp`. Both return when the client
//! goes away (stdin closed) or on Ctrl-C / SIGTERM.

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use rmcp::transport::streamable_http_server::session::local::LocalSessionManager;
use rmcp::transport::streamable_http_server::tower::StreamableHttpService;
use rmcp::transport::StreamableHttpServerConfig;
use rmcp::ServiceExt;
use tokio::net::TcpListener;

use crate::errors::{McpError, Result};
use crate::fleet::Fleet;
use crate::server::GymTools;

/// How long open HTTP sessions get to wind down after a shutdown signal.
const HTTP_DRAIN: Duration = Duration::from_secs(3);

/// Serves one MCP session on stdin/stdout until stdin closes or a shutdown signal.
pub(crate) async fn serve_stdio(fleet: Arc<Fleet>) -> Result<()> {
    let service = GymTools::new(fleet)
        .serve(rmcp::transport::io::stdio_pipes())
        .await
        .map_err(|e| McpError::startup(format!("MCP over stdio: initialisation failed: {e}")))?;
    let stop = service.cancellation_token();
    tokio::select! {
        quit = service.waiting() => {
            match quit {
                Ok(reason) => tracing::info!(?reason, "MCP session over stdio ended"),
                Err(err) => tracing::warn!("MCP session task failed: {err}"),
            }
        }
        () = tokio_graceful::default_signal() => {
            tracing::info!("interrupted or terminated");
            stop.cancel()
        }
    }
    Ok(())
}

/// Refuses an `--http` address off loopback unless requests need a token
/// (`--http-token`).
pub(crate) fn check_http_addr(addr: SocketAddr, has_token: bool) -> Result<()> {
    if addr.ip().is_loopback() || has_token {
        Ok(())
    } else {
        Err(McpError::startup(format!(
            "--http {addr}: without --http-token, MCP over HTTP is served on loopback only \
             (127.0.0.1 or [::1])"
        )))
    }
}

/// Answers 401 to a request without `Authorization: Bearer <token>`.
async fn require_token(
    axum::extract::State(token): axum::extract::State<Arc<str>>,
    request: axum::extract::Request,
    next: axum::middleware::Next,
) -> axum::response::Response {
    use axum::response::IntoResponse;
    let given = request
        .headers()
        .get(axum::http::header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "));
    if given.is_some_and(|given| constant_time_eq(given.as_bytes(), token.as_bytes())) {
        next.run(request).await
    } else {
        (
            axum::http::StatusCode::UNAUTHORIZED,
            [(axum::http::header::WWW_AUTHENTICATE, "Bearer")],
            "gymfleet-mcp: send `Authorization: Bearer <token>` (the --http-token)\n",
        )
            .into_response()
    }
}

/// Answers a session's `DELETE` (its end) with 204 No Content where rmcp answers 202
/// Accepted: MCP clients (the official Python SDK among them) take 200 or 204 as the
/// session ended, and warn on 202.
async fn session_end_no_content(
    request: axum::extract::Request,
    next: axum::middleware::Next,
) -> axum::response::Response {
    let ending = request.method() == axum::http::Method::DELETE;
    let mut response = next.run(request).await;
    if ending && response.status() == axum::http::StatusCode::ACCEPTED {
        *response.status_mut() = axum::http::StatusCode::NO_CONTENT;
    }
    response
}

/// Compares without stopping at the first difference, so timing says nothing about
/// how much of a guess was right.
fn constant_time_eq(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// Serves MCP over streamable HTTP at `http://addr/mcp` (loopback only) until a shutdown
/// signal. Prints the bound URL on stderr, so that port 0 can be used.
pub(crate) async fn serve_http(
    addr: SocketAddr,
    token: Option<String>,
    fleet: Arc<Fleet>,
) -> Result<()> {
    check_http_addr(addr, token.is_some())?;
    let listener = TcpListener::bind(addr)
        .await
        .map_err(|e| McpError::startup(format!("--http {addr}: cannot bind: {e}")))?;
    let bound = listener
        .local_addr()
        .map_err(|e| McpError::startup(format!("--http {addr}: {e}")))?;
    let config = StreamableHttpServerConfig::default();
    let sessions_stop = config.cancellation_token.clone();
    let service = StreamableHttpService::new(
        move || Ok(GymTools::new(Arc::clone(&fleet))),
        Arc::new(LocalSessionManager::default()),
        config,
    );
    let mut router = axum::Router::new()
        .nest_service("/mcp", service)
        .layer(axum::middleware::from_fn(session_end_no_content));
    if let Some(token) = token {
        router = router.layer(axum::middleware::from_fn_with_state(
            Arc::<str>::from(token),
            require_token,
        ));
    }
    eprintln!("gymfleet-mcp: listening on http://{bound}/mcp");
    tracing::info!(%bound, "serving MCP over streamable HTTP at /mcp");

    let stopping = sessions_stop.clone();
    let serving = axum::serve(listener, router)
        .with_graceful_shutdown(async move { stopping.cancelled().await });
    tokio::select! {
        served = serving => served.map_err(|e| McpError::startup(format!("--http {bound}: {e}"))),
        () = async {
            tokio_graceful::default_signal().await;
            tracing::info!("interrupted or terminated");
            sessions_stop.cancel();
            tokio::time::sleep(HTTP_DRAIN).await;
        } => {
            let drain = HTTP_DRAIN.as_secs();
            tracing::warn!("HTTP sessions still open after {drain} s; stopping anyway");
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn http_listens_off_loopback_only_with_a_token() {
        let loopback: SocketAddr = "127.0.0.1:0".parse().unwrap();
        let anywhere: SocketAddr = "0.0.0.0:8080".parse().unwrap();
        assert!(check_http_addr(loopback, false).is_ok());
        assert!(check_http_addr(anywhere, true).is_ok());
        let err = check_http_addr(anywhere, false).unwrap_err();
        assert_eq!(
            err.to_string(),
            "--http 0.0.0.0:8080: without --http-token, MCP over HTTP is served on loopback \
             only (127.0.0.1 or [::1])"
        );
    }

    #[test]
    fn token_comparison_needs_every_byte() {
        assert!(constant_time_eq(b"secret-token", b"secret-token"));
        assert!(!constant_time_eq(b"secret-token", b"secret-tokem"));
        assert!(!constant_time_eq(b"secret-token", b"secret-toke"));
        assert!(!constant_time_eq(b"", b"x"));
    }
}
