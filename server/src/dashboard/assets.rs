//! The dashboard's page and static files, all embedded in the binary: the page, its
//! script and style (`server/dashboard/`), and three.js r170 with its OrbitControls,
//! the same pinned files the HTML replay embeds (`client/assets/three/`, whose README
//! gives their sha256 sums). Nothing is fetched from the internet.

use std::sync::{Arc, OnceLock};

use axum::http::header::{
    CACHE_CONTROL, CONTENT_SECURITY_POLICY, CONTENT_TYPE, REFERRER_POLICY, X_CONTENT_TYPE_OPTIONS,
    X_FRAME_OPTIONS,
};
use axum::http::HeaderValue;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;

use super::state::Dashboard;

const PAGE: &str = include_str!("../../dashboard/index.html");
const SCRIPT: &str = include_str!("../../dashboard/dashboard.js");
const VIEWER: &str = include_str!("../../dashboard/viewer.js");
const STYLE: &str = include_str!("../../dashboard/dashboard.css");
const ICON: &str = include_str!("../../dashboard/icon.svg");
const THREE: &str = include_str!("../../../client/assets/three/three.module.min.js");
const ORBIT_CONTROLS: &str = include_str!("../../../client/assets/three/OrbitControls.js");
const THREE_LICENSE: &str = include_str!("../../../client/assets/three/LICENSE");

/// Only the dashboard's own files may run, style or be fetched: no inline script, no
/// other origin, no frames around it, no form posting anywhere.
const POLICY: &str = "default-src 'none'; script-src 'self'; style-src 'self'; \
                      img-src 'self'; connect-src 'self'; base-uri 'none'; \
                      form-action 'none'; frame-ancestors 'none'";

const JS: &str = "text/javascript; charset=utf-8";

/// OrbitControls imports the bare name `three`, which only an import map resolves; the
/// policy allows no inline script (an import map is one), so the dashboard serves it
/// importing three.js by its path instead.
fn orbit_controls() -> &'static str {
    static SERVED: OnceLock<String> = OnceLock::new();
    SERVED.get_or_init(|| ORBIT_CONTROLS.replacen("from 'three';", "from './three.js';", 1))
}

fn file(content_type: &'static str, body: &'static str) -> Response {
    (
        [(CONTENT_TYPE, content_type), (CACHE_CONTROL, "no-cache")],
        body,
    )
        .into_response()
}

/// The page and its files.
pub(super) fn routes() -> Router<Arc<Dashboard>> {
    Router::new()
        .route(
            "/",
            get(|| async { file("text/html; charset=utf-8", PAGE) }),
        )
        .route("/assets/dashboard.js", get(|| async { file(JS, SCRIPT) }))
        .route("/assets/viewer.js", get(|| async { file(JS, VIEWER) }))
        .route(
            "/assets/dashboard.css",
            get(|| async { file("text/css; charset=utf-8", STYLE) }),
        )
        .route(
            "/assets/icon.svg",
            get(|| async { file("image/svg+xml", ICON) }),
        )
        .route("/assets/three.js", get(|| async { file(JS, THREE) }))
        .route(
            "/assets/OrbitControls.js",
            get(|| async { file(JS, orbit_controls()) }),
        )
        .route(
            "/assets/three-LICENSE.txt",
            get(|| async { file("text/plain; charset=utf-8", THREE_LICENSE) }),
        )
}

/// Adds the headers every answer carries: the content security policy, no MIME
/// sniffing, no framing, no referrer.
pub(super) async fn security_headers(mut response: Response) -> Response {
    let headers = response.headers_mut();
    headers.insert(CONTENT_SECURITY_POLICY, HeaderValue::from_static(POLICY));
    headers.insert(X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
    headers.insert(X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    headers.insert(REFERRER_POLICY, HeaderValue::from_static("no-referrer"));
    response
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_controls_import_three_by_path() {
        assert!(ORBIT_CONTROLS.contains("from 'three';"));
        let served = orbit_controls();
        assert!(!served.contains("from 'three'"));
        assert!(served.contains("from './three.js';"));
    }

    #[test]
    fn the_page_loads_only_its_own_files() {
        // No inline script (the policy would block it) and nothing from elsewhere.
        assert!(PAGE.contains(r#"<script type="module" src="/assets/dashboard.js"></script>"#));
        assert_eq!(PAGE.matches("<script").count(), 1);
        for page in [PAGE, SCRIPT, VIEWER, STYLE] {
            assert!(!page.contains("http://") && !page.contains("https://"));
            assert!(
                !page.contains("innerHTML"),
                "names are written as text only"
            );
        }
    }
}
