//! [`CreateOptions`]: the creation options both handles take, checked at the boundary
//! (Python ints are unbounded; the wire's are not) and turned into the client's builders.

use std::time::Duration;

use gymfleet_client::{
    BatchOptions, ClientError, EnvOptions, PdGains, Randomization, ReachTask, Task, TaskKind,
    TrackTask, Units, UprightTask,
};
use pyo3::prelude::*;

use crate::errors::to_py_err;

/// The options of `CreateEnvRequest` (and so of `CreateBatchRequest`), as Python gave them.
/// Names are the proto's field names.
#[derive(Debug, Clone, Default, FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct CreateOptions {
    pub(crate) end_effector_ids: Vec<String>,
    pub(crate) dt: Option<f64>,
    pub(crate) substeps: Option<i64>,
    pub(crate) max_steps: Option<i64>,
    pub(crate) seed: Option<i128>,
    pub(crate) reset_noise: Option<f64>,
    pub(crate) kp: Option<Vec<f64>>,
    pub(crate) kd: Option<Vec<f64>>,
    pub(crate) task: Option<TaskFields>,
    pub(crate) randomize: Option<RandomizeFields>,
    /// A model of the server's library instead of the document.
    pub(crate) model: Option<String>,
    /// The document's mesh files as one archive (zip, tar or tar.gz bytes).
    pub(crate) assets: Option<Vec<u8>>,
    /// Where the document sits in `assets`, when it was given by its path inside them.
    pub(crate) document_path: Option<String>,
    /// `"document"` or `"si"` (checked by `gymfleet._common.check_units`).
    pub(crate) units: Option<String>,
}

/// Domain-randomisation ranges as `gymfleet._common.randomize_fields` checks them.
#[derive(Debug, Clone, Default, FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct RandomizeFields {
    mass_scale: Option<[f64; 2]>,
    friction_scale: Option<[f64; 2]>,
    damping_scale: Option<[f64; 2]>,
    gain_scale: Option<[f64; 2]>,
}

/// A task as `gymfleet._common.task_fields` flattens it: the kind, the action cost and
/// every kind's fields (the others' at their defaults).
#[derive(Debug, Clone, Default, FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct TaskFields {
    kind: String,
    action_cost: f32,
    end_effector: Option<String>,
    point: Option<[f64; 3]>,
    target: Option<[f64; 3]>,
    target_min: Option<[f64; 3]>,
    target_max: Option<[f64; 3]>,
    success_radius: f64,
    terminate_on_success: bool,
    targets: Option<Vec<f64>>,
    tolerance: f64,
    instance: Option<String>,
    axis: Option<[f64; 3]>,
    max_tilt_deg: f64,
    /// A terms task's JSON.
    json: Option<String>,
}

impl TaskFields {
    fn task(&self) -> PyResult<Task> {
        let kind = match self.kind.as_str() {
            "reach" => TaskKind::Reach(ReachTask {
                end_effector: self.end_effector.clone().unwrap_or_default(),
                point: self.point,
                target: self.target,
                target_box: self.target_min.zip(self.target_max),
                success_radius: self.success_radius,
                terminate_on_success: self.terminate_on_success,
            }),
            "track" => TaskKind::Track(TrackTask {
                targets: self.targets.clone().unwrap_or_default(),
                tolerance: self.tolerance,
                terminate_on_success: self.terminate_on_success,
            }),
            "upright" => TaskKind::Upright(UprightTask {
                instance: self.instance.clone().unwrap_or_default(),
                axis: self.axis,
                max_tilt_deg: self.max_tilt_deg,
            }),
            "terms" => TaskKind::Terms(self.json.clone().unwrap_or_default()),
            other => {
                return Err(invalid(format!(
                    "task: expected one of reach, track, upright, terms, got {:?}",
                    other.chars().take(64).collect::<String>()
                )))
            }
        };
        Ok(Task {
            kind,
            action_cost: self.action_cost,
        })
    }
}

/// An `INVALID_ARGUMENT` raised before anything is sent.
pub(crate) fn invalid(message: String) -> PyErr {
    to_py_err(ClientError::InvalidArgument {
        message,
        reason: gymfleet_client::ErrorReason::InvalidField,
    })
}

/// `value` as a `u32` count, or an error naming `field`.
fn count(field: &str, value: i64) -> PyResult<u32> {
    u32::try_from(value).map_err(|_| {
        invalid(format!(
            "{field}: expected an integer from 0 to {}, got {value}",
            u32::MAX
        ))
    })
}

/// A seed: any integer from 0 to 2^64 − 1.
pub(crate) fn seed(field: &str, value: i128) -> PyResult<u64> {
    u64::try_from(value).map_err(|_| {
        invalid(format!(
            "{field}: expected an integer from 0 to {}, got {value}",
            u64::MAX
        ))
    })
}

/// A per-call timeout in seconds: positive and finite, or `None` for none.
pub(crate) fn timeout(value: Option<f64>) -> PyResult<Option<Duration>> {
    match value {
        None => Ok(None),
        Some(s) if s.is_finite() && s > 0.0 && s < 1e9 => Ok(Some(Duration::from_secs_f64(s))),
        Some(s) => Err(invalid(format!(
            "timeout: expected a positive number of seconds (or None), got {s}"
        ))),
    }
}

impl CreateOptions {
    /// The client's builder for one env of `document_json`.
    pub(crate) fn env_options(&self, document_json: String) -> PyResult<EnvOptions> {
        let mut options = match &self.model {
            Some(name) => EnvOptions::from_model(name.clone()),
            None => EnvOptions::new(document_json),
        }
        .end_effectors(self.end_effector_ids.clone());
        if let Some(assets) = &self.assets {
            options = options.assets(assets.clone());
        }
        if let Some(path) = &self.document_path {
            options = options.document_path(path.clone());
        }
        if let Some(dt) = self.dt {
            options = options.dt(dt);
        }
        if let Some(substeps) = self.substeps {
            options = options.substeps(count("substeps", substeps)?);
        }
        if let Some(max_steps) = self.max_steps {
            options = options.max_steps(count("max_steps", max_steps)?);
        }
        if let Some(value) = self.seed {
            options = options.seed(seed("seed", value)?);
        }
        if let Some(noise) = self.reset_noise {
            options = options.reset_noise(noise);
        }
        if let Some(task) = &self.task {
            options = options.task(task.task()?);
        }
        match self.units.as_deref() {
            None | Some("document") => {}
            Some("si") => options = options.units(Units::Si),
            Some(other) => {
                return Err(invalid(format!(
                    "units: expected \"document\" or \"si\", got {:?}",
                    other.chars().take(64).collect::<String>()
                )))
            }
        }
        if let Some(r) = &self.randomize {
            options = options.randomize(Randomization {
                mass_scale: r.mass_scale,
                friction_scale: r.friction_scale,
                damping_scale: r.damping_scale,
                gain_scale: r.gain_scale,
            });
        }
        if self.kp.is_some() || self.kd.is_some() {
            options = options.pd_gains(PdGains {
                kp: self.kp.clone().unwrap_or_default(),
                kd: self.kd.clone().unwrap_or_default(),
            });
        }
        Ok(options)
    }

    /// The client's builder for a batch of `n_envs` envs of `document_json`.
    pub(crate) fn batch_options(
        &self,
        document_json: String,
        n_envs: i64,
    ) -> PyResult<BatchOptions> {
        let n = usize::try_from(n_envs)
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| invalid(format!("num_envs: expected at least 1, got {n_envs}")))?;
        Ok(BatchOptions::from_env(self.env_options(document_json)?, n))
    }
}
