//! The dashboard's JSON API: who the caller is (a session's tenant, or the anonymous one
//! when auth is off), logging in and out, the overview and scenes. Every error is
//! `{"error": "…"}` with its status.

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::{Path, State};
use axum::http::header::{CACHE_CONTROL, CONTENT_TYPE, HOST, SET_COOKIE};
use axum::http::{HeaderMap, Method, StatusCode, Uri};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use serde_json::{json, Value};

use super::json as wire;
use super::session;
use super::state::{Dashboard, MAX_LISTED, RATE_WINDOW};
use crate::domain::DrawsOf;
use crate::error::{Echo, ServerError};
use crate::tenant::Tenant;

/// Largest accepted login body.
const MAX_LOGIN_BYTES: usize = 4096;

/// A refused call: its status and what to say.
#[derive(Debug)]
pub(super) struct ApiError(StatusCode, String);

impl ApiError {
    fn not_logged_in() -> Self {
        ApiError(
            StatusCode::UNAUTHORIZED,
            "not logged in: this server requires a token; POST it to /api/login as \
             {\"token\": \"…\"} (a session lasts 12 hours)"
                .to_string(),
        )
    }
}

impl From<ServerError> for ApiError {
    fn from(err: ServerError) -> Self {
        let status = match err.code() {
            tonic::Code::NotFound => StatusCode::NOT_FOUND,
            tonic::Code::InvalidArgument => StatusCode::BAD_REQUEST,
            tonic::Code::Unavailable => StatusCode::SERVICE_UNAVAILABLE,
            _ => StatusCode::INTERNAL_SERVER_ERROR,
        };
        ApiError(status, err.to_string())
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let body = wire::inert(&json!({ "error": self.1 }));
        (self.0, json_headers(), body).into_response()
    }
}

fn json_headers() -> [(axum::http::HeaderName, &'static str); 2] {
    [
        (CONTENT_TYPE, "application/json"),
        (CACHE_CONTROL, "no-store"),
    ]
}

/// `value` as a 200 answer.
fn ok(value: &Value) -> Response {
    (json_headers(), wire::inert(value)).into_response()
}

type Answer = Result<Response, ApiError>;

/// The API's routes.
pub(super) fn routes() -> Router<Arc<Dashboard>> {
    Router::new()
        .route("/api/session", get(session_info))
        .route("/api/login", post(login))
        .route("/api/logout", post(logout))
        .route("/api/overview", get(overview))
        .route("/api/envs/{id}/scene", get(env_scene))
        .route("/api/batches/{id}/envs/{index}/scene", get(batch_scene))
        .fallback(not_found)
}

/// Whether `host` (a `Host` header: name or address, perhaps with a port) is this
/// machine's loopback.
fn is_loopback_host(host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        // [::1]:8080
        Some(rest) => rest.split(']').next().unwrap_or_default(),
        None => host.rsplit_once(':').map_or(host, |(name, _)| name),
    };
    name.eq_ignore_ascii_case("localhost")
        || name
            .parse::<std::net::IpAddr>()
            .is_ok_and(|ip| ip.is_loopback())
}

impl Dashboard {
    /// Who is asking: the tenant of the request's session, or, with auth off, the
    /// anonymous tenant, provided the request was addressed to a loopback host (a page of
    /// another site that rebinds its name to 127.0.0.1 is refused).
    fn caller(&self, headers: &HeaderMap) -> Result<Tenant, ApiError> {
        if self.tokens.is_some() {
            return self
                .sessions
                .tenant(headers)
                .ok_or_else(ApiError::not_logged_in);
        }
        let host = headers
            .get(HOST)
            .and_then(|h| h.to_str().ok())
            .unwrap_or_default();
        if is_loopback_host(host) {
            Ok(Tenant::anonymous())
        } else {
            Err(ApiError(
                StatusCode::FORBIDDEN,
                format!(
                    "this dashboard runs without --auth-tokens, so it answers only requests \
                     addressed to this machine's loopback (localhost, 127.0.0.1, [::1]); \
                     got Host: {}",
                    Echo(host)
                ),
            ))
        }
    }
}

async fn session_info(State(d): State<Arc<Dashboard>>, headers: HeaderMap) -> Answer {
    let auth = d.tokens.is_some();
    Ok(match d.caller(&headers) {
        Ok(tenant) => ok(&json!({ "auth": auth, "logged_in": true, "tenant": tenant.name() })),
        // Not logged in is an answer here, not a failure: the page then asks for a token.
        Err(ApiError(StatusCode::UNAUTHORIZED, _)) => {
            ok(&json!({ "auth": auth, "logged_in": false, "tenant": null }))
        }
        Err(err) => return Err(err),
    })
}

