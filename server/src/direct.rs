//! [`DirectService`]: the simulator service without a network: the same
//! `gymfleet.v1.Simulator` implementation that [`crate::serve`] mounts, called in the
//! calling process with requests it decoded itself. The fuzz targets (`fuzz/`) use it to
//! hand prost-decoded `CreateEnvRequest`s and `StepBatchRequest`s to the server's domain
//! path (edge conversion, limits, registry, pool) without a socket; a benchmark can use it
//! to tell the transport's share from the service's.

use std::sync::Arc;

use gymfleet_batch::StepPool;
use gymfleet_proto::v1::simulator_server::Simulator;
use tokio::sync::watch;
use tonic::Request;

use crate::config::ServerConfig;
use crate::error::Result;
use crate::service::SimulatorService;
use crate::simulation::Simulation;
use crate::tenant::Tenant;

/// A simulator service of its own (its own pool and registries), called directly.
/// Its calls need a tokio runtime, as a served one's do.
pub struct DirectService {
    service: SimulatorService,
    /// Kept so that open `StreamBatch` streams do not see a shutdown.
    _running: watch::Sender<bool>,
}

impl DirectService {
    /// A service with `config`'s limits and `config.threads` pool threads. The
    /// listener-related fields of `config` (TLS, auth tokens, metrics address) are unused:
    /// every call runs as the caller of [`DirectService::request`] says.
    pub fn new(config: ServerConfig) -> Result<Self> {
        let pool = StepPool::with_niceness(config.threads, config.pool_niceness)?;
        let sim = Arc::new(Simulation::new(config, pool));
        let (running, shutdown) = watch::channel(false);
        Ok(DirectService {
            service: SimulatorService::new(sim, shutdown),
            _running: running,
        })
    }

    /// The service, to call as tonic would (`simulator().step_batch(request).await`).
    pub fn simulator(&self) -> &impl Simulator {
        &self.service
    }

    /// `message` as a request of `tenant`, as the authenticator hands it on
    /// ([`Tenant::anonymous`] when auth is off).
    pub fn request<T>(message: T, tenant: &Tenant) -> Request<T> {
        let mut request = Request::new(message);
        request.extensions_mut().insert(tenant.clone());
        request
    }
}

impl std::fmt::Debug for DirectService {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DirectService").finish_non_exhaustive()
    }
}
