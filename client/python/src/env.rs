//! [`EnvHandle`]: one server-side environment, for `gymfleet.GymfleetEnv`.

use std::sync::atomic::{AtomicBool, Ordering};

use gymfleet_client::{ActionType, Env, EnvState};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::info::env_info;
use crate::options::{seed, timeout, CreateOptions};
use crate::runtime::{wait, Deadline};
use crate::servers::{resolve, Target};

/// How a step's action values are read, as Python hands it to the extension: the
/// package maps its `action_type` string (`"torque"`, ...) to one of these once, when an
/// env or batch is made, so no string crosses the boundary per step.
#[pyclass(module = "gymfleet._core", eq, eq_int, frozen, from_py_object)]
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum ActionKind {
    Torque,
    Position,
    Velocity,
}

impl From<ActionKind> for ActionType {
    fn from(kind: ActionKind) -> Self {
        match kind {
            ActionKind::Torque => ActionType::Torque,
            ActionKind::Position => ActionType::Position,
            ActionKind::Velocity => ActionType::Velocity,
        }
    }
}

/// One env on a server. Its calls block (with the GIL released) until the reply.
#[pyclass(module = "gymfleet._core", frozen)]
pub(crate) struct EnvHandle {
    env: Env,
    /// The per-call deadline; settable from Python.
    timeout: Deadline,
    closed: AtomicBool,
}

#[pymethods]
impl EnvHandle {
    /// The per-call timeout in seconds (`None`: none).
    #[getter]
    fn get_timeout(&self) -> Option<f64> {
        self.timeout.seconds()
    }

    #[setter]
    fn set_timeout(&self, seconds: Option<f64>) -> PyResult<()> {
        self.timeout.set_seconds(seconds)
    }

    /// Creates an env of `document_json` on `server` (see `resolve`).
    #[staticmethod]
    #[pyo3(signature = (server, document_json, options, timeout_s=None, token=None))]
    fn create(
        py: Python<'_>,
        server: Option<&str>,
        document_json: String,
        options: CreateOptions,
        timeout_s: Option<f64>,
        token: Option<&str>,
    ) -> PyResult<Self> {
        let timeout = timeout(timeout_s)?;
        let options = options.env_options(document_json)?;
        let env = match resolve(py, server, token)? {
            Target::One(client) => {
                wait(
                    py,
                    timeout,
                    || async move { client.create_env(options).await },
                )?
            }
            Target::Fleet(fleet) => {
                wait(
                    py,
                    timeout,
                    || async move { fleet.create_env(options).await },
                )?
            }
        };
        Ok(EnvHandle {
            env,
            timeout: Deadline::new(timeout),
            closed: AtomicBool::new(false),
        })
    }

