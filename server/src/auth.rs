//! Bearer-token authentication (`--auth-tokens FILE`, docs/design.md §6.6).
//!
//! A [`TokenTable`] (`tenant.rs`) maps tokens to [`Tenant`]s. The [`Authenticator`]
//! interceptor sits in front of the simulator and reflection services (never health, which
//! stays open for probes): it reads `authorization: Bearer <token>`, refuses a missing or
//! unknown token with UNAUTHENTICATED (counted in the metrics), and puts the caller's
//! [`Tenant`] into the request's extensions. With auth off every caller is the anonymous
//! tenant. The service reads the tenant with [`tenant_of`], which fails closed: a request
//! that did not pass the interceptor has no tenant and is refused.

use std::sync::Arc;

use gymfleet_proto::v1::ErrorReason;
use tonic::{Request, Status};

use crate::metrics::Metrics;
use crate::tenant::{Tenant, TokenTable};

/// The interceptor that authenticates every call of the services it guards.
#[derive(Clone)]
pub(crate) struct Authenticator {
    tokens: Option<Arc<TokenTable>>,
    /// Where refusals are counted.
    metrics: Option<Arc<Metrics>>,
}

impl Authenticator {
    /// Checks tokens against `tokens`; with `None` everyone is the anonymous tenant.
    /// Refusals count in `metrics`.
    pub(crate) fn new(tokens: Option<Arc<TokenTable>>, metrics: Arc<Metrics>) -> Self {
        Authenticator {
            tokens,
            metrics: Some(metrics),
        }
    }

    fn authenticate(&self, request: &Request<()>) -> Result<Tenant, Status> {
        let Some(tokens) = &self.tokens else {
            return Ok(Tenant::anonymous());
        };
        let Some(value) = request.metadata().get("authorization") else {
            return Err(unauthenticated(
                "this server requires a token: send `authorization: Bearer <token>` metadata (gymfleet's clients and tools read it from the GYMFLEET_TOKEN variable or --token)",
            ));
        };
        let token = value
            .to_str()
            .ok()
            .and_then(|v| v.strip_prefix("Bearer "))
            .map(str::trim)
            .ok_or_else(|| unauthenticated("authorization: expected `Bearer <token>`"))?;
        tokens
            .tenant(token)
            .cloned()
            .ok_or_else(|| unauthenticated("authorization: unknown token"))
    }
}

impl tonic::service::Interceptor for Authenticator {
    fn call(&mut self, mut request: Request<()>) -> Result<Request<()>, Status> {
        let tenant = self.authenticate(&request).inspect_err(|_| {
            if let Some(metrics) = &self.metrics {
                metrics.reject("unauthenticated");
            }
        })?;
        request.extensions_mut().insert(tenant);
        Ok(request)
    }
}

/// UNAUTHENTICATED with `message`, and its reason.
fn unauthenticated(message: &'static str) -> Status {
    let mut status = Status::unauthenticated(message);
    crate::error::with_reason(&mut status, ErrorReason::Unauthenticated, None);
    status
}

/// The tenant the [`Authenticator`] found for `request`. A request that did not pass
/// through it is refused rather than served as anyone.
pub(crate) fn tenant_of<T>(request: &Request<T>) -> Result<Tenant, Status> {
    request
        .extensions()
        .get::<Tenant>()
        .cloned()
        .ok_or_else(|| unauthenticated("the request was not authenticated"))
}

#[cfg(test)]
mod tests {
    use tonic::service::Interceptor;
    use tonic::Code;

    use super::*;

    const TOKEN_A: &str = "alpha-0123456789abcdef";
    const TOKEN_B: &str = "beta-0123456789abcdef";

    fn table() -> TokenTable {
        TokenTable::parse(&format!("team-a {TOKEN_A}\nteam_b {TOKEN_B}\n")).unwrap()
    }

    fn call(auth: &mut Authenticator, header: Option<&str>) -> Result<Tenant, Status> {
        let mut request = Request::new(());
        if let Some(h) = header {
            request
                .metadata_mut()
                .insert("authorization", h.parse().unwrap());
        }
        let request = auth.call(request)?;
        tenant_of(&request)
    }

    #[test]
    fn the_interceptor_admits_known_tokens_only() {
        let mut auth = Authenticator {
            tokens: Some(Arc::new(table())),
            metrics: None,
        };
        let tenant = call(&mut auth, Some(&format!("Bearer {TOKEN_B}"))).unwrap();
        assert_eq!(tenant.name(), "team_b");
        for (header, message) in [
            (
                None,
                "this server requires a token: send `authorization: Bearer <token>` metadata (gymfleet's clients and tools read it from the GYMFLEET_TOKEN variable or --token)",
            ),
            (Some(TOKEN_A), "authorization: expected `Bearer <token>`"),
            (Some("Bearer wrong"), "authorization: unknown token"),
        ] {
            let status = call(&mut auth, header).unwrap_err();
            assert_eq!(status.code(), Code::Unauthenticated);
            assert_eq!(status.message(), message);
        }
        let mut open = Authenticator {
            tokens: None,
            metrics: None,
        };
        assert_eq!(call(&mut open, None).unwrap(), Tenant::anonymous());
        assert_eq!(
            tenant_of(&Request::new(())).unwrap_err().code(),
            Code::Unauthenticated
        );
    }
}
