//! The `gymfleet.v1.Simulator` service: decodes each request at the edge (`TryFrom`),
//! calls the [`Simulation`], and encodes the answer. Errors become statuses only
//! through `From<ServerError> for Status`.

use std::sync::Arc;
use std::time::Instant;

use gymfleet_proto::v1 as pb;
use pb::simulator_server::Simulator;
use tokio::sync::{mpsc, watch};
use tokio_stream::wrappers::ReceiverStream;
use tonic::{Request, Response, Status, Streaming};

use crate::auth::tenant_of;
use crate::convert;
use crate::domain::{
    BatchRequest, BatchStep, Created, DrawsOf, EnvRequest, EnvStep, ForkRequest, RenderOf,
};
use crate::error::{Result, ServerError};
use crate::simulation::Simulation;
use crate::tenant::Tenant;

/// Results buffered per StreamBatch stream before the server waits for the client.
const STREAM_BUFFER: usize = 8;

/// The gRPC face of a [`Simulation`].
pub(crate) struct SimulatorService {
    sim: Arc<Simulation>,
    shutdown: watch::Receiver<bool>,
}

impl SimulatorService {
    pub(crate) fn new(sim: Arc<Simulation>, shutdown: watch::Receiver<bool>) -> Self {
        SimulatorService { sim, shutdown }
    }
}

impl SimulatorService {
    /// The answer to a call: records its duration and status code, counts a refusal,
    /// and turns the error into its status.
    fn finish<T>(
        &self,
        method: &'static str,
        start: Instant,
        result: Result<T>,
    ) -> Result<Response<T>, Status> {
        let metrics = self.sim.metrics();
        match result {
            Ok(value) => {
                metrics.rpc(method, tonic::Code::Ok, start.elapsed());
                Ok(Response::new(value))
            }
            Err(err) => {
                metrics.rejected(&err);
                metrics.rpc(method, err.code(), start.elapsed());
                Err(Status::from(err))
            }
        }
    }
}

fn env_info(created: Created) -> pb::EnvInfo {
    convert::env_info(created.id, &created.spec, &created.links)
}

fn batch_info(created: Created) -> pb::BatchInfo {
    let (n_envs, autoreset) = created.batch.unwrap_or_default();
    convert::batch_info(created.id, n_envs, autoreset, &created.spec, &created.links)
}

/// Steps one `StepBatch` or `StreamBatch` request.
async fn stream_step(
    sim: &Simulation,
    tenant: &Tenant,
    request: pb::StepBatchRequest,
) -> Result<pb::BatchStepResult> {
    let stepped = sim
        .step_batch(tenant, BatchStep::try_from(request)?)
        .await?;
    Ok(convert::batch_step_result(stepped))
}

