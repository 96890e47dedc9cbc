//! [`BatchHandle`]: a batch of envs on one server, or sharded over a fleet, for
//! `gymfleet.GymfleetVectorEnv`. Replies become numpy arrays without per-element
//! Python objects: observations take over the reply's decoded vector.

use gymfleet_client::{Autoreset, EnvState, FleetBatch};
use numpy::{PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::env::ActionKind;
use crate::info::batch_info;
use crate::options::{invalid, seed, timeout, CreateOptions};
use crate::rows::{matrix, step_tuple, StepRows, StepTuple};
use crate::runtime::{wait, Deadline};
use crate::servers::{resolve, Target};
use crate::stream::StepStream;

/// A batch of identical envs; its calls block (GIL released) until every shard answered.
#[pyclass(module = "gymfleet._core", frozen)]
pub(crate) struct BatchHandle {
    /// The batch, on one server (a fleet batch of one shard, `FleetBatch::from`) or
    /// sharded. An async lock: a call holds it across its network round trip.
    batch: tokio::sync::Mutex<FleetBatch>,
    info: gymfleet_client::BatchInfo,
    /// `(server, batch_id, start, stop)` per shard (changed by `recover`).
    placement: std::sync::Mutex<Vec<(String, String, usize, usize)>>,
    /// The per-call deadline; settable from Python.
    timeout: Deadline,
    closed: std::sync::atomic::AtomicBool,
}

/// `(server, batch_id, start, stop)` per shard of `batch`.
fn placement(batch: &FleetBatch) -> Vec<(String, String, usize, usize)> {
    batch
        .placement()
        .into_iter()
        .map(|p| (p.server, p.batch_id, p.envs.start, p.envs.end))
        .collect()
}

impl BatchHandle {
    /// A step's rows (`n` of them) as numpy arrays and a dict of termination reasons.
    fn step_tuple<'py>(
        &self,
        py: Python<'py>,
        rows: StepRows,
        n: usize,
    ) -> PyResult<StepTuple<'py>> {
        step_tuple(
            py,
            rows,
            n,
            self.info.observation_dim,
            self.info.term_names.len(),
        )
    }
}

#[pymethods]
impl BatchHandle {
    /// The per-call timeout in seconds (`None`: none).
    #[getter]
    fn get_timeout(&self) -> Option<f64> {
        self.timeout.seconds()
    }

    #[setter]
    fn set_timeout(&self, seconds: Option<f64>) -> PyResult<()> {
        self.timeout.set_seconds(seconds)
    }

    /// Creates `n_envs` envs of `document_json` on `server` (see `resolve`), with
    /// `autoreset` one of `"disabled"`, `"same_step"`, `"next_step"`.
    #[staticmethod]
    #[pyo3(signature = (
        server, document_json, n_envs, autoreset, options, timeout_s=None, token=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn create(
        py: Python<'_>,
        server: Option<&str>,
        document_json: String,
        n_envs: i64,
        autoreset: &str,
        options: CreateOptions,
        timeout_s: Option<f64>,
        token: Option<&str>,
    ) -> PyResult<Self> {
        let timeout = timeout(timeout_s)?;
        let mode = match autoreset {
            "disabled" => Autoreset::Disabled,
            "same_step" => Autoreset::SameStep,
            "next_step" => Autoreset::NextStep,
            other => {
                return Err(invalid(format!(
                    "autoreset: expected \"disabled\", \"same_step\" or \"next_step\", got {:?}",
                    other.chars().take(64).collect::<String>()
                )))
            }
        };
        let options = options
            .batch_options(document_json, n_envs)?
            .autoreset(mode);
        let batch: FleetBatch = match resolve(py, server, token)? {
            Target::One(client) => {
                wait(
                    py,
                    timeout,
                    || async move { client.create_batch(options).await },
                )?
                .into()
            }
            Target::Fleet(fleet) => {
                wait(
                    py,
                    timeout,
                    || async move { fleet.create_batch(options).await },
                )?
            }
        };
        let info = batch.info().clone();
        let placement = std::sync::Mutex::new(placement(&batch));
        Ok(BatchHandle {
            batch: tokio::sync::Mutex::new(batch),
            info,
            placement,
            timeout: Deadline::new(timeout),
            closed: Default::default(),
        })
    }

