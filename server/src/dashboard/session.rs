//! The dashboard's sessions: a token given once to `POST /api/login` becomes a random
//! session id, kept here with its tenant and sent back as an `HttpOnly; SameSite=Strict`
//! cookie. The token itself is never stored in the browser nor put in a URL.

use std::collections::HashMap;
use std::sync::{Mutex, PoisonError};
use std::time::Duration;

use axum::http::header::COOKIE;
use axum::http::HeaderMap;

use crate::clock::Clock;
use crate::tenant::Tenant;

/// The session cookie's name.
pub(super) const COOKIE_NAME: &str = "gymfleet_dashboard";
/// How long a session lasts after its login.
pub(super) const SESSION_LIFETIME: Duration = Duration::from_secs(12 * 3600);
/// Most sessions held at once; past it, the one that would end first is dropped.
const MAX_SESSIONS: usize = 1024;

/// Random session ids, each with its tenant and when it ends (on the server's clock).
pub(super) struct Sessions {
    clock: Clock,
    sessions: Mutex<HashMap<String, (Tenant, Duration)>>,
}

impl Sessions {
    pub(super) fn new(clock: Clock) -> Self {
        Sessions {
            clock,
            sessions: Mutex::new(HashMap::new()),
        }
    }

    fn map(&self) -> std::sync::MutexGuard<'_, HashMap<String, (Tenant, Duration)>> {
        // Only inserts and removals happen under the lock: a poisoned map is still whole.
        self.sessions.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// A new session of `tenant`: its id (64 hex digits from the operating system's
    /// random source), or `None` if that source failed.
    pub(super) fn start(&self, tenant: Tenant) -> Option<String> {
        let mut bytes = [0u8; 32];
        getrandom::fill(&mut bytes).ok()?;
        let id: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        let now = self.clock.elapsed();
        let mut sessions = self.map();
        sessions.retain(|_, (_, ends)| *ends > now);
        if sessions.len() >= MAX_SESSIONS {
            let first_to_end = sessions
                .iter()
                .min_by_key(|(_, (_, ends))| *ends)
                .map(|(id, _)| id.clone());
            if let Some(old) = first_to_end {
                sessions.remove(&old);
            }
        }
        sessions.insert(id.clone(), (tenant, now + SESSION_LIFETIME));
        Some(id)
    }

    /// The tenant of the session whose cookie `headers` carry, if it has not ended.
    pub(super) fn tenant(&self, headers: &HeaderMap) -> Option<Tenant> {
        let id = session_id(headers)?;
        let now = self.clock.elapsed();
        let mut sessions = self.map();
        match sessions.get(id) {
            Some((tenant, ends)) if *ends > now => Some(tenant.clone()),
            Some(_) => {
                sessions.remove(id);
                None
            }
            None => None,
        }
    }

    /// Ends the session whose cookie `headers` carry, if any.
    pub(super) fn end(&self, headers: &HeaderMap) {
        if let Some(id) = session_id(headers) {
            self.map().remove(id);
        }
    }
}

/// The session id in the request's `Cookie` headers.
fn session_id(headers: &HeaderMap) -> Option<&str> {
    headers
        .get_all(COOKIE)
        .iter()
        .filter_map(|value| value.to_str().ok())
        .flat_map(|value| value.split(';'))
        .filter_map(|pair| pair.trim().split_once('='))
        .find(|(name, _)| *name == COOKIE_NAME)
        .map(|(_, id)| id)
        .filter(|id| !id.is_empty())
}

/// The `Set-Cookie` value that stores session `id` in the browser.
pub(super) fn set_cookie(id: &str) -> String {
    format!(
        "{COOKIE_NAME}={id}; HttpOnly; SameSite=Strict; Path=/; Max-Age={}",
        SESSION_LIFETIME.as_secs()
    )
}

/// The `Set-Cookie` value that removes the session cookie.
pub(super) fn clear_cookie() -> String {
    format!("{COOKIE_NAME}=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0")
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::HeaderValue;

    fn with_cookie(cookie: &str) -> HeaderMap {
        let mut headers = HeaderMap::new();
        headers.insert(COOKIE, HeaderValue::from_str(cookie).unwrap());
        headers
    }

    #[test]
    fn a_session_maps_its_cookie_to_its_tenant_until_it_ends() {
        let clock = Clock::manual();
        let sessions = Sessions::new(clock.clone());
        let id = sessions.start(Tenant::named("team-a")).expect("an id");
        assert_eq!(id.len(), 64);
        assert!(id.bytes().all(|b| b.is_ascii_hexdigit()));
        let cookie = format!("theme=dark; {COOKIE_NAME}={id}; other=1");
        assert_eq!(
            sessions.tenant(&with_cookie(&cookie)),
            Some(Tenant::named("team-a"))
        );
        assert_eq!(
            sessions.tenant(&with_cookie("gymfleet_dashboard=0123")),
            None
        );
        assert_eq!(sessions.tenant(&with_cookie("gymfleet_dashboard=")), None);
        assert_eq!(sessions.tenant(&HeaderMap::new()), None);

        clock.advance(SESSION_LIFETIME);
        assert_eq!(sessions.tenant(&with_cookie(&cookie)), None, "it ended");

        let id = sessions.start(Tenant::named("team-a")).unwrap();
        let cookie = with_cookie(&format!("{COOKIE_NAME}={id}"));
        sessions.end(&cookie);
        assert_eq!(sessions.tenant(&cookie), None, "logged out");
    }

    #[test]
    fn sessions_are_bounded_and_the_first_to_end_goes_first() {
        let clock = Clock::manual();
        let sessions = Sessions::new(clock.clone());
        let first = sessions.start(Tenant::named("a")).unwrap();
        clock.advance(Duration::from_secs(1));
        for _ in 1..MAX_SESSIONS {
            sessions.start(Tenant::named("b")).unwrap();
        }
        let last = sessions.start(Tenant::named("c")).unwrap();
        assert_eq!(sessions.map().len(), MAX_SESSIONS);
        let cookie = |id: &str| with_cookie(&format!("{COOKIE_NAME}={id}"));
        assert_eq!(sessions.tenant(&cookie(&first)), None);
        assert_eq!(sessions.tenant(&cookie(&last)), Some(Tenant::named("c")));
    }

    #[test]
    fn cookies_are_http_only_same_site_strict() {
        assert_eq!(
            set_cookie("ab12"),
            "gymfleet_dashboard=ab12; HttpOnly; SameSite=Strict; Path=/; Max-Age=43200"
        );
        assert_eq!(
            clear_cookie(),
            "gymfleet_dashboard=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0"
        );
    }
}
