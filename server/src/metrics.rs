//! [`Metrics`]: what the server counts, and `--metrics-listen`'s `/metrics` endpoint
//! (Prometheus/OpenMetrics text, encoded by `prometheus-client` from a registry of this
//! server's own, so several servers in one process never mix their numbers).
//!
//! | name | kind | labels |
//! |---|---|---|
//! | `gymfleet_env_steps_total` | counter | `tenant` |
//! | `gymfleet_envs_open`, `gymfleet_batches_open`, `gymfleet_batch_envs_open` | gauge | `tenant` |
//! | `gymfleet_rpc_duration_seconds` | histogram | `method`, `code` |
//! | `gymfleet_rejected_requests_total` | counter | `reason` |
//! | `gymfleet_pool_queue_depth` | gauge | |
//! | `gymfleet_pool_wait_seconds_total`, `gymfleet_pool_jobs_total` | counter | |
//!
//! The anonymous tenant (auth off) is labelled `tenant=""`.

use std::sync::Arc;
use std::time::Duration;

use prometheus_client::encoding::EncodeLabelSet;
use prometheus_client::metrics::counter::Counter;
use prometheus_client::metrics::family::Family;
use prometheus_client::metrics::gauge::Gauge;
use prometheus_client::metrics::histogram::{exponential_buckets, Histogram};
use prometheus_client::registry::Registry;
use tokio::net::TcpListener;
use tonic::Code;

use gymfleet_batch::JobQueueStats;

use crate::error::ServerError;
use crate::tenant::Tenant;

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
struct TenantLabel {
    tenant: String,
}

impl TenantLabel {
    fn of(tenant: &Tenant) -> Self {
        TenantLabel {
            tenant: tenant.name().to_string(),
        }
    }
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
struct RpcLabels {
    method: &'static str,
    code: &'static str,
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
struct ReasonLabel {
    reason: String,
}

type HistogramFamily = Family<RpcLabels, Histogram, fn() -> Histogram>;

fn rpc_histogram() -> Histogram {
    // 25 µs to ~100 s: a bare round trip up to a 16k-env batch creation.
    Histogram::new(exponential_buckets(25e-6, 2.0, 22))
}

/// The server's metrics.
pub(crate) struct Metrics {
    registry: Registry,
    env_steps: Family<TenantLabel, Counter>,
    envs_open: Family<TenantLabel, Gauge>,
    batches_open: Family<TenantLabel, Gauge>,
    batch_envs_open: Family<TenantLabel, Gauge>,
    rpc_duration: HistogramFamily,
    rejected: Family<ReasonLabel, Counter>,
    pool_queue_depth: Gauge,
    pool_wait: Counter<f64>,
    pool_jobs: Counter,
    /// Held while a scrape refreshes and encodes.
    scrape: std::sync::Mutex<()>,
}

impl std::fmt::Debug for Metrics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Metrics")
    }
}

impl Metrics {
    pub(crate) fn new() -> Self {
        let mut registry = Registry::default();
        let env_steps = Family::<TenantLabel, Counter>::default();
        registry.register(
            "gymfleet_env_steps",
            "Environment steps taken (a batch step of n envs counts n)",
            env_steps.clone(),
        );
        let envs_open = Family::<TenantLabel, Gauge>::default();
        registry.register(
            "gymfleet_envs_open",
            "Single environments open",
            envs_open.clone(),
        );
        let batches_open = Family::<TenantLabel, Gauge>::default();
        registry.register(
            "gymfleet_batches_open",
            "Batches open",
            batches_open.clone(),
        );
        let batch_envs_open = Family::<TenantLabel, Gauge>::default();
        registry.register(
            "gymfleet_batch_envs_open",
            "Environments held in open batches",
            batch_envs_open.clone(),
        );
        let rpc_duration: HistogramFamily = Family::new_with_constructor(rpc_histogram);
        registry.register(
            "gymfleet_rpc_duration_seconds",
            "Time from a call's arrival to its answer, by method and status code",
            rpc_duration.clone(),
        );
        let rejected = Family::<ReasonLabel, Counter>::default();
        registry.register(
            "gymfleet_rejected_requests",
            "Calls refused before any work: a limit (named by its flag), no or a bad token, \
             or an invalid argument",
            rejected.clone(),
        );
        let pool_queue_depth = Gauge::default();
        registry.register(
            "gymfleet_pool_queue_depth",
            "Jobs handed to the simulation pool and waiting for a thread",
            pool_queue_depth.clone(),
        );
        let pool_wait = Counter::<f64>::default();
        registry.register(
            "gymfleet_pool_wait_seconds",
            "Time the started pool jobs waited for a thread, in all (divide by \
             gymfleet_pool_jobs_total for the mean)",
            pool_wait.clone(),
        );
        let pool_jobs = Counter::default();
        registry.register("gymfleet_pool_jobs", "Pool jobs started", pool_jobs.clone());
        Metrics {
            registry,
            env_steps,
            envs_open,
            batches_open,
            batch_envs_open,
            rpc_duration,
            rejected,
            pool_queue_depth,
            pool_wait,
            pool_jobs,
            scrape: std::sync::Mutex::new(()),
        }
    }

    /// Counts `n` env steps of `tenant`.
    pub(crate) fn env_steps(&self, tenant: &Tenant, n: usize) {
        self.env_steps
            .get_or_create(&TenantLabel::of(tenant))
            .inc_by(u64::try_from(n).unwrap_or(u64::MAX));
    }

    /// Records a finished call.
    pub(crate) fn rpc(&self, method: &'static str, code: Code, took: Duration) {
        self.rpc_duration
            .get_or_create(&RpcLabels {
                method,
                code: code_name(code),
            })
            .observe(took.as_secs_f64());
    }