    /// What the server(s) said about the batch; `shards` lists `(server, batch_id, start,
    /// stop)`.
    #[getter]
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let placement = self
            .placement
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
            .clone();
        batch_info(py, &self.info, placement)
    }

    /// Resets every env, or those in `env_indices` (ascending); env `i` is reseeded with
    /// `seed + i` first when `seed` is given; from the document's keyframe named
    /// `keyframe` (`""`: its initial one, if any). Returns every env's observation.
    #[pyo3(signature = (seed_value=None, env_indices=None, keyframe=""))]
    fn reset<'py>(
        &self,
        py: Python<'py>,
        seed_value: Option<i128>,
        env_indices: Option<PyReadonlyArray1<'py, u32>>,
        keyframe: &str,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let seed = seed_value.map(|s| seed("seed", s)).transpose()?;
        let indices: Option<Vec<u32>> = env_indices.map(|a| a.as_array().to_vec());
        let observations = wait(py, self.timeout.get(), || async move {
            self.batch
                .lock()
                .await
                .reset_envs_to(seed, 0, indices.as_deref(), keyframe)
                .await
        })?;
        matrix(
            py,
            observations.into_observations(),
            self.info.observation_dim,
        )
    }

    /// Replaces heightfield `name`'s heights in envs `env_indices` (`None`: every env).
    #[pyo3(signature = (name, heights, env_indices=None))]
    fn set_heightfield<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        heights: Vec<f32>,
        env_indices: Option<PyReadonlyArray1<'py, u32>>,
    ) -> PyResult<()> {
        let indices: Vec<u32> = env_indices.map_or_else(Vec::new, |a| a.as_array().to_vec());
        wait(py, self.timeout.get(), || async move {
            self.batch
                .lock()
                .await
                .set_heightfield(&indices, name, &heights)
                .await
        })
    }

    /// The saved states of the envs in `env_indices` (ascending; `None`: every env), as
    /// `bytes`, in that order.
    #[pyo3(signature = (env_indices=None))]
    fn save_states<'py>(
        &self,
        py: Python<'py>,
        env_indices: Option<PyReadonlyArray1<'py, u32>>,
    ) -> PyResult<Vec<Bound<'py, PyBytes>>> {
        let indices: Vec<u32> = env_indices.map_or_else(Vec::new, |a| a.as_array().to_vec());
        let states = wait(py, self.timeout.get(), || async move {
            self.batch.lock().await.save_states(&indices).await
        })?;
        Ok(states
            .iter()
            .map(|s| PyBytes::new(py, s.as_bytes()))
            .collect())
    }

    /// Loads `states[k]` into env `env_indices[k]` (`None`: every env, one state each);
    /// returns every env's observation.
    #[pyo3(signature = (states, env_indices=None))]
    fn load_states<'py>(
        &self,
        py: Python<'py>,
        states: Vec<Vec<u8>>,
        env_indices: Option<PyReadonlyArray1<'py, u32>>,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let indices: Vec<u32> = env_indices.map_or_else(Vec::new, |a| a.as_array().to_vec());
        let states: Vec<EnvState> = states.into_iter().map(EnvState::from_bytes).collect();
        let observations = wait(py, self.timeout.get(), || async move {
            self.batch.lock().await.load_states(&indices, &states).await
        })?;
        matrix(
            py,
            observations.into_observations(),
            self.info.observation_dim,
        )
    }

    /// Steps every env with `actions` (`n_envs × action_dim`), moving their mocap bodies to
    /// `mocap_poses` (`n_envs × mocap bodies × 7` values, row-major) when given.
    #[pyo3(signature = (kind, actions, mocap_poses=None))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        kind: ActionKind,
        actions: PyReadonlyArray2<'py, f32>,
        mocap_poses: Option<PyReadonlyArray1<'py, f32>>,
    ) -> PyResult<StepTuple<'py>> {
        let action_type = gymfleet_client::ActionType::from(kind);
        let values: Vec<f32> = match actions.as_slice() {
            Ok(flat) => flat.to_vec(),
            Err(_) => actions.as_array().iter().copied().collect(),
        };
        let mocap = mocap_poses.map_or_else(Vec::new, |m| m.as_array().to_vec());
        let rows = wait(py, self.timeout.get(), || async move {
            self.batch
                .lock()
                .await
                .step_owned(action_type, values, mocap)
                .await
                .map(StepRows::new)
        })?;
        self.step_tuple(py, rows, self.info.n_envs)
    }

    /// Steps only the envs `env_indices` (ascending, distinct) with `actions` (one row per
    /// listed env, in that order); the result has their rows, while the finished envs and
    /// the termination reasons name batch indices.
    fn step_envs<'py>(
        &self,
        py: Python<'py>,
        kind: ActionKind,
        env_indices: PyReadonlyArray1<'py, u32>,
        actions: PyReadonlyArray2<'py, f32>,
    ) -> PyResult<StepTuple<'py>> {
        let action_type = gymfleet_client::ActionType::from(kind);
        let envs = env_indices.as_array().to_vec();
        let values: Vec<f32> = actions.as_array().iter().copied().collect();
        let n = envs.len();
        let rows = wait(py, self.timeout.get(), || async move {
            // One server's batch is called without holding the lock across the round
            // trip, so that several sends can be in flight (their envs are disjoint).
            let lone = self.batch.lock().await.lone().cloned();
            match lone {
                Some(batch) => batch.step_envs(action_type, &envs, &values).await,
                None => {
                    self.batch
                        .lock()
                        .await
                        .step_envs(action_type, &envs, &values)
                        .await
                }
            }
            .map(StepRows::new)
        })?;
        self.step_tuple(py, rows, n)
    }

    /// Checkpoints the batch every `steps` steps (0: never again), starting with one now,
    /// so that `recover` can rebuild the envs of a lost server (`FleetBatch::checkpoint_every`).
    fn checkpoint_every(&self, py: Python<'_>, steps: u64) -> PyResult<()> {
        wait(py, self.timeout.get(), || async move {
            self.batch.lock().await.checkpoint_every(steps).await
        })
    }

    /// Rebuilds the envs of every lost server from the last checkpoint, on `server`
    /// (`None`: the surviving servers in turn), replaying what was done since
    /// (`FleetBatch::recover`). Returns the step that found the loss, as `step_envs`
    /// returns it, with its env indices (empty: every env); `None` when no step found it
    /// or nothing was lost.
    #[pyo3(signature = (server=None, token=None))]
    fn recover<'py>(
        &self,
        py: Python<'py>,
        server: Option<&str>,
        token: Option<&str>,
    ) -> PyResult<Option<(Vec<u32>, StepTuple<'py>)>> {
        let replacement = match server {
            None => None,
            Some(addr) => match resolve(py, Some(addr), token)? {
                Target::One(client) => Some(client),
                Target::Fleet(_) => {
                    return Err(invalid(format!(
                        "server: expected one replacement server's address, got the list {addr:?}"
                    )))
                }
            },
        };
        let step = wait(py, self.timeout.get(), || async move {
            let mut batch = self.batch.lock().await;
            let step = batch.recover(replacement.as_ref()).await;
            *self
                .placement
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner()) = placement(&batch);
            let step = step?;
            Ok::<_, gymfleet_client::ClientError>(step.map(|s| {
                let envs = s.env_indices().to_vec();
                let n = s.n_envs();
                (envs, n, StepRows::new(s))
            }))
        })?;
        step.map(|(envs, n, rows)| Ok((envs, self.step_tuple(py, rows, n)?)))
            .transpose()
    }

    /// A `StreamBatch` stream of this batch for the asynchronous API's sends (up to
    /// `window` in flight), or `None` when the batch is sharded over a fleet (whose
    /// sends go one at a time).
    fn open_stream(&self, py: Python<'_>, window: usize) -> PyResult<Option<StepStream>> {
        let stream = wait(py, self.timeout.get(), || async move {
            match self.batch.lock().await.lone().cloned() {
                Some(batch) => batch.stream_with_window(window).await.map(Some),
                None => Ok(None),
            }
        })?;
        Ok(stream.map(|stream| StepStream::new(stream, &self.info)))
    }

    /// Every env's current observation, without stepping.
    fn observe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let observations = wait(py, self.timeout.get(), || async move {
            self.batch.lock().await.observe().await
        })?;
        matrix(
            py,
            observations.into_observations(),
            self.info.observation_dim,
        )
    }

    /// Env `env_index`'s domain-randomisation factors drawn at its last reset.
    fn randomization<'py>(
        &self,
        py: Python<'py>,
        env_index: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = wait(py, self.timeout.get(), || async move {
            self.batch.lock().await.randomization(env_index).await
        })?;
        crate::info::draws(py, d)
    }

    /// A picture of env `env_index` now: a `height × width × 3` uint8 array (RGB).
    #[pyo3(signature = (env_index, camera="iso", width=0, height=0, eye=None, target=None, fov_deg=0.0, orthographic=false))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        env_index: usize,
        camera: &str,
        width: u32,
        height: u32,
        eye: Option<[f64; 3]>,
        target: Option<[f64; 3]>,
        fov_deg: f32,
        orthographic: bool,
    ) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
        let camera = crate::render::camera(camera, eye, target, fov_deg, orthographic)?;
        let image = wait(py, self.timeout.get(), || async move {
            self.batch
                .lock()
                .await
                .render(env_index, &camera, width, height)
                .await
        })?;
        crate::render::to_array(py, &image)
    }

    /// Closes the batch on its server(s); `True` the first time, `False` afterwards.
    fn close(&self, py: Python<'_>) -> PyResult<bool> {
        use std::sync::atomic::Ordering;
        if self.closed.swap(true, Ordering::SeqCst) {
            return Ok(false);
        }
        wait(py, self.timeout.get(), || async move {
            self.batch.lock().await.close().await
        })?;
        Ok(true)
    }

    /// Whether `close` was called.
    #[getter]
    fn closed(&self) -> bool {
        self.closed.load(std::sync::atomic::Ordering::SeqCst)
    }
}
