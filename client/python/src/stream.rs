//! [`StepStream`]: a batch's `StreamBatch` stream for the asynchronous API
//! (`gymfleet/pipeline.py`): subset steps sent one after another without a thread each,
//! their results taken in the order they were sent.

use gymfleet_client::{BatchInfo, BatchStream, ClientError};
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::env::ActionKind;
use crate::rows::{step_tuple, StepRows, StepTuple};
use crate::runtime::wait;

/// One open stream of one server's batch. Its calls block with the GIL released; an error
/// ends the stream (the server answers nothing after it), and the caller opens another.
#[pyclass(module = "gymfleet._core", frozen)]
pub(crate) struct StepStream {
    stream: tokio::sync::Mutex<BatchStream>,
    observation_dim: usize,
    terms: usize,
}

impl StepStream {
    pub(crate) fn new(stream: BatchStream, info: &BatchInfo) -> Self {
        StepStream {
            stream: tokio::sync::Mutex::new(stream),
            observation_dim: info.observation_dim,
            terms: info.term_names.len(),
        }
    }
}

#[pymethods]
impl StepStream {
    /// Sends a step of the envs `env_indices` (ascending, distinct) with one action row
    /// each. Returns once it is on its way (with the window full, after taking the oldest
    /// result off the wire, kept for `next`).
    fn send_envs(
        &self,
        py: Python<'_>,
        kind: ActionKind,
        env_indices: PyReadonlyArray1<'_, u32>,
        actions: PyReadonlyArray2<'_, f32>,
    ) -> PyResult<()> {
        let action_type = gymfleet_client::ActionType::from(kind);
        let envs = env_indices.as_array().to_vec();
        let values: Vec<f32> = actions.as_array().iter().copied().collect();
        wait(py, None, || async move {
            self.stream
                .lock()
                .await
                .send_envs(action_type, &envs, &values)
                .await
        })
    }

    /// The oldest sent step's rows, as `BatchHandle.step_envs` returns them; with
    /// `timeout` (seconds), `DeadlineExceeded` when none came by then (the step stays
    /// pending: taking a result off the wire is not interrupted part-way).
    #[pyo3(signature = (timeout=None))]
    fn next<'py>(&self, py: Python<'py>, timeout: Option<f64>) -> PyResult<StepTuple<'py>> {
        let limit = crate::options::timeout(timeout)?;
        let step = wait(py, limit, || async move {
            match self.stream.lock().await.next().await {
                Some(step) => step,
                None => Err(ClientError::FailedPrecondition {
                    message: "next: no step is pending on the stream".into(),
                    reason: gymfleet_client::ErrorReason::Unspecified,
                }),
            }
        })?;
        let n = step.env_indices().len();
        step_tuple(py, StepRows::new(step), n, self.observation_dim, self.terms)
    }
}
