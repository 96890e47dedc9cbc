//! [`ServerConfig`]: the limits and knobs of one server, independent of how they were
//! given (the CLI in `cli.rs`, or a test building one by hand).

use std::sync::Arc;
use std::time::Duration;

use crate::clock::Clock;
use crate::limit::{
    Limit, DEFAULT_MAX_BATCH_SIZE, DEFAULT_MAX_CONTACT_WORK, DEFAULT_MAX_DOCUMENT_BYTES,
    DEFAULT_MAX_DOFS, DEFAULT_MAX_END_EFFECTORS, DEFAULT_MAX_ENVS, DEFAULT_MAX_INSTANCES,
    DEFAULT_MAX_JOINTS, DEFAULT_MAX_MESSAGE_BYTES, DEFAULT_MAX_STEP_WORK,
};
use crate::tenant::TokenTable;

/// Default idle time after which an untouched env or batch is closed: 10 minutes.
pub const DEFAULT_IDLE_TTL: Duration = Duration::from_secs(600);

/// The server's TLS certificate chain and key (PEM), and for mutual TLS the CA whose
/// certificates clients must present.
#[derive(Clone, PartialEq, Eq)]
pub struct TlsConfig {
    /// The certificate chain, PEM.
    pub cert_pem: Vec<u8>,
    /// The private key, PEM.
    pub key_pem: Vec<u8>,
    /// With mutual TLS: the CA certificate(s) that sign client certificates, PEM.
    pub client_ca_pem: Option<Vec<u8>>,
}

impl std::fmt::Debug for TlsConfig {
    // The key stays out of logs.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TlsConfig")
            .field("cert_pem", &format_args!("{} bytes", self.cert_pem.len()))
            .field("key_pem", &"(hidden)")
            .field("mutual", &self.client_ca_pem.is_some())
            .finish()
    }
}

