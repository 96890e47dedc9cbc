//! The command line ([`Cli`], clap derive; every flag also reads a `GYMFLEET_*`
//! variable) and logging setup.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use clap::{Parser, ValueEnum};
use tracing_subscriber::EnvFilter;

use crate::config::{ServerConfig, TlsConfig};
use crate::limit::Limit;
use crate::listen::ListenAddr;
use crate::tenant::TokenTable;

/// How log lines are written (to stderr).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LogFormat {
    /// Human-readable lines.
    Text,
    /// One JSON object per line.
    Json,
}

/// gymfleet-server: CAD robot assemblies as physics-simulated Gym environments, over gRPC.
///
/// Logging verbosity follows `RUST_LOG` (default `info`).
#[derive(Debug, Clone, Parser)]
#[command(name = "gymfleet-server", version, about)]
pub struct Cli {
    /// Address to listen on: host:port, or unix:/path/to/socket for clients on this host.
    #[arg(long, env = "GYMFLEET_LISTEN", default_value = "127.0.0.1:50051")]
    pub listen: ListenAddr,
    /// Simulation worker threads; 0 = one per core this process may use (its CPU
    /// affinity and cgroup quota).
    #[arg(long, env = "GYMFLEET_THREADS", default_value_t = 0)]
    pub threads: usize,
    /// Run the simulation threads at this scheduling niceness (1..=19) so that the
    /// network threads answer one tenant's small calls at once beside another's big
    /// batches; 10 is the measured choice. They then starve beside any other process at
    /// the default priority (a trainer, a compile): use it only on a machine (or pod)
    /// given to the server. 0 = the process's own priority.
    #[arg(
        long,
        env = "GYMFLEET_POOL_NICENESS",
        default_value_t = 0,
        value_parser = clap::value_parser!(u8).range(0..=19)
    )]
    pub pool_niceness: u8,
    /// Most environments held at once (single envs plus batch members); 0 = no limit.
    #[arg(
        long = Limit::Envs.flag(),
        env = Limit::Envs.var(),
        default_value_t = Limit::Envs.default_value()
    )]
    pub max_envs: usize,
    /// Most environments in one batch; 0 = no limit.
    #[arg(
        long = Limit::BatchSize.flag(),
        env = Limit::BatchSize.var(),
        default_value_t = Limit::BatchSize.default_value()
    )]
    pub max_batch_size: usize,
    /// Largest accepted assembly document, bytes; 0 = no limit.
    #[arg(
        long = Limit::DocumentBytes.flag(),
        env = Limit::DocumentBytes.var(),
        default_value_t = Limit::DocumentBytes.default_value()
    )]
    pub max_document_bytes: usize,
    /// Largest gRPC message decoded or encoded, bytes; 0 = tonic's 4 MiB default.
    #[arg(
        long = Limit::MessageBytes.flag(),
        env = Limit::MessageBytes.var(),
        default_value_t = Limit::MessageBytes.default_value()
    )]
    pub max_message_bytes: usize,
    /// Most instances (bodies) per document; 0 = no limit.
    #[arg(
        long = Limit::Instances.flag(),
        env = Limit::Instances.var(),
        default_value_t = Limit::Instances.default_value()
    )]
    pub max_instances: usize,
    /// Most joints per document, fixed ones included; 0 = no limit.
    #[arg(
        long = Limit::Joints.flag(),
        env = Limit::Joints.var(),
        default_value_t = Limit::Joints.default_value()
    )]
    pub max_joints: usize,
    /// Most degrees of freedom per document (a step's cost grows with them); 0 = no limit.
    #[arg(
        long = Limit::Dofs.flag(),
        env = Limit::Dofs.var(),
        default_value_t = Limit::Dofs.default_value()
    )]
    pub max_dofs: usize,
    /// Most observed end effectors per env; 0 = no limit.
    #[arg(
        long = Limit::EndEffectors.flag(),
        env = Limit::EndEffectors.var(),
        default_value_t = Limit::EndEffectors.default_value()
    )]
    pub max_end_effectors: usize,
    /// Serve TLS with this certificate chain (PEM); needs --tls-key.
    #[arg(
        long,
        env = "GYMFLEET_TLS_CERT",
        value_name = "FILE",
        requires = "tls_key"
    )]
    pub tls_cert: Option<PathBuf>,
    /// The private key (PEM) of --tls-cert.
    #[arg(
        long,
        env = "GYMFLEET_TLS_KEY",
        value_name = "FILE",
        requires = "tls_cert"
    )]
    pub tls_key: Option<PathBuf>,
    /// Mutual TLS: accept only clients with a certificate signed by this CA (PEM).
    #[arg(
        long,
        env = "GYMFLEET_TLS_CLIENT_CA",
        value_name = "FILE",
        requires = "tls_cert"
    )]
    pub tls_client_ca: Option<PathBuf>,
    /// Serve Prometheus metrics at http://ADDR/metrics (plain HTTP, no token: keep it
    /// on a private port), e.g. 0.0.0.0:9090.
    #[arg(long, env = "GYMFLEET_METRICS_LISTEN", value_name = "ADDR")]
    pub metrics_listen: Option<std::net::SocketAddr>,
    /// Also serve gRPC health (grpc.health.v1.Health, nothing else) at ADDR in plaintext,
    /// e.g. 0.0.0.0:8081: for probes that cannot do TLS (the kubelet's gRPC probe) when
    /// the main listener serves TLS. It reports what the main listener's health reports.
    #[arg(long, env = "GYMFLEET_HEALTH_LISTEN", value_name = "ADDR")]
    pub health_listen: Option<std::net::SocketAddr>,
    /// Serve a read-only dashboard at http://ADDR/ (envs, batches, rates, the pool, a
    /// live 3D view), e.g. 127.0.0.1:8080. Plain HTTP; an address other than loopback
    /// needs --auth-tokens (the page then asks for a token and shows that tenant's).
    #[arg(long, env = "GYMFLEET_DASHBOARD_LISTEN", value_name = "ADDR")]
    pub dashboard_listen: Option<std::net::SocketAddr>,
    /// Require bearer tokens: a file of `TENANT TOKEN` lines (`#` comments). Each tenant
    /// sees only its own envs and batches. Health checks stay open.
    #[arg(long, env = "GYMFLEET_AUTH_TOKENS", value_name = "FILE")]
    pub auth_tokens: Option<PathBuf>,
    /// A model library: every .json, .xml (MJCF) and .mjcf file of this directory, loaded
    /// and checked at start, is a model requests may name (`model: "reacher"` for
    /// reacher.xml) instead of sending a document; ListModels lists them.
    #[arg(long, env = "GYMFLEET_MODELS", value_name = "DIR")]
    pub models: Option<PathBuf>,
    /// Most environments one tenant (or, with auth off, all callers together) holds at
    /// once; 0 = no limit beyond --max-envs.
    #[arg(
        long = Limit::TenantEnvs.flag(),
        env = Limit::TenantEnvs.var(),
        default_value_t = Limit::TenantEnvs.default_value()
    )]
    pub tenant_max_envs: usize,
    /// Most work one step call may ask for, in DOF-substeps (envs × substeps × DOFs of a
    /// batch or env); 0 = no limit.
    #[arg(
        long = Limit::StepWork.flag(),
        env = Limit::StepWork.var(),
        default_value_t = Limit::StepWork.default_value()
    )]
    pub max_step_work: usize,
    /// Most contact work one env step may ask of the solver, in contact point-substeps
    /// (the contact points its collision detection finds × substeps); a step over it fails
    /// with RESOURCE_EXHAUSTED and leaves the env where it was, and a document whose bodies
    /// start over it is refused; 0 = no limit.
    #[arg(
        long = Limit::ContactWork.flag(),
        env = Limit::ContactWork.var(),
        default_value_t = Limit::ContactWork.default_value()
    )]
    pub max_contact_work: usize,
    /// Close envs and batches untouched for this many seconds; 0 = never.
    #[arg(long, env = "GYMFLEET_IDLE_TTL_SECS", default_value_t = 600)]
    pub idle_ttl_secs: u64,
    /// Log format.
    #[arg(long, env = "GYMFLEET_LOG_FORMAT", value_enum, default_value_t = LogFormat::Text)]
    pub log_format: LogFormat,
}