#[tonic::async_trait]
impl Simulator for SimulatorService {
    async fn create_env(
        &self,
        request: Request<pb::CreateEnvRequest>,
    ) -> Result<Response<pb::EnvInfo>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let result = async {
            let request = EnvRequest::try_from(request.into_inner())?;
            self.sim.create_env(&tenant, request).await.map(env_info)
        };
        self.finish("CreateEnv", start, result.await)
    }

    async fn reset(
        &self,
        request: Request<pb::ResetRequest>,
    ) -> Result<Response<pb::Observation>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        let result = self.sim.reset_env(&tenant, &r.env_id, r.seed).await;
        self.finish(
            "Reset",
            start,
            result.map(|(obs, split)| convert::observation(&obs, split)),
        )
    }

    async fn step(
        &self,
        request: Request<pb::StepRequest>,
    ) -> Result<Response<pb::StepResult>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let result = async {
            let step = EnvStep::try_from(request.into_inner())?;
            let outcome = self.sim.step_env(&tenant, step).await?;
            let flags = outcome.flags;
            Ok(pb::StepResult {
                observation: Some(convert::observation(&outcome.observation, outcome.split)),
                reward: flags.reward,
                terminated: flags.terminated,
                truncated: flags.truncated,
                done: flags.done(),
                termination_reason: flags.termination.map(|t| t.as_str().to_string()),
                episode_step: outcome.episode_step,
                terms: outcome.terms,
            })
        };
        self.finish("Step", start, result.await)
    }

    async fn observe(
        &self,
        request: Request<pb::EnvRef>,
    ) -> Result<Response<pb::Observation>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        let result = self.sim.observe_env(&tenant, &r.env_id).await;
        self.finish(
            "Observe",
            start,
            result.map(|(obs, split)| convert::observation(&obs, split)),
        )
    }

    async fn close(
        &self,
        request: Request<pb::EnvRef>,
    ) -> Result<Response<pb::CloseEnvResponse>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        self.finish(
            "Close",
            start,
            self.sim
                .close_env(&tenant, &r.env_id)
                .await
                .map(|()| pb::CloseEnvResponse {}),
        )
    }

    async fn create_batch(
        &self,
        request: Request<pb::CreateBatchRequest>,
    ) -> Result<Response<pb::BatchInfo>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let result = async {
            let request = BatchRequest::try_from(request.into_inner())?;
            self.sim
                .create_batch(&tenant, request)
                .await
                .map(batch_info)
        };
        self.finish("CreateBatch", start, result.await)
    }

    async fn reset_batch(
        &self,
        request: Request<pb::ResetBatchRequest>,
    ) -> Result<Response<pb::BatchObservation>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        self.finish(
            "ResetBatch",
            start,
            self.sim
                .reset_batch(&tenant, &r.batch_id, r.seed, r.seed_offset, r.env_indices)
                .await
                .map(convert::batch_observation),
        )
    }

    async fn step_batch(
        &self,
        request: Request<pb::StepBatchRequest>,
    ) -> Result<Response<pb::BatchStepResult>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        self.finish(
            "StepBatch",
            start,
            stream_step(&self.sim, &tenant, request.into_inner()).await,
        )
    }

    async fn get_randomization(
        &self,
        request: Request<pb::RandomizationRequest>,
    ) -> Result<Response<pb::RandomizationDraws>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let result = async {
            let target = DrawsOf::try_from(request.into_inner())?;
            self.sim.randomization(&tenant, target).await
        };
        self.finish(
            "GetRandomization",
            start,
            result.await.map(convert::randomization_draws),
        )
    }

    async fn get_scene(&self, request: Request<pb::EnvRef>) -> Result<Response<pb::Scene>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let env_id = request.into_inner().env_id;
        let result = self.sim.scene(&tenant, &env_id).await;
        self.finish("GetScene", start, result.map(convert::scene))
    }

    async fn save_state(
        &self,
        request: Request<pb::EnvRef>,
    ) -> Result<Response<pb::EnvState>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let env_id = request.into_inner().env_id;
        let result = self.sim.save_state(&tenant, &env_id).await;
        self.finish(
            "SaveState",
            start,
            result.map(|state| pb::EnvState { state }),
        )
    }

    async fn load_state(
        &self,
        request: Request<pb::LoadStateRequest>,
    ) -> Result<Response<pb::Observation>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        let result = self.sim.load_state(&tenant, &r.env_id, r.state).await;
        self.finish(
            "LoadState",
            start,
            result.map(|(obs, split)| convert::observation(&obs, split)),
        )
    }

    async fn save_batch_state(
        &self,
        request: Request<pb::BatchStateRequest>,
    ) -> Result<Response<pb::BatchState>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        let result = self
            .sim
            .save_batch_state(&tenant, &r.batch_id, r.env_indices)
            .await;
        self.finish(
            "SaveBatchState",
            start,
            result.map(|states| pb::BatchState { states }),
        )
    }

    async fn load_batch_state(
        &self,
        request: Request<pb::LoadBatchStateRequest>,
    ) -> Result<Response<pb::BatchObservation>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        let result = self
            .sim
            .load_batch_state(&tenant, &r.batch_id, r.env_indices, r.states)
            .await;
        self.finish(
            "LoadBatchState",
            start,
            result.map(convert::batch_observation),
        )
    }

    async fn fork(
        &self,
        request: Request<pb::ForkRequest>,
    ) -> Result<Response<pb::BatchInfo>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let result = async {
            let request = ForkRequest::try_from(request.into_inner())?;
            self.sim.fork(&tenant, request).await.map(batch_info)
        };
        self.finish("Fork", start, result.await)
    }

    async fn convert_document(
        &self,
        request: Request<pb::ConvertDocumentRequest>,
    ) -> Result<Response<pb::ConvertedDocument>, Status> {
        let start = Instant::now();
        let _tenant = tenant_of(&request)?;
        let result = async {
            let r = request.into_inner();
            let format = convert::document_format(r.format)?;
            let (document_json, warnings, format) =
                self.sim.convert(r.document_json, format, r.assets).await?;
            Ok(pb::ConvertedDocument {
                document_json,
                warnings,
                format: convert::format_to_proto(format) as i32,
            })
        };
        self.finish("ConvertDocument", start, result.await)
    }

    async fn list_models(
        &self,
        request: Request<pb::ListModelsRequest>,
    ) -> Result<Response<pb::ModelList>, Status> {
        let start = Instant::now();
        let _tenant = tenant_of(&request)?;
        let models = self
            .sim
            .models()
            .into_iter()
            .map(|(name, format, dofs, action_dim)| pb::ModelInfo {
                name,
                format: convert::format_to_proto(format) as i32,
                dofs: u32::try_from(dofs).unwrap_or(u32::MAX),
                action_dim: u32::try_from(action_dim).unwrap_or(u32::MAX),
            })
            .collect();
        self.finish("ListModels", start, Ok(pb::ModelList { models }))
    }

    async fn render(
        &self,
        request: Request<pb::RenderRequest>,
    ) -> Result<Response<pb::Image>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let result = async {
            let target = RenderOf::try_from(request.into_inner())?;
            self.sim.render(&tenant, target).await
        };
        self.finish("Render", start, result.await.map(convert::image))
    }

    async fn observe_batch(
        &self,
        request: Request<pb::BatchRef>,
    ) -> Result<Response<pb::BatchObservation>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        self.finish(
            "ObserveBatch",
            start,
            self.sim
                .observe_batch(&tenant, &r.batch_id)
                .await
                .map(convert::batch_observation),
        )
    }

    async fn close_batch(
        &self,
        request: Request<pb::BatchRef>,
    ) -> Result<Response<pb::CloseBatchResponse>, Status> {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let r = request.into_inner();
        self.finish(
            "CloseBatch",
            start,
            self.sim
                .close_batch(&tenant, &r.batch_id)
                .await
                .map(|()| pb::CloseBatchResponse {}),
        )
    }

    type StreamBatchStream = ReceiverStream<Result<pb::BatchStepResult, Status>>;

    async fn stream_batch(
        &self,
        request: Request<Streaming<pb::StepBatchRequest>>,
    ) -> Result<Response<Self::StreamBatchStream>, Status> {
        let tenant = tenant_of(&request)?;
        let mut incoming = request.into_inner();
        let (tx, rx) = mpsc::channel(STREAM_BUFFER);
        let sim = Arc::clone(&self.sim);
        let mut shutdown = self.shutdown.clone();
        tokio::spawn(async move {
            loop {
                // Requests are taken one at a time, so results leave in request order.
                let stopping = async {
                    // An error means the server is gone: stop as well.
                    let _ = shutdown.wait_for(|stop| *stop).await;
                };
                let next = tokio::select! {
                    biased;
                    () = stopping => None,
                    next = incoming.message() => Some(next),
                };
                let request = match next {
                    None => {
                        let _ = tx.send(Err(ServerError::ShuttingDown.into())).await;
                        return;
                    }
                    Some(Ok(Some(request))) => request,
                    // The client finished its side: end ours.
                    Some(Ok(None)) => return,
                    Some(Err(status)) => {
                        tracing::debug!(%status, "StreamBatch: client stream failed");
                        return;
                    }
                };
                let start = Instant::now();
                let result = stream_step(&sim, &tenant, request).await;
                let failed = result.is_err();
                let metrics = sim.metrics();
                let code = result
                    .as_ref()
                    .map_or_else(ServerError::code, |_| tonic::Code::Ok);
                if let Err(err) = &result {
                    metrics.rejected(err);
                }
                metrics.rpc("StreamBatch", code, start.elapsed());
                if tx.send(result.map_err(Status::from)).await.is_err() || failed {
                    // The client went away, or an error ended the stream.
                    return;
                }
            }
        });
        Ok(Response::new(ReceiverStream::new(rx)))
    }

    async fn get_server_info(
        &self,
        request: Request<pb::GetServerInfoRequest>,
    ) -> Result<Response<pb::ServerInfo>, Status> {
        let tenant = tenant_of(&request)?;
        Ok(Response::new(convert::server_info(
            &self.sim.status(&tenant),
        )))
    }
}
