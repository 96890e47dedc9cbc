//! The `GYMFLEET_*` variables that say how to connect, read in one place:
//! [`ClientBuilder::from_env`] for programs (the Python package), and the names the
//! command-line tools' flags read through clap ([`crate::ConnectArgs`]).

use crate::client::{Client, ClientBuilder};
use crate::error::{ClientError, Result};

/// The bearer token sent to every server.
pub const ENV_TOKEN: &str = "GYMFLEET_TOKEN";
/// Connect with TLS, trusting this CA certificate file (PEM).
pub const ENV_TLS_CA: &str = "GYMFLEET_TLS_CA";
/// Mutual TLS: this client's certificate file (PEM); goes with [`ENV_TLS_CLIENT_KEY`].
pub const ENV_TLS_CLIENT_CERT: &str = "GYMFLEET_TLS_CLIENT_CERT";
/// Mutual TLS: the key file (PEM) of [`ENV_TLS_CLIENT_CERT`].
pub const ENV_TLS_CLIENT_KEY: &str = "GYMFLEET_TLS_CLIENT_KEY";
/// The name the servers' certificates carry, when it is not the host connected to.
pub const ENV_TLS_DOMAIN: &str = "GYMFLEET_TLS_DOMAIN";

impl ClientBuilder {
    /// A builder for `addr` with the token and TLS settings of the environment
    /// ([`ENV_TOKEN`], [`ENV_TLS_CA`], [`ENV_TLS_CLIENT_CERT`] with
    /// [`ENV_TLS_CLIENT_KEY`], [`ENV_TLS_DOMAIN`]), the variables the command-line tools
    /// read too; an empty variable counts as unset. A client certificate without its key
    /// (or the other way round) is an `InvalidArgument`.
    pub fn from_env(addr: impl Into<String>) -> Result<ClientBuilder> {
        Self::from_vars(addr, |name| std::env::var(name).ok())
    }

    /// [`ClientBuilder::from_env`] with the variables looked up by `var`.
    fn from_vars(
        addr: impl Into<String>,
        var: impl Fn(&str) -> Option<String>,
    ) -> Result<ClientBuilder> {
        let var = |name: &str| var(name).filter(|v| !v.is_empty());
        let mut builder = Client::builder(addr);
        if let Some(token) = var(ENV_TOKEN) {
            builder = builder.token(token);
        }
        if let Some(ca) = var(ENV_TLS_CA) {
            builder = builder.tls_ca_file(ca);
        }
        match (var(ENV_TLS_CLIENT_CERT), var(ENV_TLS_CLIENT_KEY)) {
            (Some(cert), Some(key)) => builder = builder.tls_identity_files(cert, key),
            (None, None) => {}
            _ => {
                return Err(ClientError::InvalidArgument {
                    reason: crate::ErrorReason::Unspecified,
                    message: format!(
                        "{ENV_TLS_CLIENT_CERT} and {ENV_TLS_CLIENT_KEY} go together: set \
                         both or neither"
                    ),
                })
            }
        }
        if let Some(domain) = var(ENV_TLS_DOMAIN) {
            builder = builder.tls_domain(domain);
        }
        Ok(builder)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from(vars: &[(&str, &str)]) -> Result<ClientBuilder> {
        let vars: Vec<(String, String)> = vars
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        ClientBuilder::from_vars("h:1", |name| {
            vars.iter().find(|(k, _)| k == name).map(|(_, v)| v.clone())
        })
    }

    #[test]
    fn the_variables_make_the_builder_and_empty_ones_count_as_unset() {
        let debug = format!(
            "{:?}",
            from(&[
                (ENV_TOKEN, "t0123456789abcdef"),
                (ENV_TLS_CA, "ca.pem"),
                (ENV_TLS_DOMAIN, "sim.example.org"),
                (ENV_TLS_CLIENT_CERT, ""),
            ])
            .unwrap()
        );
        assert!(debug.contains("token: Some(\"(set)\")"), "{debug}");
        assert!(!debug.contains("t0123456789abcdef"), "{debug}");
        assert!(debug.contains("ca.pem"), "{debug}");
        assert!(debug.contains("sim.example.org"), "{debug}");
        assert_eq!(
            format!("{:?}", from(&[(ENV_TOKEN, "")]).unwrap()),
            format!("{:?}", Client::builder("h:1"))
        );
    }

    #[test]
    fn a_client_certificate_without_its_key_is_refused() {
        for half in [ENV_TLS_CLIENT_CERT, ENV_TLS_CLIENT_KEY] {
            let err = from(&[(half, "x.pem")]).unwrap_err();
            assert_eq!(
                err.to_string(),
                "invalid argument: GYMFLEET_TLS_CLIENT_CERT and GYMFLEET_TLS_CLIENT_KEY go \
                 together: set both or neither"
            );
        }
        let both = from(&[
            (ENV_TLS_CLIENT_CERT, "c.pem"),
            (ENV_TLS_CLIENT_KEY, "k.pem"),
        ]);
        let debug = format!("{:?}", both.unwrap());
        assert!(debug.contains("tls_identity: Some(\"(set)\")"), "{debug}");
    }
}
