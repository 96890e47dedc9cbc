//! [`BatchStream`]: batch steps pipelined over one `StreamBatch` stream.

use std::collections::VecDeque;

use gymfleet_proto::v1 as pb;
use tokio::sync::mpsc;
use tokio_stream::wrappers::ReceiverStream;
use tonic::Streaming;

use crate::batch::{Batch, BatchStep};
use crate::client::Client;
use crate::error::{ClientError, Result};
use crate::types::ActionType;

/// Requests a [`BatchStream`] keeps in flight by default.
pub const DEFAULT_STREAM_WINDOW: usize = 4;

impl Batch {
    /// Opens a `StreamBatch` stream that keeps up to [`DEFAULT_STREAM_WINDOW`] steps in
    /// flight.
    pub async fn stream(&self) -> Result<BatchStream> {
        self.stream_with_window(DEFAULT_STREAM_WINDOW).await
    }

    /// Opens a `StreamBatch` stream that keeps up to `window` steps (at least 1) in flight.
    pub async fn stream_with_window(&self, window: usize) -> Result<BatchStream> {
        BatchStream::open(self.client().clone(), self.clone(), window).await
    }
}

/// Batch steps over one long-lived bidirectional stream. Requests are answered in the
/// order they were sent; up to `window` of them are in flight at once, so the network
/// round trip overlaps with the server's stepping.
///
/// [`BatchStream::send`] queues a step and returns as soon as it is sent (if `window`
/// steps are already in flight, it first receives the oldest result and keeps it for
/// [`BatchStream::next`]). [`BatchStream::next`] returns the oldest unreturned result.
/// [`BatchStream::step`] is `send` then `next`. An error ends the stream.
///
/// ```no_run
/// use gymfleet_client::{ActionType, Batch};
///
/// # async fn demo(batch: Batch) -> gymfleet_client::Result<()> {
/// let actions = vec![0.0_f32; batch.info().n_envs * batch.info().action_dim];
/// let mut stream = batch.stream_with_window(8).await?;
/// for _ in 0..100 {
///     stream.send(ActionType::Torque, &actions).await?;
/// }
/// while let Some(step) = stream.next().await {
///     let step = step?;
///     println!("step {}: env 0 at {:?}", step.step_index(), step.obs(0));
/// }
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct BatchStream {
    batch: Batch,
    requests: Option<mpsc::Sender<pb::StepBatchRequest>>,
    responses: Streaming<pb::BatchStepResult>,
    window: usize,
    /// Sent and not yet received.
    in_flight: usize,
    /// Received (to make room in the window) and not yet returned by `next`.
    received: VecDeque<Result<BatchStep>>,
    /// The stream failed; nothing more will come.
    failed: bool,
    /// The server ended the request side (a send found it closed).
    ended: bool,
}

impl BatchStream {
    pub(crate) async fn open(client: Client, batch: Batch, window: usize) -> Result<Self> {
        let window = window.max(1);
        let (tx, rx) = mpsc::channel(window);
        let responses = client
            .rpc()
            .stream_batch(ReceiverStream::new(rx))
            .await?
            .into_inner();
        Ok(BatchStream {
            batch,
            requests: Some(tx),
            responses,
            window,
            in_flight: 0,
            received: VecDeque::new(),
            failed: false,
            ended: false,
        })
    }

    /// The most steps in flight at once.
    pub fn window(&self) -> usize {
        self.window
    }

    /// Steps sent whose results have not been returned by [`BatchStream::next`] yet.
    pub fn pending(&self) -> usize {
        self.in_flight + self.received.len()
    }

    /// Sends one batch step (`n_envs × action_dim` values, row-major).
    pub async fn send(&mut self, action_type: ActionType, actions: &[f32]) -> Result<()> {
        self.send_with_mocap(action_type, actions, &[]).await
    }

