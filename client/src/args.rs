//! [`ConnectArgs`] (feature `cli`): the connection flags every gymfleet command-line tool
//! shares (`--token`, `--tls-ca`, `--tls-client-cert`, `--tls-client-key`,
//! `--tls-domain`), as a clap `Args` group that makes a [`ClientBuilder`].

use std::path::PathBuf;

use crate::client::{Client, ClientBuilder};
use crate::environment::{
    ENV_TLS_CA, ENV_TLS_CLIENT_CERT, ENV_TLS_CLIENT_KEY, ENV_TLS_DOMAIN, ENV_TOKEN,
};

/// How to reach servers that require a token or TLS. Flatten it into a tool's flags
/// (`#[command(flatten)]`); each flag also reads its `GYMFLEET_*` variable, the same ones
/// [`ClientBuilder::from_env`] reads.
#[derive(Clone, Default, PartialEq, Eq, clap::Args)]
pub struct ConnectArgs {
    /// Bearer token sent to every server (servers run with --auth-tokens).
    #[arg(
        long,
        env = ENV_TOKEN,
        value_name = "TOKEN",
        hide_env_values = true
    )]
    pub token: Option<String>,
    /// Connect with TLS, trusting this CA certificate (PEM).
    #[arg(long, env = ENV_TLS_CA, value_name = "FILE")]
    pub tls_ca: Option<PathBuf>,
    /// Mutual TLS: this client's certificate (PEM); needs --tls-client-key.
    #[arg(
        long,
        env = ENV_TLS_CLIENT_CERT,
        value_name = "FILE",
        requires = "tls_client_key"
    )]
    pub tls_client_cert: Option<PathBuf>,
    /// Mutual TLS: the key (PEM) of --tls-client-cert.
    #[arg(
        long,
        env = ENV_TLS_CLIENT_KEY,
        value_name = "FILE",
        requires = "tls_client_cert"
    )]
    pub tls_client_key: Option<PathBuf>,
    /// The name the servers' certificates carry, when it is not the host connected to.
    #[arg(long, env = ENV_TLS_DOMAIN, value_name = "NAME")]
    pub tls_domain: Option<String>,
}

impl std::fmt::Debug for ConnectArgs {
    // The token stays out of logs and reports.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ConnectArgs")
            .field("token", &self.token.as_ref().map(|_| "(set)"))
            .field("tls_ca", &self.tls_ca)
            .field("tls_client_cert", &self.tls_client_cert)
            .field("tls_client_key", &self.tls_client_key)
            .field("tls_domain", &self.tls_domain)
            .finish()
    }
}

impl ConnectArgs {
    /// A builder for `addr` with these settings (and the defaults otherwise).
    pub fn builder(&self, addr: impl Into<String>) -> ClientBuilder {
        let mut builder = Client::builder(addr);
        if let Some(token) = &self.token {
            builder = builder.token(token.clone());
        }
        if let Some(ca) = &self.tls_ca {
            builder = builder.tls_ca_file(ca.clone());
        }
        if let (Some(cert), Some(key)) = (&self.tls_client_cert, &self.tls_client_key) {
            builder = builder.tls_identity_files(cert.clone(), key.clone());
        }
        if let Some(domain) = &self.tls_domain {
            builder = builder.tls_domain(domain.clone());
        }
        builder
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Debug, Parser)]
    struct Tool {
        #[command(flatten)]
        connect: ConnectArgs,
    }

    #[test]
    fn flags_parse_and_pair_up() {
        let tool = Tool::try_parse_from([
            "tool",
            "--token",
            "t0123456789abcdef",
            "--tls-ca",
            "ca.pem",
            "--tls-domain",
            "sim.example.org",
        ])
        .unwrap();
        assert_eq!(tool.connect.token.as_deref(), Some("t0123456789abcdef"));
        assert!(!format!("{:?}", tool.connect).contains("t0123456789abcdef"));
        let debug = format!("{:?}", tool.connect.builder("h:1"));
        assert!(debug.contains("token: Some(\"(set)\")"), "{debug}");
        assert!(!debug.contains("t0123456789abcdef"), "{debug}");
        let err = Tool::try_parse_from(["tool", "--tls-client-cert", "c.pem"]).unwrap_err();
        assert!(err.to_string().contains("--tls-client-key"), "{err}");
    }
}