/// How a server runs. Every limit of 0 means "no limit", as in `ServerLimits` on the wire.
#[derive(Debug, Clone, PartialEq)]
pub struct ServerConfig {
    /// Worker threads of the simulation pool; 0 = one per core this process may use
    /// (its CPU affinity and cgroup quota: `gymfleet_batch::usable_cores`).
    pub threads: usize,
    /// Scheduling niceness of the pool's threads (Linux): 0 (the default) leaves them at
    /// the process's priority; 1..=19 runs them below the server's network threads, so
    /// that one tenant's small calls are answered at once beside another's big batches
    /// (`gymfleet_batch::FAIR_POOL_NICENESS`), at the price of starving beside any other
    /// process on the machine. For a machine given to the server alone.
    pub pool_niceness: u8,
    /// Most environments held at once (single envs plus batch members); 0 = no limit.
    pub max_envs: usize,
    /// Most environments in one batch; 0 = no limit.
    pub max_batch_size: usize,
    /// Largest accepted `document_json`, in bytes; 0 = no limit (beyond the message size).
    pub max_document_bytes: usize,
    /// Largest gRPC message decoded or encoded, in bytes. 0 keeps tonic's 4 MiB default.
    pub max_message_bytes: usize,
    /// Most instances per document; 0 = no limit.
    pub max_instances: usize,
    /// Most joints per document (fixed ones included); 0 = no limit.
    pub max_joints: usize,
    /// Most DOFs per document; 0 = no limit.
    pub max_dofs: usize,
    /// Most end effectors per env; 0 = no limit.
    pub max_end_effectors: usize,
    /// Most work per step call, in DOF-substeps (envs × substeps × DOFs); 0 = no limit.
    pub max_step_work: usize,
    /// Most contact work per env step, in contact point-substeps (contact points ×
    /// substeps); 0 = no limit.
    pub max_contact_work: usize,
    /// TLS (`--tls-cert`, `--tls-key`, `--tls-client-ca`); `None` = plaintext.
    pub tls: Option<TlsConfig>,
    /// Where to serve Prometheus metrics (`GET /metrics`, plain HTTP); `None` = nowhere.
    pub metrics_listen: Option<std::net::SocketAddr>,
    /// Where to serve `grpc.health.v1.Health` alone, in plaintext and without a token
    /// (`--health-listen`): for probes that cannot speak TLS, such as the kubelet's gRPC
    /// probe, while the main listener serves TLS. `None` = only on the main listener.
    pub health_listen: Option<std::net::SocketAddr>,
    /// Where to serve the read-only dashboard page and its JSON API (plain HTTP);
    /// `None` = nowhere. A non-loopback address needs `auth_tokens` (the server refuses
    /// to start otherwise).
    pub dashboard_listen: Option<std::net::SocketAddr>,
    /// Bearer tokens and their tenants (`--auth-tokens`); `None` = auth off, every caller
    /// is the anonymous tenant.
    pub auth_tokens: Option<Arc<TokenTable>>,
    /// Most environments one tenant holds at once; 0 = no limit beyond `max_envs`.
    pub tenant_max_envs: usize,
    /// The model library (`--models DIR`) requests name by `model`; `None` = none.
    pub models: Option<Arc<crate::models::ModelLibrary>>,
    /// Envs and batches untouched for this long are closed. `Duration::ZERO` disables it.
    pub idle_ttl: Duration,
    /// How often the idle sweeper looks; `None` = a quarter of `idle_ttl`, at least 1 s
    /// and at most 60 s. Tests set it short.
    pub sweep_interval: Option<Duration>,
    /// The clock idle times are measured on: the system's, or one a test moves by hand.
    pub clock: Clock,
    /// Fault injection for the panic-containment test, in debug builds only (never in a
    /// release build, which is what ships): a `Step` or `StepBatch` whose first action
    /// value is exactly this number panics inside its pool job instead of stepping. (Not a
    /// cargo feature: a feature the tests turn on would make every build that includes a
    /// test or an example compile this crate twice over; README, "Build once".)
    #[cfg(debug_assertions)]
    #[doc(hidden)]
    pub panic_on_action: Option<f32>,
    /// Test-only gate on the pool's jobs, in debug builds only, for the same reason: see
    /// [`crate::JobGate`].
    #[cfg(debug_assertions)]
    #[doc(hidden)]
    pub job_gate: Option<crate::JobGate>,
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig {
            threads: 0,
            pool_niceness: 0,
            max_envs: DEFAULT_MAX_ENVS,
            max_batch_size: DEFAULT_MAX_BATCH_SIZE,
            max_document_bytes: DEFAULT_MAX_DOCUMENT_BYTES,
            max_message_bytes: DEFAULT_MAX_MESSAGE_BYTES,
            max_instances: DEFAULT_MAX_INSTANCES,
            max_joints: DEFAULT_MAX_JOINTS,
            max_dofs: DEFAULT_MAX_DOFS,
            max_end_effectors: DEFAULT_MAX_END_EFFECTORS,
            max_step_work: DEFAULT_MAX_STEP_WORK,
            max_contact_work: DEFAULT_MAX_CONTACT_WORK,
            tls: None,
            metrics_listen: None,
            health_listen: None,
            dashboard_listen: None,
            auth_tokens: None,
            tenant_max_envs: 0,
            models: None,
            idle_ttl: DEFAULT_IDLE_TTL,
            sweep_interval: None,
            clock: Clock::system(),
            #[cfg(debug_assertions)]
            panic_on_action: None,
            #[cfg(debug_assertions)]
            job_gate: None,
        }
    }
}

impl ServerConfig {
    /// The value of `limit` here; 0 = no limit.
    pub fn limit(&self, limit: Limit) -> usize {
        match limit {
            Limit::Envs => self.max_envs,
            Limit::TenantEnvs => self.tenant_max_envs,
            Limit::BatchSize => self.max_batch_size,
            Limit::DocumentBytes => self.max_document_bytes,
            Limit::MessageBytes => self.max_message_bytes,
            Limit::Instances => self.max_instances,
            Limit::Joints => self.max_joints,
            Limit::Dofs => self.max_dofs,
            Limit::EndEffectors => self.max_end_effectors,
            Limit::StepWork => self.max_step_work,
            Limit::ContactWork => self.max_contact_work,
        }
    }

    /// The idle TTL, if reclaiming is enabled.
    pub fn idle_ttl(&self) -> Option<Duration> {
        (!self.idle_ttl.is_zero()).then_some(self.idle_ttl)
    }

    /// How often the idle sweeper runs.
    pub fn sweep_interval(&self) -> Duration {
        self.sweep_interval.unwrap_or_else(|| {
            (self.idle_ttl / 4).clamp(Duration::from_secs(1), Duration::from_secs(60))
        })
    }
}