    /// What the server said about the env.
    #[getter]
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        env_info(py, self.env.info(), self.env.server())
    }

    /// Resets it (reseeded first when `seed` is given), from the document's keyframe
    /// named `keyframe` (`""`: its initial one, if any); returns the observation.
    #[pyo3(signature = (seed_value=None, keyframe=""))]
    fn reset<'py>(
        &self,
        py: Python<'py>,
        seed_value: Option<i128>,
        keyframe: &str,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let seed = seed_value.map(|s| seed("seed", s)).transpose()?;
        let env = &self.env;
        let observation = wait(py, self.timeout.get(), || async move {
            env.reset_to(seed, keyframe).await
        })?;
        Ok(PyArray1::from_vec(
            py,
            observation.to_flat(&self.env.info().observation_layout),
        ))
    }

    /// One step: `(observation, reward, terminated, truncated, termination_reason,
    /// episode_step, terms)` (`terms`: a terms task's values, empty without one).
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (kind, action, mocap_poses=None))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        kind: ActionKind,
        action: PyReadonlyArray1<'py, f32>,
        mocap_poses: Option<PyReadonlyArray1<'py, f32>>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f32>>,
        f32,
        bool,
        bool,
        Option<String>,
        u32,
        Bound<'py, PyArray1<f32>>,
    )> {
        let action_type = ActionType::from(kind);
        let values = action.as_array().to_vec();
        let mocap = mocap_poses.map_or_else(Vec::new, |m| m.as_array().to_vec());
        let env = &self.env;
        let r = wait(py, self.timeout.get(), || async move {
            env.step_owned(action_type, values, mocap).await
        })?;
        Ok((
            PyArray1::from_vec(
                py,
                r.observation.to_flat(&self.env.info().observation_layout),
            ),
            r.reward,
            r.terminated,
            r.truncated,
            r.termination_reason,
            r.episode_step,
            PyArray1::from_vec(py, r.terms),
        ))
    }

    /// Sets where mocap body `body` is to be at the end of the next step: `pose` is
    /// `[x, y, z, qw, qx, qy, qz]` in the env's units.
    fn set_mocap_pose(&self, py: Python<'_>, body: &str, pose: Vec<f32>) -> PyResult<()> {
        let pose: [f32; 7] = pose.try_into().map_err(|p: Vec<f32>| {
            crate::options::invalid(format!(
                "pose: expected 7 values (x, y, z, qw, qx, qy, qz), got {}",
                p.len()
            ))
        })?;
        let env = &self.env;
        wait(py, self.timeout.get(), || async move {
            env.set_mocap_pose(body, pose).await
        })
    }

    /// Replaces heightfield `name`'s heights (rows × columns values in [0, 1], row 0 at −y).
    fn set_heightfield(&self, py: Python<'_>, name: &str, heights: Vec<f32>) -> PyResult<()> {
        let env = &self.env;
        wait(py, self.timeout.get(), || async move {
            env.set_heightfield(name, &heights).await
        })
    }

    /// The current observation, without stepping.
    fn observe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let env = &self.env;
        let observation = wait(
            py,
            self.timeout.get(),
            || async move { env.observe().await },
        )?;
        Ok(PyArray1::from_vec(
            py,
            observation.to_flat(&self.env.info().observation_layout),
        ))
    }

    /// The env's saved state, as `bytes` (the env is re-seated from it).
    fn save_state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let env = &self.env;
        let state = wait(
            py,
            self.timeout.get(),
            || async move { env.save_state().await },
        )?;
        Ok(PyBytes::new(py, state.as_bytes()))
    }

    /// Loads a saved state; the observation there.
    fn load_state<'py>(
        &self,
        py: Python<'py>,
        state: Vec<u8>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let env = &self.env;
        let state = EnvState::from_bytes(state);
        let observation = wait(py, self.timeout.get(), || async move {
            env.load_state(&state).await
        })?;
        Ok(PyArray1::from_vec(
            py,
            observation.to_flat(&self.env.info().observation_layout),
        ))
    }

    /// Sets the joint state from values (MuJoCo's `set_state`): one position and velocity
    /// per DOF, and a floating base's 13 floats (none without one). Returns the
    /// observation there and the server's warnings.
    fn set_joint_state<'py>(
        &self,
        py: Python<'py>,
        positions: Vec<f64>,
        velocities: Vec<f64>,
        base: Vec<f64>,
    ) -> PyResult<(Bound<'py, PyArray1<f32>>, Vec<String>)> {
        let env = &self.env;
        let (observation, warnings) = wait(py, self.timeout.get(), || async move {
            env.set_joint_state(&positions, &velocities, &base).await
        })?;
        let flat = observation.to_flat(&self.env.info().observation_layout);
        Ok((PyArray1::from_vec(py, flat), warnings))
    }

    /// Every instance's and site's state now, as a dict of names and float64 arrays
    /// (`gymfleet_client::Bodies`' fields).
    fn bodies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let env = &self.env;
        let bodies = wait(py, self.timeout.get(), || async move { env.bodies().await })?;
        crate::info::bodies(py, bodies)
    }

    /// The domain-randomisation factors drawn at the last reset.
    fn randomization<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let env = &self.env;
        let d = wait(py, self.timeout.get(), || async move {
            env.randomization().await
        })?;
        crate::info::draws(py, d)
    }

    /// A picture of the env as it is now: a `height × width × 3` uint8 array (RGB).
    #[pyo3(signature = (camera="iso", width=0, height=0, eye=None, target=None, fov_deg=0.0, orthographic=false))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        camera: &str,
        width: u32,
        height: u32,
        eye: Option<[f64; 3]>,
        target: Option<[f64; 3]>,
        fov_deg: f32,
        orthographic: bool,
    ) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
        let camera = crate::render::camera(camera, eye, target, fov_deg, orthographic)?;
        let env = &self.env;
        let image = wait(py, self.timeout.get(), || async move {
            env.render(&camera, width, height).await
        })?;
        crate::render::to_array(py, &image)
    }

    /// Closes the env on its server; `True` the first time, `False` afterwards.
    fn close(&self, py: Python<'_>) -> PyResult<bool> {
        if self.closed.swap(true, Ordering::SeqCst) {
            return Ok(false);
        }
        let env = &self.env;
        wait(py, self.timeout.get(), || async move { env.close().await })?;
        Ok(true)
    }

    /// Whether `close` was called.
    #[getter]
    fn closed(&self) -> bool {
        self.closed.load(Ordering::SeqCst)
    }
}