impl Cli {
    /// The server configuration these flags describe; reads the files they name (an
    /// error says which flag and file, and what is wrong).
    pub fn server_config(&self) -> Result<ServerConfig, String> {
        // A PEM file, read whole: one that is not PEM (e.g. a deploy's placeholder Secret)
        // is refused here, naming its flag and file, before anything is bound.
        let read = |flag: &str, path: &PathBuf| {
            let pem = std::fs::read(path).map_err(|e| format!("{flag} {}: {e}", path.display()))?;
            if !pem.windows(11).any(|w| w == b"-----BEGIN ") {
                return Err(format!(
                    "{flag} {}: not PEM (no `-----BEGIN` line)",
                    path.display()
                ));
            }
            Ok(pem)
        };
        let tls = match (&self.tls_cert, &self.tls_key) {
            (Some(cert), Some(key)) => Some(TlsConfig {
                cert_pem: read("--tls-cert", cert)?,
                key_pem: read("--tls-key", key)?,
                client_ca_pem: match &self.tls_client_ca {
                    Some(ca) => Some(read("--tls-client-ca", ca)?),
                    None => None,
                },
            }),
            _ => None,
        };
        let auth_tokens = match &self.auth_tokens {
            Some(path) => Some(Arc::new(TokenTable::load(path)?)),
            None => None,
        };
        if let Some(addr) = self.dashboard_listen {
            crate::dashboard::check_listen(addr, auth_tokens.is_some())
                .map_err(|e| e.to_string())?;
        }
        let models = match &self.models {
            Some(dir) => Some(Arc::new(
                crate::models::ModelLibrary::load(dir).map_err(|e| e.to_string())?,
            )),
            None => None,
        };
        Ok(ServerConfig {
            threads: self.threads,
            pool_niceness: self.pool_niceness,
            max_envs: self.max_envs,
            max_batch_size: self.max_batch_size,
            max_document_bytes: self.max_document_bytes,
            max_message_bytes: self.max_message_bytes,
            max_instances: self.max_instances,
            max_joints: self.max_joints,
            max_dofs: self.max_dofs,
            max_end_effectors: self.max_end_effectors,
            max_step_work: self.max_step_work,
            max_contact_work: self.max_contact_work,
            tls,
            metrics_listen: self.metrics_listen,
            health_listen: self.health_listen,
            dashboard_listen: self.dashboard_listen,
            auth_tokens,
            models,
            tenant_max_envs: self.tenant_max_envs,
            idle_ttl: Duration::from_secs(self.idle_ttl_secs),
            ..ServerConfig::default()
        })
    }
}

