//! A batch step's rows as the binding hands them to Python: [`StepRows`] (taken out of the
//! reply before the GIL is taken back) and [`step_tuple`] (numpy arrays, without
//! per-element Python objects), for `BatchHandle` and `StepStream` alike.

use gymfleet_client::BatchStep;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One batch step's results, taken out of the reply before the GIL is taken back.
pub(crate) struct StepRows {
    observations: Vec<f32>,
    rewards: Vec<f32>,
    terms: Vec<f32>,
    terminated: Vec<bool>,
    truncated: Vec<bool>,
    final_env_indices: Vec<u32>,
    final_observations: Vec<f32>,
    termination_reasons: Vec<(u32, String)>,
}

impl StepRows {
    pub(crate) fn new(step: BatchStep) -> Self {
        let final_env_indices = step.final_env_indices().to_vec();
        let final_observations = final_env_indices
            .iter()
            .flat_map(|&i| {
                step.final_observation(i as usize)
                    .unwrap_or_default()
                    .iter()
                    .copied()
            })
            .collect();
        let termination_reasons = step
            .termination_reasons()
            .map(|(i, r)| (i, r.to_string()))
            .collect();
        StepRows {
            rewards: step.rewards().to_vec(),
            terms: step.terms().to_vec(),
            terminated: step.terminated().to_vec(),
            truncated: step.truncated().to_vec(),
            final_env_indices,
            final_observations,
            termination_reasons,
            observations: step.into_observations(),
        }
    }
}

/// `rows × dim` floats as a 2-D array that owns them.
pub(crate) fn matrix(
    py: Python<'_>,
    values: Vec<f32>,
    dim: usize,
) -> PyResult<Bound<'_, PyArray2<f32>>> {
    let rows = values.len().checked_div(dim).unwrap_or(0);
    PyArray1::from_vec(py, values).reshape([rows, dim])
}

/// What `step` returns: observations, rewards, terminated, truncated, the envs reset in
/// the step (same-step autoreset) with their final observations, the termination
/// reasons by env, and a terms task's values (`n_envs × len(term_names)`).
pub(crate) type StepTuple<'py> = (
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyArray1<f32>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyDict>,
    Bound<'py, PyArray2<f32>>,
);

/// A step's rows (`n` of them, `dim` observation floats and `k` term values each) as
/// numpy arrays and a dict of termination reasons.
pub(crate) fn step_tuple(
    py: Python<'_>,
    rows: StepRows,
    n: usize,
    dim: usize,
    k: usize,
) -> PyResult<StepTuple<'_>> {
    let reasons = PyDict::new(py);
    for (env, reason) in rows.termination_reasons {
        reasons.set_item(env, reason)?;
    }
    Ok((
        matrix(py, rows.observations, dim)?,
        PyArray1::from_vec(py, rows.rewards),
        PyArray1::from_vec(py, rows.terminated),
        PyArray1::from_vec(py, rows.truncated),
        PyArray1::from_vec(py, rows.final_env_indices),
        matrix(py, rows.final_observations, dim)?,
        reasons,
        PyArray1::from_vec(py, rows.terms).reshape([n, k])?,
    ))
}