async fn login(State(d): State<Arc<Dashboard>>, headers: HeaderMap, body: Bytes) -> Answer {
    let Some(tokens) = &d.tokens else {
        return Err(ApiError(
            StatusCode::BAD_REQUEST,
            "this server runs without --auth-tokens: there is nothing to log in to".into(),
        ));
    };
    let json_body = headers
        .get(CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.trim_start().starts_with("application/json"));
    if !json_body {
        // A cross-site form cannot send this type without the browser asking first.
        return Err(ApiError(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "POST /api/login takes Content-Type: application/json".into(),
        ));
    }
    let token = serde_json::from_slice::<Value>(&body)
        .ok()
        .filter(|_| body.len() <= MAX_LOGIN_BYTES)
        .and_then(|v| v.get("token").and_then(Value::as_str).map(str::to_string))
        .ok_or_else(|| {
            ApiError(
                StatusCode::BAD_REQUEST,
                "the body must be JSON: {\"token\": \"…\"}".into(),
            )
        })?;
    let tenant = tokens.tenant(token.trim()).cloned().ok_or_else(|| {
        d.sim.metrics().reject("unauthenticated");
        ApiError(StatusCode::UNAUTHORIZED, "unknown token".into())
    })?;
    // A new login replaces the session the browser had, if any.
    d.sessions.end(&headers);
    let id = d.sessions.start(tenant.clone()).ok_or_else(|| {
        ApiError(
            StatusCode::SERVICE_UNAVAILABLE,
            "cannot start a session: the operating system's random source failed".into(),
        )
    })?;
    tracing::info!(tenant = %tenant, "dashboard login");
    let mut answer = ok(&json!({ "auth": true, "logged_in": true, "tenant": tenant.name() }));
    if let Ok(cookie) = session::set_cookie(&id).parse() {
        answer.headers_mut().insert(SET_COOKIE, cookie);
    }
    Ok(answer)
}

async fn logout(State(d): State<Arc<Dashboard>>, headers: HeaderMap) -> Answer {
    d.sessions.end(&headers);
    let mut answer = ok(&json!({ "logged_in": false }));
    if let Ok(cookie) = session::clear_cookie().parse() {
        answer.headers_mut().insert(SET_COOKIE, cookie);
    }
    Ok(answer)
}

async fn overview(State(d): State<Arc<Dashboard>>, headers: HeaderMap) -> Answer {
    let tenant = d.caller(&headers)?;
    let now = d.clock.elapsed();
    let watching = d.sim.watching(&tenant, MAX_LISTED);
    let list = |(total, items): &(usize, Vec<crate::registry::Watched>)| {
        let items: Vec<Value> = items
            .iter()
            .map(|w| wire::watched(w, w.activity.rates(now, RATE_WINDOW)))
            .collect();
        json!({ "total": total, "items": items })
    };
    let status = d.sim.status(&tenant);
    let stats = d.sim.job_queue();
    let rates = d.pool_rates(stats);
    Ok(ok(&json!({
        "auth": d.tokens.is_some(),
        "tenant": tenant.name(),
        "server": {
            "version": env!("CARGO_PKG_VERSION"),
            "instance_id": status.instance_id,
            "threads": status.threads,
            "batch_envs": status.batch_envs,
        },
        "pool": wire::pool(
            status.threads,
            stats,
            rates.map(|r| r.jobs_per_s),
            rates.map(|r| r.mean_wait_s),
        ),
        "envs": list(&watching.envs),
        "batches": list(&watching.batches),
    })))
}

async fn env_scene(
    State(d): State<Arc<Dashboard>>,
    headers: HeaderMap,
    Path(id): Path<String>,
) -> Answer {
    let tenant = d.caller(&headers)?;
    let scene = d.sim.watch_scene(&tenant, DrawsOf::Env(id.clone())).await?;
    Ok(ok(&wire::scene(&id, None, &scene)))
}

async fn batch_scene(
    State(d): State<Arc<Dashboard>>,
    headers: HeaderMap,
    Path((id, index)): Path<(String, String)>,
) -> Answer {
    let tenant = d.caller(&headers)?;
    let index: usize = index.parse().map_err(|_| {
        ApiError(
            StatusCode::BAD_REQUEST,
            format!(
                "env index: expected a whole number from 0, got {}",
                Echo(&index)
            ),
        )
    })?;
    let target = DrawsOf::BatchEnv(id.clone(), index);
    let scene = d.sim.watch_scene(&tenant, target).await?;
    Ok(ok(&wire::scene(&id, Some(index), &scene)))
}

async fn not_found(method: Method, uri: Uri) -> ApiError {
    ApiError(
        StatusCode::NOT_FOUND,
        format!("no such page: {method} {}", Echo(uri.path())),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_hosts_are_recognised() {
        for host in [
            "localhost",
            "LOCALHOST:80",
            "127.0.0.1:8080",
            "127.9.9.9",
            "[::1]:80",
            "[::1]",
        ] {
            assert!(is_loopback_host(host), "{host}");
        }
        for host in [
            "",
            "evil.example",
            "evil.example:8080",
            "10.0.0.1:80",
            "localhost.evil.example",
            "[::2]:1",
        ] {
            assert!(!is_loopback_host(host), "{host}");
        }
    }
}
