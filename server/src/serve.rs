//! [`serve`]: wires the pool, the services (simulator, health, reflection), the idle
//! sweeper, the metrics and dashboard listeners, and graceful shutdown around one
//! listener.

use std::future::Future;
use std::sync::Arc;
use std::time::Duration;

use gymfleet_batch::StepPool;
use gymfleet_proto::v1::simulator_server::SimulatorServer;
use tokio::sync::{oneshot, watch};
use tonic::service::interceptor::InterceptedService;
use tonic::transport::server::TcpIncoming;
use tonic::transport::{Certificate, Identity, Server, ServerTlsConfig};
use tonic_health::pb::health_server::{Health, HealthServer};

use crate::auth::Authenticator;
use crate::clock::Clock;
use crate::config::{ServerConfig, TlsConfig};
use crate::error::StartupError;

type Result<T, E = StartupError> = std::result::Result<T, E>;
use crate::listen::Listener;
use crate::service::SimulatorService;
use crate::simulation::Simulation;

/// Serves the simulator on `listener` (a `tokio::net::TcpListener`, or any [`Listener`],
/// e.g. a Unix-domain socket) until `shutdown` completes, then stops accepting
/// connections, ends open `StreamBatch` streams with UNAVAILABLE, waits for in-flight
/// calls to finish, and returns.
///
/// Also serves `grpc.health.v1.Health` (with `gymfleet.v1.Simulator` SERVING) and gRPC
/// reflection v1 and v1alpha. Accepted TCP connections get `TCP_NODELAY`. With
/// `config.auth_tokens`, every service but health needs a bearer token. With
/// `config.dashboard_listen`, also serves the dashboard there (refused on an address other
/// than loopback without auth tokens), and stops it with the rest.
///
/// ```no_run
/// # async fn demo() -> Result<(), Box<dyn std::error::Error>> {
/// let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await?;
/// let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
/// let server = tokio::spawn(gymfleet_server::serve(
///     listener,
///     gymfleet_server::ServerConfig::default(),
///     async { stopped.await.ok(); },
/// ));
/// // ... drive it with gymfleet-client ...
/// stop.send(()).ok();
/// server.await.expect("server task")?;
/// # Ok(())
/// # }
/// ```
pub async fn serve(
    listener: impl Into<Listener>,
    config: ServerConfig,
    shutdown: impl Future<Output = ()>,
) -> Result<()> {
    let dashboard = crate::dashboard::bind(&config).await?;
    serve_bound(listener.into(), dashboard, config, shutdown, None).await
}

/// The simulator service as the network reaches it (behind the authenticator, with the
/// message limits), for clients in the same process ([`crate::LocalServer::in_process`]).
pub(crate) type InProcess = InterceptedService<SimulatorServer<SimulatorService>, Authenticator>;

