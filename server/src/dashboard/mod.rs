//! `--dashboard-listen`: a read-only web page that shows what the server is doing (the
//! caller's envs and batches with their step rates and episode counts, the pool's queue
//! and wait, and any env, single or one of a batch, moving in 3D), and the JSON API the
//! page reads, since browsers cannot speak gRPC.
//!
//! | route | answer |
//! |---|---|
//! | `GET /` | the page (`server/dashboard/index.html`) |
//! | `GET /assets/…` | its script, style and icon, and three.js r170 (the HTML replay's pinned copy) |
//! | `GET /api/session` | `{auth, logged_in, tenant}` |
//! | `POST /api/login` | `{"token": "…"}` (JSON) → a session cookie |
//! | `POST /api/logout` | ends the session |
//! | `GET /api/overview` | the server, the pool, the caller's envs and batches |
//! | `GET /api/envs/{id}/scene` | an env's shapes and poses |
//! | `GET /api/batches/{id}/envs/{index}/scene` | the same for env `index` of a batch |
//!
//! It reads the same registries as the gRPC service ([`Simulation::watching`],
//! [`Simulation::watch_scene`]) through lookups that never mark an entry used, and a scene
//! under the entry's lock on the pool: no CPU work runs on tokio workers. Everything is
//! embedded (`include_str!`): no build step, nothing fetched from the internet.
//!
//! Security: with auth on, the page asks for a token once; `POST /api/login` maps it to
//! a random session id kept server-side and set as an `HttpOnly; SameSite=Strict` cookie
//! (the token is never in a URL), and every API call sees only the session's tenant. With
//! auth off the server refuses any address but loopback ([`check_listen`]), and answers
//! only requests addressed to a loopback host (no DNS rebinding). Names from documents
//! go out JSON-escaped with `<`, `>` and `&` as `\u` escapes, and the page writes them
//! with `textContent` only; a strict Content-Security-Policy allows no inline script.

mod api;
mod assets;
mod json;
mod session;
mod state;

use std::future::IntoFuture;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use tokio::net::TcpListener;
use tokio::sync::watch;

use crate::config::ServerConfig;
use crate::error::StartupError;

type Result<T, E = StartupError> = std::result::Result<T, E>;
use crate::simulation::Simulation;

/// How long a dashboard waits, at shutdown, for its requests in flight.
const SHUTDOWN_GRACE: Duration = Duration::from_secs(5);

/// Refuses a dashboard on an address other than loopback when auth is off: anyone who
/// could reach it would see every env.
pub(crate) fn check_listen(addr: SocketAddr, auth: bool) -> Result<()> {
    if auth || addr.ip().is_loopback() {
        return Ok(());
    }
    Err(StartupError::Bind {
        addr: addr.to_string(),
        reason: "a dashboard on an address other than loopback needs --auth-tokens \
                 (GYMFLEET_AUTH_TOKENS): without tokens, anyone who reaches the port sees \
                 every env; serve it on 127.0.0.1 (through an SSH tunnel, say) or turn auth on"
            .to_string(),
    })
}

/// Checks and binds `config.dashboard_listen`, if set.
pub(crate) async fn bind(config: &ServerConfig) -> Result<Option<TcpListener>> {
    let Some(addr) = config.dashboard_listen else {
        return Ok(None);
    };
    check_listen(addr, config.auth_tokens.is_some())?;
    let listener = TcpListener::bind(addr)
        .await
        .map_err(|e| StartupError::Bind {
            addr: addr.to_string(),
            reason: e.to_string(),
        })?;
    Ok(Some(listener))
}

/// Serves the dashboard on `listener` until `stop` turns true, then waits (a few seconds
/// at most) for the requests in flight.
pub(crate) async fn serve_dashboard(
    listener: TcpListener,
    sim: Arc<Simulation>,
    config: ServerConfig,
    mut stop: watch::Receiver<bool>,
) {
    let dashboard = Arc::new(state::Dashboard::new(sim, &config));
    let app = assets::routes()
        .merge(api::routes())
        .with_state(dashboard)
        .layer(axum::middleware::map_response(assets::security_headers));
    let mut grace = stop.clone();
    let stopping = async move {
        // An error means the server is gone: stop as well.
        let _ = stop.wait_for(|stop| *stop).await;
    };
    let served = axum::serve(listener, app)
        .with_graceful_shutdown(stopping)
        .into_future();
    // Once the stop signal has come, the grace period bounds the wait for open requests.
    let grace = async move {
        let _ = grace.wait_for(|stop| *stop).await;
        tokio::time::sleep(SHUTDOWN_GRACE).await;
    };
    let result = tokio::select! {
        result = served => result,
        () = grace => Ok(()),
    };
    if let Err(err) = result {
        tracing::error!(%err, "dashboard failed");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_loopback_is_served_without_auth() {
        let any: SocketAddr = ([0, 0, 0, 0], 8080).into();
        let err = check_listen(any, false).unwrap_err().to_string();
        assert!(
            err.starts_with("cannot listen on 0.0.0.0:8080: a dashboard on an address"),
            "{err}"
        );
        let v6_any: SocketAddr = "[::]:8080".parse().unwrap();
        assert!(check_listen(v6_any, false).is_err());
        let lan: SocketAddr = ([192, 168, 1, 5], 8080).into();
        assert!(check_listen(lan, false).is_err());
        for ok in ["127.0.0.1:8080", "127.1.2.3:0", "[::1]:8080"] {
            assert!(check_listen(ok.parse().unwrap(), false).is_ok(), "{ok}");
        }
        assert!(
            check_listen(any, true).is_ok(),
            "with auth any address will do"
        );
    }
}
