//! Where a handle's server is: the process's embedded server (`server=None`), one
//! address, or a comma-separated fleet ([`resolve`]); the [`Server`] class that runs one
//! more server in this process; and one cached connection per address.
//!
//! Every embedded server is the server crate's [`LocalServer`] on `127.0.0.1:0`, reached
//! over loopback gRPC like any other: the package has one client implementation.

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use gymfleet_client::{Client, ClientBuilder, Fleet, FleetEndpoints, ServerInfo};
use gymfleet_server::{LocalServer, ServerConfig};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::to_py_err;
use crate::runtime::{runtime, wait};

/// What a handle talks to.
pub(crate) enum Target {
    /// One server.
    One(Client),
    /// Several; batches are sharded over them.
    Fleet(Fleet),
}

/// The connection for `server` (`None`: the embedded server, started on first use; a
/// comma-separated list: a fleet), sending `token` (instead of `GYMFLEET_TOKEN`) when
/// given.
pub(crate) fn resolve(
    py: Python<'_>,
    server: Option<&str>,
    token: Option<&str>,
) -> PyResult<Target> {
    let addr = match server {
        // The embedded server: called in this process (no socket), no token.
        None => return embedded_client(py).map(Target::One),
        Some(list) if list.contains(',') => {
            let endpoints = FleetEndpoints::parse(list).map_err(to_py_err)?;
            let clients = endpoints
                .addrs()
                .iter()
                .map(|a| client(py, a, token))
                .collect::<PyResult<Vec<_>>>()?;
            return Fleet::from_clients(clients)
                .map(Target::Fleet)
                .map_err(to_py_err);
        }
        Some(addr) => addr.trim().to_string(),
    };
    client(py, &addr, token).map(Target::One)
}

/// The cached connection to the server at `addr`, with the token and TLS settings of
/// the `GYMFLEET_*` variables the command-line tools read too (`ClientBuilder::from_env`);
/// `token` replaces `GYMFLEET_TOKEN` (a connection per address and token).
fn client(py: Python<'_>, addr: &str, token: Option<&str>) -> PyResult<Client> {
    let mut settings = ClientBuilder::from_env(addr).map_err(to_py_err)?;
    let key = match token {
        Some(token) => {
            if token.is_empty() {
                return Err(crate::options::invalid(
                    "token: expected a non-empty bearer token".to_string(),
                ));
            }
            settings = settings.token(token);
            format!("{addr}\u{0}{token}")
        }
        None => addr.to_string(),
    };
    cached(py, &key, settings)
}