/// [`serve`] with the dashboard's listener (if `config.dashboard_listen` is set) already
/// bound, so that [`crate::LocalServer`] knows its address before serving.
pub(crate) async fn serve_bound(
    listener: Listener,
    dashboard: Option<tokio::net::TcpListener>,
    config: ServerConfig,
    shutdown: impl Future<Output = ()>,
    in_process: Option<oneshot::Sender<InProcess>>,
) -> Result<()> {
    // TLS first: an unusable certificate or key stops the start before anything else is
    // bound or announced.
    let mut builder = Server::builder();
    if let Some(tls) = &config.tls {
        builder = builder
            .tls_config(server_tls(tls))
            .map_err(|e| StartupError::Tls(error_chain(&e)))?;
    }
    let pool = StepPool::with_niceness(config.threads, config.pool_niceness)?;
    let threads = pool.threads();
    let sim = Arc::new(Simulation::new(config.clone(), pool));
    let (stop_tx, stop_rx) = watch::channel(false);

    let (health, health_service) = tonic_health::server::health_reporter();
    health
        .set_serving::<SimulatorServer<SimulatorService>>()
        .await;
    let reflection = || {
        tonic_reflection::server::Builder::configure()
            .register_encoded_file_descriptor_set(gymfleet_proto::FILE_DESCRIPTOR_SET)
            .register_encoded_file_descriptor_set(tonic_health::pb::FILE_DESCRIPTOR_SET)
    };
    let (reflection_v1, reflection_v1alpha) =
        (reflection().build_v1()?, reflection().build_v1alpha()?);

    let mut simulator =
        SimulatorServer::new(SimulatorService::new(Arc::clone(&sim), stop_rx.clone()));
    if config.max_message_bytes != 0 {
        simulator = simulator
            .max_decoding_message_size(config.max_message_bytes)
            .max_encoding_message_size(config.max_message_bytes);
    }

    let background = Background::start(&config, &sim, &health_service, dashboard, &stop_rx).await?;
    log_serving(&config, listener.local_addr()?, threads);
    let signal = async move {
        shutdown.await;
        tracing::info!("shutting down: finishing in-flight calls");
        health
            .set_not_serving::<SimulatorServer<SimulatorService>>()
            .await;
        let _ = stop_tx.send(true);
    };
    // Everything but health answers only callers with a token when auth is on.
    let auth = Authenticator::new(config.auth_tokens.clone(), sim.shared_metrics());
    let simulator = InterceptedService::new(simulator, auth.clone());
    if let Some(sender) = in_process {
        // The caller may have given up waiting; serving goes on regardless.
        let _ = sender.send(simulator.clone());
    }
    let router = builder
        .add_service(health_service)
        .add_service(InterceptedService::new(reflection_v1, auth.clone()))
        .add_service(InterceptedService::new(reflection_v1alpha, auth.clone()))
        .add_service(simulator);
    let served = match listener {
        Listener::Tcp(listener) => {
            let incoming = TcpIncoming::from(listener).with_nodelay(Some(true));
            router.serve_with_incoming_shutdown(incoming, signal).await
        }
        #[cfg(unix)]
        Listener::Unix(listener, socket_file) => {
            let incoming = tokio_stream::wrappers::UnixListenerStream::new(listener);
            let served = router.serve_with_incoming_shutdown(incoming, signal).await;
            drop(socket_file);
            served
        }
    };
    background.stop().await;
    served?;
    tracing::info!("stopped");
    Ok(())
}

fn log_serving(config: &ServerConfig, addr: impl std::fmt::Display, threads: usize) {
    let tenants = config.auth_tokens.as_ref().map_or(0, |t| t.tenants().len());
    tracing::info!(
        %addr,
        tls = config.tls.is_some(),
        mutual_tls = config.tls.as_ref().is_some_and(|t| t.client_ca_pem.is_some()),
        threads,
        pool_niceness = config.pool_niceness,
        idle_ttl_secs = config.idle_ttl.as_secs(),
        auth = config.auth_tokens.is_some(),
        tenants,
        "serving gymfleet.v1.Simulator"
    );
}

/// The tasks a server runs beside its main listener: the metrics and health-only
/// listeners, the dashboard and the idle sweeper, each if configured.
struct Background {
    metrics: Option<tokio::task::JoinHandle<()>>,
    health_only: Option<tokio::task::JoinHandle<()>>,
    dashboard: Option<tokio::task::JoinHandle<()>>,
    sweeper: Option<tokio::task::JoinHandle<()>>,
}