    /// [`BatchStream::send`] with every env's mocap targets, as
    /// [`crate::Batch::step_with_mocap`] takes them (empty: the targets stay).
    pub async fn send_with_mocap(
        &mut self,
        action_type: ActionType,
        actions: &[f32],
        mocap_poses: &[f32],
    ) -> Result<()> {
        let request = self.batch.step_request(
            action_type,
            actions.to_vec(),
            mocap_poses.to_vec(),
            Vec::new(),
        );
        self.send_request(request).await
    }

    /// Sends a step of the envs `env_indices` only (as [`crate::Batch::step_envs`]: one
    /// action row per listed env, in that order); its result has their rows.
    pub async fn send_envs(
        &mut self,
        action_type: ActionType,
        env_indices: &[u32],
        actions: &[f32],
    ) -> Result<()> {
        let request = self.batch.step_request(
            action_type,
            actions.to_vec(),
            Vec::new(),
            env_indices.to_vec(),
        );
        self.send_request(request).await
    }

    async fn send_request(&mut self, request: pb::StepBatchRequest) -> Result<()> {
        if self.in_flight >= self.window {
            let result = self.receive().await;
            self.received.push_back(result);
        }
        if self.failed {
            return Err(ClientError::Unavailable {
                reason: crate::ErrorReason::Unspecified,
                message: "the batch stream has ended after an error; open a new one".into(),
                code: tonic::Code::Unavailable,
            });
        }
        let ended = || ClientError::Unavailable {
            reason: crate::ErrorReason::Unspecified,
            message: "the batch stream has ended (a step sent before failed, or the server \
                      closed it): take the pending results with next(), then open a new \
                      stream; this step was not sent"
                .into(),
            code: tonic::Code::Unavailable,
        };
        if self.ended {
            return Err(ended());
        }
        let Some(requests) = &self.requests else {
            return Err(ClientError::protocol("send after the stream was finished"));
        };
        if requests.send(request).await.is_err() {
            // The server ended the stream (a step sent before failed, or it is going
            // away): its answers to the steps sent before, the error among them, are
            // still to be taken with `next`; nothing is read off the wire here.
            self.ended = true;
            return Err(ended());
        }
        self.in_flight += 1;
        Ok(())
    }

    /// The oldest result not yet returned, or `None` when every sent step has been
    /// returned.
    pub async fn next(&mut self) -> Option<Result<BatchStep>> {
        if let Some(result) = self.received.pop_front() {
            return Some(result);
        }
        if self.in_flight == 0 {
            return None;
        }
        Some(self.receive().await)
    }

    /// Sends one step and returns the oldest pending result: with nothing else in flight,
    /// this step's.
    pub async fn step(&mut self, action_type: ActionType, actions: &[f32]) -> Result<BatchStep> {
        self.send(action_type, actions).await?;
        match self.next().await {
            Some(result) => result,
            None => Err(ClientError::protocol("no result for a sent step")),
        }
    }

    /// Ends the request side and returns the results still pending, in order. The first
    /// error, if any, is returned instead.
    pub async fn finish(mut self) -> Result<Vec<BatchStep>> {
        self.requests = None;
        let mut rest = Vec::with_capacity(self.pending());
        while let Some(result) = self.next().await {
            rest.push(result?);
        }
        Ok(rest)
    }

    /// Receives the next result off the wire.
    async fn receive(&mut self) -> Result<BatchStep> {
        if self.failed {
            self.in_flight = 0;
            return Err(ClientError::Unavailable {
                reason: crate::ErrorReason::Unspecified,
                message: "the batch stream has ended after an error; open a new one".into(),
                code: tonic::Code::Unavailable,
            });
        }
        let message = self.responses.message().await;
        let outcome = match message {
            Ok(Some(result)) => {
                self.in_flight -= 1;
                return BatchStep::new(result, self.batch.info());
            }
            Ok(None) => ClientError::protocol(format!(
                "the server ended the stream with {} steps unanswered",
                self.in_flight
            )),
            Err(status) => ClientError::from(status),
        };
        self.failed = true;
        self.in_flight = 0;
        Err(outcome)
    }
}