/// The cached connection to `addr`, connecting with `settings` on first use. A
/// connection outlives a server restart (it reconnects), so one per address is enough.
fn cached(py: Python<'_>, addr: &str, settings: ClientBuilder) -> PyResult<Client> {
    static CLIENTS: OnceLock<Mutex<HashMap<String, Client>>> = OnceLock::new();
    let clients = CLIENTS.get_or_init(Default::default);
    if let Some(client) = lock(clients).get(addr) {
        return Ok(client.clone());
    }
    let client = wait(py, None, || settings.connect())?;
    lock(clients).insert(addr.to_string(), client.clone());
    Ok(client)
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The address of the process's embedded server, started on first use: one pool thread
/// per core this process may use, at the process's own priority (it shares the machine
/// with the trainer that calls it: nicer threads would starve beside the trainer's own,
/// BENCHMARKS.md N1), the server's default limits, no idle TTL (its envs belong to this
/// process, which frees them when they are closed or garbage-collected). It runs until
/// the process exits.
#[pyfunction]
pub(crate) fn embedded_address(py: Python<'_>) -> PyResult<String> {
    embedded(py).map(LocalServer::client_addr)
}

/// The embedded server (see [`embedded_address`]), started on first use.
fn embedded(py: Python<'_>) -> PyResult<&'static LocalServer> {
    static EMBEDDED: OnceLock<LocalServer> = OnceLock::new();
    static STARTING: Mutex<()> = Mutex::new(());
    if let Some(server) = EMBEDDED.get() {
        return Ok(server);
    }
    let started = py.detach(|| {
        let _one_at_a_time = lock(&STARTING);
        if let Some(server) = EMBEDDED.get() {
            return Ok(server);
        }
        let config = ServerConfig {
            idle_ttl: Duration::ZERO,
            ..ServerConfig::default()
        };
        let server = runtime().block_on(LocalServer::start(config))?;
        Ok(EMBEDDED.get_or_init(|| server))
    });
    started.map_err(start_error)
}

/// The connection to the embedded server: its service called in this process, with no
/// socket or HTTP/2 between (`LocalServer::in_process`). Other processes (and the
/// dashboard) still reach the server at [`embedded_address`].
fn embedded_client(py: Python<'_>) -> PyResult<Client> {
    static CLIENT: OnceLock<Client> = OnceLock::new();
    if let Some(client) = CLIENT.get() {
        return Ok(client.clone());
    }
    let server = embedded(py)?;
    let client = Client::builder(server.client_addr())
        .in_process(server.in_process())
        .map_err(to_py_err)?;
    Ok(CLIENT.get_or_init(|| client).clone())
}

fn start_error(e: gymfleet_server::StartupError) -> PyErr {
    PyRuntimeError::new_err(format!("cannot start the embedded gymfleet server: {e}"))
}

fn start(py: Python<'_>, config: ServerConfig) -> PyResult<LocalServer> {
    py.detach(|| runtime().block_on(LocalServer::start(config)))
        .map_err(start_error)
}

/// A gymfleet server running inside this process on `127.0.0.1:<free port>`, until
/// `stop()` (or the end of a `with` block, or the process).
#[pyclass(module = "gymfleet._core", frozen)]
pub(crate) struct Server {
    address: String,
    server: Mutex<Option<LocalServer>>,
}

#[pymethods]
impl Server {
    #[new]
    #[pyo3(signature = (
        *, threads=0, max_envs=None, max_batch_size=None, idle_ttl=None, auth_tokens=None,
        models=None, pool_niceness=0
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        threads: usize,
        max_envs: Option<usize>,
        max_batch_size: Option<usize>,
        idle_ttl: Option<f64>,
        auth_tokens: Option<std::path::PathBuf>,
        models: Option<std::path::PathBuf>,
        pool_niceness: i64,
    ) -> PyResult<Self> {
        let defaults = ServerConfig::default();
        let pool_niceness = u8::try_from(pool_niceness)
            .ok()
            .filter(|n| *n <= 19)
            .ok_or_else(|| {
                crate::options::invalid(format!(
                    "pool_niceness: expected a niceness 0..=19 (0: this process's own \
                     priority), got {pool_niceness}"
                ))
            })?;
        let idle_ttl = match idle_ttl {
            None => Duration::ZERO,
            Some(s) if (0.0..1e9).contains(&s) => Duration::from_secs_f64(s),
            Some(s) => {
                return Err(crate::options::invalid(format!(
                    "idle_ttl: expected a number of seconds >= 0 (0: never), got {s}"
                )))
            }
        };
        let auth_tokens = match auth_tokens {
            Some(path) => Some(std::sync::Arc::new(
                gymfleet_server::TokenTable::load(&path).map_err(crate::options::invalid)?,
            )),
            None => None,
        };
        // The model library (`--models DIR`): read, converted and checked now.
        let models = match models {
            Some(dir) => Some(std::sync::Arc::new(
                py.detach(|| gymfleet_server::ModelLibrary::load(&dir))
                    .map_err(|e| crate::options::invalid(format!("models: {e}")))?,
            )),
            None => None,
        };
        let config = ServerConfig {
            threads,
            pool_niceness,
            models,
            max_envs: max_envs.unwrap_or(defaults.max_envs),
            max_batch_size: max_batch_size.unwrap_or(defaults.max_batch_size),
            idle_ttl,
            auth_tokens,
            ..defaults
        };
        let server = start(py, config)?;
        Ok(Server {
            address: server.client_addr(),
            server: Mutex::new(Some(server)),
        })
    }

    /// `"127.0.0.1:<port>"`: what `server=` takes.
    #[getter]
    fn address(&self) -> String {
        self.address.clone()
    }

    /// Whether it is still serving.
    #[getter]
    fn running(&self) -> bool {
        lock(&self.server).is_some()
    }

    /// Stops serving: in-flight calls finish, then its envs and batches are gone and
    /// clients of it get `Unavailable` (a fleet: `ServerLost`). Stopping twice is a no-op.
    fn stop(&self, py: Python<'_>) -> PyResult<()> {
        let Some(server) = lock(&self.server).take() else {
            return Ok(());
        };
        py.detach(|| runtime().block_on(server.stop()))
            .map_err(|e| PyRuntimeError::new_err(format!("gymfleet server {}: {e}", self.address)))
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    fn __exit__(
        &self,
        py: Python<'_>,
        _exc_type: Option<Bound<'_, PyAny>>,
        _exc: Option<Bound<'_, PyAny>>,
        _traceback: Option<Bound<'_, PyAny>>,
    ) -> PyResult<bool> {
        self.stop(py)?;
        Ok(false)
    }

    fn __repr__(&self) -> String {
        let state = if self.running() { "running" } else { "stopped" };
        format!("gymfleet.Server(address='{}', {state})", self.address)
    }
}

/// The per-pod addresses of a Kubernetes StatefulSet behind a headless Service,
/// `NAME-<i>.SERVICE.NAMESPACE.svc.cluster.local:PORT` for `i` in `0..replicas`.
#[pyfunction]
#[pyo3(signature = (name, service, namespace="default", replicas=1, port=50051))]
pub(crate) fn stateful_set(
    name: &str,
    service: &str,
    namespace: &str,
    replicas: usize,
    port: u16,
) -> PyResult<Vec<String>> {
    FleetEndpoints::stateful_set(name, service, namespace, replicas, port)
        .map(|e| e.addrs().to_vec())
        .map_err(to_py_err)
}

/// What a server says about itself (version, threads, envs and batches open, limits);
/// for a fleet, a list with one per server.
#[pyfunction]
#[pyo3(signature = (server=None, token=None))]
pub(crate) fn server_info(
    py: Python<'_>,
    server: Option<&str>,
    token: Option<&str>,
) -> PyResult<Py<PyAny>> {
    match resolve(py, server, token)? {
        Target::One(client) => {
            let info = wait(py, None, || async move { client.server_info().await })?;
            Ok(info_dict(py, &info)?.into_any().unbind())
        }
        Target::Fleet(fleet) => {
            let infos = wait(py, None, || async move { fleet.server_infos().await })?;
            let dicts = infos
                .iter()
                .map(|i| info_dict(py, i))
                .collect::<PyResult<Vec<_>>>()?;
            Ok(pyo3::types::PyList::new(py, dicts)?.into_any().unbind())
        }
    }
}

/// The server's model library (`--models DIR`): one dict per model, `{name, format,
/// dofs, action_dim}`, sorted by name; empty without a library. For a fleet, the first
/// server's (every server of a fleet is meant to hold the same library).
#[pyfunction]
#[pyo3(signature = (server=None, token=None))]
pub(crate) fn list_models<'py>(
    py: Python<'py>,
    server: Option<&str>,
    token: Option<&str>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let client = match resolve(py, server, token)? {
        Target::One(client) => client,
        Target::Fleet(fleet) => fleet.clients()[0].clone(),
    };
    let models = wait(py, None, || async move { client.list_models().await })?;
    models
        .iter()
        .map(|m| {
            let d = PyDict::new(py);
            d.set_item("name", &m.name)?;
            let format = match m.format {
                gymfleet_client::DocumentFormat::Mjcf => "mjcf",
                gymfleet_client::DocumentFormat::Urdf => "urdf",
                gymfleet_client::DocumentFormat::Json | gymfleet_client::DocumentFormat::Detect => {
                    "json"
                }
            };
            d.set_item("format", format)?;
            d.set_item("dofs", m.dofs)?;
            d.set_item("action_dim", m.action_dim)?;
            Ok(d)
        })
        .collect()
}

/// A description (MJCF text, or assembly JSON) as the assembly JSON `server` builds from
/// it, and the conversion's warnings (`ConvertDocument`).
#[pyfunction]
#[pyo3(signature = (document, server=None, assets=None, token=None, document_path=None))]
pub(crate) fn convert_document(
    py: Python<'_>,
    document: String,
    server: Option<&str>,
    assets: Option<Vec<u8>>,
    token: Option<&str>,
    document_path: Option<String>,
) -> PyResult<(String, Vec<String>)> {
    let client = match resolve(py, server, token)? {
        Target::One(client) => client,
        Target::Fleet(fleet) => fleet.clients()[0].clone(),
    };
    let converted = wait(py, None, || async move {
        client
            .convert_document_in(
                document,
                gymfleet_client::DocumentFormat::Detect,
                assets.unwrap_or_default(),
                document_path.as_deref().unwrap_or(""),
            )
            .await
    })?;
    Ok((converted.document_json, converted.warnings))
}

fn info_dict<'py>(py: Python<'py>, i: &ServerInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("version", &i.version)?;
    d.set_item("threads", i.threads)?;
    d.set_item("envs", i.envs)?;
    d.set_item("batches", i.batches)?;
    d.set_item("batch_envs", i.batch_envs)?;
    let limits = PyDict::new(py);
    limits.set_item("max_envs", i.limits.max_envs)?;
    limits.set_item("max_batch_size", i.limits.max_batch_size)?;
    limits.set_item("max_document_bytes", i.limits.max_document_bytes)?;
    limits.set_item("max_message_bytes", i.limits.max_message_bytes)?;
    limits.set_item("idle_ttl_seconds", i.limits.idle_ttl_seconds)?;
    limits.set_item("max_instances", i.limits.max_instances)?;
    limits.set_item("max_joints", i.limits.max_joints)?;
    limits.set_item("max_dofs", i.limits.max_dofs)?;
    limits.set_item("max_end_effectors", i.limits.max_end_effectors)?;
    limits.set_item("tenant_max_envs", i.limits.tenant_max_envs)?;
    limits.set_item("max_step_work", i.limits.max_step_work)?;
    limits.set_item("max_contact_work", i.limits.max_contact_work)?;
    d.set_item("limits", limits)?;
    d.set_item("tenant", &i.tenant)?;
    d.set_item("auth_required", i.auth_required)?;
    d.set_item("instance_id", &i.instance_id)?;
    Ok(d)
}