impl Background {
    async fn start<H: Health>(
        config: &ServerConfig,
        sim: &Arc<Simulation>,
        health_service: &HealthServer<H>,
        dashboard: Option<tokio::net::TcpListener>,
        stop_rx: &watch::Receiver<bool>,
    ) -> Result<Self> {
        let metrics = match config.metrics_listen {
            Some(addr) => {
                let listener =
                    tokio::net::TcpListener::bind(addr)
                        .await
                        .map_err(|e| StartupError::Bind {
                            addr: addr.to_string(),
                            reason: e.to_string(),
                        })?;
                tracing::info!(addr = %listener.local_addr()?, "serving metrics at /metrics");
                let sim = Arc::clone(sim);
                let scrape = Arc::new(move || sim.metrics().encode(&sim.gauges()));
                Some(tokio::spawn(crate::metrics::serve_metrics(
                    listener, scrape,
                )))
            }
            None => None,
        };
        let health_only = match config.health_listen {
            Some(addr) => Some(serve_health(addr, health_service.clone()).await?),
            None => None,
        };
        let dashboard = match dashboard {
            Some(listener) => {
                tracing::info!(addr = %listener.local_addr()?, "serving the dashboard at /");
                Some(tokio::spawn(crate::dashboard::serve_dashboard(
                    listener,
                    Arc::clone(sim),
                    config.clone(),
                    stop_rx.clone(),
                )))
            }
            None => None,
        };
        let sweeper = config.idle_ttl().map(|ttl| {
            tokio::spawn(sweep_idle(
                Arc::clone(sim),
                ttl,
                config.sweep_interval(),
                config.clock.clone(),
                stop_rx.clone(),
            ))
        });
        Ok(Self {
            metrics,
            health_only,
            dashboard,
            sweeper,
        })
    }

    /// Once the main listener has drained.
    async fn stop(self) {
        if let Some(metrics) = self.metrics {
            metrics.abort();
        }
        if let Some(health_only) = self.health_only {
            // Probes keep an answer (NOT_SERVING) until the main listener has drained.
            health_only.abort();
        }
        if let Some(dashboard) = self.dashboard {
            // It watches the same stop signal (or sees it dropped, if serving failed) and
            // returns once its requests in flight are answered.
            let _ = dashboard.await;
        }
        if let Some(sweeper) = self.sweeper {
            // It watches the same stop signal; it has stopped or stops at its next wake-up.
            sweeper.abort();
        }
    }
}

/// Serves `health` alone at `addr`, in plaintext (`ServerConfig::health_listen`), until
/// the returned task is aborted.
async fn serve_health<H: Health>(
    addr: std::net::SocketAddr,
    health: HealthServer<H>,
) -> Result<tokio::task::JoinHandle<()>> {
    let listener = tokio::net::TcpListener::bind(addr)
        .await
        .map_err(|e| StartupError::Bind {
            addr: addr.to_string(),
            reason: e.to_string(),
        })?;
    tracing::info!(addr = %listener.local_addr()?, "serving gRPC health (plaintext)");
    let incoming = TcpIncoming::from(listener).with_nodelay(Some(true));
    let router = Server::builder().add_service(health);
    Ok(tokio::spawn(async move {
        if let Err(e) = router.serve_with_incoming(incoming).await {
            tracing::warn!(error = %error_chain(&e), "the health listener stopped");
        }
    }))
}

fn server_tls(tls: &TlsConfig) -> ServerTlsConfig {
    let identity = Identity::from_pem(&tls.cert_pem, &tls.key_pem);
    let config = ServerTlsConfig::new().identity(identity);
    match &tls.client_ca_pem {
        Some(ca) => config.client_ca_root(Certificate::from_pem(ca)),
        None => config,
    }
}

/// An error and its sources, joined.
fn error_chain(err: &(dyn std::error::Error + 'static)) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(s) = source {
        text.push_str(": ");
        text.push_str(&s.to_string());
        source = s.source();
    }
    text
}

/// Every `interval`, and whenever a manual `clock` moves, closes the envs and batches
/// idle for at least `ttl`.
async fn sweep_idle(
    sim: Arc<Simulation>,
    ttl: Duration,
    interval: Duration,
    clock: Clock,
    mut stop: watch::Receiver<bool>,
) {
    let mut ticks = tokio::time::interval(interval);
    ticks.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut moves = clock.moves();
    loop {
        let moved = async {
            match &mut moves {
                Some(moves) => moves.changed().await.is_ok(),
                None => std::future::pending().await,
            }
        };
        tokio::select! {
            _ = stop.wait_for(|stop| *stop) => return,
            _ = ticks.tick() => {}
            true = moved => {}
        }
        clock.sweep(|| sim.reclaim_idle(ttl));
    }
}