    /// Counts a call refused before any work, if `err` is such a refusal.
    pub(crate) fn rejected(&self, err: &ServerError) {
        if let Some(reason) = rejection_reason(err) {
            self.reject(reason);
        }
    }

    /// Counts a call refused for `reason`.
    pub(crate) fn reject(&self, reason: &str) {
        self.rejected
            .get_or_create(&ReasonLabel {
                reason: reason.to_string(),
            })
            .inc();
    }

    /// The text of `/metrics`, with the gauges set from `gauges`, read from the server
    /// now (`Simulation::gauges`).
    pub(crate) fn encode(&self, gauges: &Gauges) -> String {
        // One scrape at a time: the gauges are cleared and refilled, and the pool
        // counters catch up by difference, which two scrapes at once would do twice.
        let _one_scrape = self
            .scrape
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        for family in [&self.envs_open, &self.batches_open, &self.batch_envs_open] {
            family.clear();
        }
        let as_gauge = |n: usize| i64::try_from(n).unwrap_or(i64::MAX);
        for (tenant, open) in &gauges.open {
            let label = TenantLabel::of(tenant);
            self.envs_open
                .get_or_create(&label)
                .set(as_gauge(open.envs));
            self.batches_open
                .get_or_create(&label)
                .set(as_gauge(open.batches));
            self.batch_envs_open
                .get_or_create(&label)
                .set(as_gauge(open.batch_envs));
        }
        let jobs = &gauges.jobs;
        self.pool_queue_depth.set(as_gauge(jobs.waiting));
        // Counters only go up: add what is new since the last scrape.
        let started = jobs.started.saturating_sub(self.pool_jobs.get());
        self.pool_jobs.inc_by(started);
        let waited = Duration::from_nanos(jobs.waited_ns).as_secs_f64() - self.pool_wait.get();
        if waited > 0.0 {
            self.pool_wait.inc_by(waited);
        }
        let mut text = String::new();
        // Writing to a String cannot fail.
        let _ = prometheus_client::encoding::text::encode(&mut text, &self.registry);
        text
    }
}

/// What the gauges of `/metrics` show, read from the server at a scrape.
#[derive(Debug, Default, Clone)]
pub(crate) struct Gauges {
    /// What each tenant holds.
    pub(crate) open: Vec<(Tenant, OpenCounts)>,
    /// The pool's job queue.
    pub(crate) jobs: JobQueueStats,
}

/// What one tenant holds.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct OpenCounts {
    pub(crate) envs: usize,
    pub(crate) batches: usize,
    pub(crate) batch_envs: usize,
}

/// Why `err` refused a call before any work: its limit's name (`max_batch_size`), or
/// `invalid_argument`; `None` for other errors.
fn rejection_reason(err: &ServerError) -> Option<&'static str> {
    match err.limit() {
        Some(limit) => Some(limit.name()),
        None => (err.code() == Code::InvalidArgument).then_some("invalid_argument"),
    }
}

fn code_name(code: Code) -> &'static str {
    match code {
        Code::Ok => "OK",
        Code::Cancelled => "CANCELLED",
        Code::Unknown => "UNKNOWN",
        Code::InvalidArgument => "INVALID_ARGUMENT",
        Code::DeadlineExceeded => "DEADLINE_EXCEEDED",
        Code::NotFound => "NOT_FOUND",
        Code::AlreadyExists => "ALREADY_EXISTS",
        Code::PermissionDenied => "PERMISSION_DENIED",
        Code::ResourceExhausted => "RESOURCE_EXHAUSTED",
        Code::FailedPrecondition => "FAILED_PRECONDITION",
        Code::Aborted => "ABORTED",
        Code::OutOfRange => "OUT_OF_RANGE",
        Code::Unimplemented => "UNIMPLEMENTED",
        Code::Internal => "INTERNAL",
        Code::Unavailable => "UNAVAILABLE",
        Code::DataLoss => "DATA_LOSS",
        Code::Unauthenticated => "UNAUTHENTICATED",
    }
}

/// Serves `GET /metrics` on `listener` until the task is aborted; each request's text
/// comes from `scrape` (`Metrics::encode` of the server's gauges), run off the async workers.
pub(crate) async fn serve_metrics(
    listener: TcpListener,
    scrape: Arc<dyn Fn() -> String + Send + Sync>,
) {
    use axum::http::header::CONTENT_TYPE;
    let app = axum::Router::new().route(
        "/metrics",
        axum::routing::get(move || {
            let scrape = Arc::clone(&scrape);
            async move {
                // Reading the registries is quick, but keep it off the async workers'
                // hot path all the same.
                let text = tokio::task::spawn_blocking(move || scrape())
                    .await
                    .unwrap_or_default();
                (
                    [(
                        CONTENT_TYPE,
                        "application/openmetrics-text; version=1.0.0; charset=utf-8",
                    )],
                    text,
                )
            }
        }),
    );
    if let Err(err) = axum::serve(listener, app).await {
        tracing::error!(%err, "metrics endpoint failed");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refusals_are_named_after_their_limits_flag() {
        let too_complex = ServerError::TooComplex {
            what: "assembly.joints",
            count: 9,
            max: 8,
            limit: crate::Limit::Joints,
        };
        assert_eq!(rejection_reason(&too_complex), Some("max_joints"));
        let batch = ServerError::BatchTooLarge { n_envs: 9, max: 8 };
        assert_eq!(rejection_reason(&batch), Some("max_batch_size"));
        assert_eq!(rejection_reason(&ServerError::ShuttingDown), None);
    }
}