/// Installs the global `tracing` subscriber: stderr, `RUST_LOG` filter (default `info`).
pub fn init_tracing(format: LogFormat) {
    let filter = EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info"));
    // Colours only for a person at a terminal: a log file or a collector gets plain text.
    let builder = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_ansi(std::io::stderr().is_terminal())
        .with_writer(std::io::stderr);
    match format {
        LogFormat::Text => builder.init(),
        LogFormat::Json => builder.json().init(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Clears the `GYMFLEET_*` variables, so that the caller's environment does not change
    /// the defaults these tests check (no test of this binary sets one).
    fn scrub_gymfleet_env() {
        std::env::vars_os()
            .map(|(key, _)| key)
            .filter(|key| key.to_string_lossy().starts_with("GYMFLEET_"))
            .for_each(|key| std::env::remove_var(key));
    }

    #[test]
    fn flags_have_documented_defaults() {
        scrub_gymfleet_env();
        let cli = Cli::try_parse_from(["gymfleet-server"]).expect("defaults parse");
        assert_eq!(cli.listen, "127.0.0.1:50051".parse::<ListenAddr>().unwrap());
        let config = cli.server_config().unwrap();
        assert_eq!(config.threads, 0);
        assert_eq!(config.pool_niceness, 0, "the process's own priority");
        for limit in Limit::ALL {
            assert_eq!(config.limit(limit), limit.default_value(), "{limit:?}");
        }
        assert_eq!(config.idle_ttl, Duration::from_secs(600));
        assert_eq!(cli.log_format, LogFormat::Text);
    }

    #[test]
    fn every_limit_is_set_by_its_flag() {
        scrub_gymfleet_env();
        for limit in Limit::ALL {
            let flag = format!("--{}", limit.flag());
            let cli = Cli::try_parse_from(["gymfleet-server", &flag, "3"]).expect("parses");
            let config = cli.server_config().unwrap();
            assert_eq!(config.limit(limit), 3, "{flag}");
        }
    }

    #[test]
    fn flags_parse() {
        scrub_gymfleet_env();
        let cli = Cli::try_parse_from([
            "gymfleet-server",
            "--listen",
            "0.0.0.0:7000",
            "--threads",
            "2",
            "--max-batch-size",
            "10",
            "--idle-ttl-secs",
            "0",
            "--log-format",
            "json",
            "--pool-niceness",
            "10",
        ])
        .expect("flags parse");
        let config = cli.server_config().unwrap();
        assert_eq!(config.threads, 2);
        assert_eq!(config.pool_niceness, 10);
        assert_eq!(config.max_batch_size, 10);
        assert_eq!(config.idle_ttl(), None);
        assert_eq!(cli.log_format, LogFormat::Json);
    }

    #[test]
    fn pool_niceness_is_bounded() {
        scrub_gymfleet_env();
        let err = Cli::try_parse_from(["gymfleet-server", "--pool-niceness", "20"])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("invalid value '20' for '--pool-niceness <POOL_NICENESS>'")
                && err.contains("20 is not in 0..=19"),
            "{err}"
        );
    }

    /// The secure overlay's placeholder Secrets (deploy/k8s/overlays/secure/secrets.yaml)
    /// stop a server that is given them, naming the file, before anything is bound.
    #[test]
    fn the_deploy_placeholders_are_refused_by_file() {
        scrub_gymfleet_env();
        const SECRETS: &str = include_str!("../../deploy/k8s/overlays/secure/secrets.yaml");
        let value = |key: &str| {
            let line = SECRETS
                .lines()
                .find(|l| l.trim_start().starts_with(key))
                .unwrap_or_else(|| panic!("{key} in secrets.yaml"));
            line.split_once(": ")
                .unwrap()
                .1
                .trim_matches('"')
                .to_string()
        };
        let dir =
            std::env::temp_dir().join(format!("gymfleet-placeholders-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let cert = dir.join("tls.crt");
        let key = dir.join("tls.key");
        let tokens = dir.join("tokens");
        std::fs::write(&cert, value("tls.crt:")).unwrap();
        std::fs::write(&key, value("tls.key:")).unwrap();
        // The tokens value is a block: its one line is the comment after `tokens: |`.
        let comment = SECRETS
            .lines()
            .skip_while(|l| !l.ends_with("tokens: |"))
            .nth(1)
            .unwrap();
        std::fs::write(&tokens, format!("{}\n", comment.trim())).unwrap();
        let parse = |args: &[&str]| {
            Cli::try_parse_from(["gymfleet-server"].iter().chain(args))
                .expect("flags parse")
                .server_config()
                .unwrap_err()
        };
        let (c, k, t) = (
            cert.to_str().unwrap(),
            key.to_str().unwrap(),
            tokens.to_str().unwrap(),
        );
        assert_eq!(
            parse(&["--tls-cert", c, "--tls-key", k]),
            format!("--tls-cert {c}: not PEM (no `-----BEGIN` line)")
        );
        assert_eq!(
            parse(&["--auth-tokens", t]),
            format!("--auth-tokens {t}: no tokens: the file has no `TENANT TOKEN` line")
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn health_listen_is_off_by_default_and_set_by_its_flag() {
        scrub_gymfleet_env();
        let cli = Cli::try_parse_from(["gymfleet-server"]).unwrap();
        assert_eq!(cli.server_config().unwrap().health_listen, None);
        let cli =
            Cli::try_parse_from(["gymfleet-server", "--health-listen", "0.0.0.0:8081"]).unwrap();
        assert_eq!(
            cli.server_config().unwrap().health_listen,
            Some(([0, 0, 0, 0], 8081).into())
        );
    }

    #[test]
    fn a_dashboard_off_loopback_needs_auth() {
        scrub_gymfleet_env();
        let cli = Cli::try_parse_from(["gymfleet-server", "--dashboard-listen", "127.0.0.1:0"])
            .expect("flags parse");
        let config = cli.server_config().unwrap();
        assert_eq!(config.dashboard_listen, Some(([127, 0, 0, 1], 0).into()));
        assert_eq!(
            ServerConfig::default().dashboard_listen,
            None,
            "off by default"
        );

        let cli = Cli::try_parse_from(["gymfleet-server", "--dashboard-listen", "0.0.0.0:8080"])
            .expect("flags parse");
        assert_eq!(
            cli.server_config().unwrap_err(),
            "cannot listen on 0.0.0.0:8080: a dashboard on an address other than loopback \
             needs --auth-tokens (GYMFLEET_AUTH_TOKENS): without tokens, anyone who reaches \
             the port sees every env; serve it on 127.0.0.1 (through an SSH tunnel, say) or \
             turn auth on"
        );
    }

    #[test]
    fn command_is_well_formed() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
