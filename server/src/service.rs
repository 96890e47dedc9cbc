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
use crate::simulation::{JointState, Simulation};
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
    /// One unary call, the same way for every RPC: the caller's tenant (set by the
    /// authenticator), then `call` on the request's message, then [`Self::finish`]. (Not
    /// a tower layer: the refusal counter needs the typed [`ServerError`], which a layer
    /// would see only as a status.) `StreamBatch` records each of its steps the same way.
    async fn unary<Req, T, F, Fut>(
        &self,
        method: &'static str,
        request: Request<Req>,
        call: F,
    ) -> Result<Response<T>, Status>
    where
        F: FnOnce(Tenant, Req) -> Fut,
        Fut: std::future::Future<Output = Result<T>>,
    {
        let start = Instant::now();
        let tenant = tenant_of(&request)?;
        let result = call(tenant, request.into_inner()).await;
        self.finish(method, start, result)
    }

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
        self.unary("CreateEnv", request, |tenant, r| async move {
            let request = EnvRequest::try_from(r)?;
            self.sim.create_env(&tenant, request).await.map(env_info)
        })
        .await
    }

    async fn reset(
        &self,
        request: Request<pb::ResetRequest>,
    ) -> Result<Response<pb::Observation>, Status> {
        self.unary("Reset", request, |tenant, r| async move {
            let obs = self
                .sim
                .reset_env(&tenant, &r.env_id, r.seed, r.keyframe)
                .await?;
            Ok(convert::observation(&obs))
        })
        .await
    }

    async fn step(
        &self,
        request: Request<pb::StepRequest>,
    ) -> Result<Response<pb::StepResult>, Status> {
        self.unary("Step", request, |tenant, r| async move {
            let step = EnvStep::try_from(r)?;
            let outcome = self.sim.step_env(&tenant, step).await?;
            let flags = outcome.flags;
            Ok(pb::StepResult {
                observation: Some(convert::observation(&outcome.observation)),
                reward: flags.reward,
                terminated: flags.terminated,
                truncated: flags.truncated,
                done: flags.done(),
                termination_reason: flags.termination.map(|t| t.as_str().to_string()),
                termination: flags
                    .termination
                    .map_or(0, |t| convert::termination(t) as i32),
                episode_step: outcome.episode_step,
                terms: outcome.terms,
            })
        })
        .await
    }

    async fn set_mocap_pose(
        &self,
        request: Request<pb::SetMocapPoseRequest>,
    ) -> Result<Response<pb::SetMocapPoseResponse>, Status> {
        self.unary("SetMocapPose", request, |tenant, r| async move {
            let pose = convert::mocap_pose(&r.pose)?;
            self.sim
                .set_mocap_pose(&tenant, &r.env_id, r.body, pose)
                .await?;
            Ok(pb::SetMocapPoseResponse {})
        })
        .await
    }

    async fn set_heightfield(
        &self,
        request: Request<pb::SetHeightfieldRequest>,
    ) -> Result<Response<pb::SetHeightfieldResponse>, Status> {
        self.unary("SetHeightfield", request, |tenant, r| async move {
            let target = (r.env_id, r.batch_id, r.env_indices);
            self.sim
                .set_heightfield(&tenant, target, r.name, r.heights)
                .await?;
            Ok(pb::SetHeightfieldResponse {})
        })
        .await
    }

    async fn observe(
        &self,
        request: Request<pb::EnvRef>,
    ) -> Result<Response<pb::Observation>, Status> {
        self.unary("Observe", request, |tenant, r| async move {
            let obs = self.sim.observe_env(&tenant, &r.env_id).await?;
            Ok(convert::observation(&obs))
        })
        .await
    }

    async fn close(
        &self,
        request: Request<pb::EnvRef>,
    ) -> Result<Response<pb::CloseEnvResponse>, Status> {
        self.unary("Close", request, |tenant, r| async move {
            self.sim.close_env(&tenant, &r.env_id).await?;
            Ok(pb::CloseEnvResponse {})
        })
        .await
    }

    async fn create_batch(
        &self,
        request: Request<pb::CreateBatchRequest>,
    ) -> Result<Response<pb::BatchInfo>, Status> {
        self.unary("CreateBatch", request, |tenant, r| async move {
            let request = BatchRequest::try_from(r)?;
            self.sim
                .create_batch(&tenant, request)
                .await
                .map(batch_info)
        })
        .await
    }

    async fn reset_batch(
        &self,
        request: Request<pb::ResetBatchRequest>,
    ) -> Result<Response<pb::BatchObservation>, Status> {
        self.unary("ResetBatch", request, |tenant, r| async move {
            self.sim
                .reset_batch(
                    &tenant,
                    &r.batch_id,
                    r.seed,
                    r.seed_offset,
                    r.env_indices,
                    r.keyframe,
                )
                .await
                .map(convert::batch_observation)
        })
        .await
    }

    async fn step_batch(
        &self,
        request: Request<pb::StepBatchRequest>,
    ) -> Result<Response<pb::BatchStepResult>, Status> {
        self.unary("StepBatch", request, |tenant, r| async move {
            stream_step(&self.sim, &tenant, r).await
        })
        .await
    }

    async fn get_randomization(
        &self,
        request: Request<pb::RandomizationRequest>,
    ) -> Result<Response<pb::RandomizationDraws>, Status> {
        self.unary("GetRandomization", request, |tenant, r| async move {
            let target = DrawsOf::try_from(r)?;
            self.sim
                .randomization(&tenant, target)
                .await
                .map(convert::randomization_draws)
        })
        .await
    }

    async fn get_scene(&self, request: Request<pb::EnvRef>) -> Result<Response<pb::Scene>, Status> {
        self.unary("GetScene", request, |tenant, r| async move {
            self.sim.scene(&tenant, &r.env_id).await.map(convert::scene)
        })
        .await
    }

    async fn save_state(
        &self,
        request: Request<pb::EnvRef>,
    ) -> Result<Response<pb::EnvState>, Status> {
        self.unary("SaveState", request, |tenant, r| async move {
            let state = self.sim.save_state(&tenant, &r.env_id).await?;
            Ok(pb::EnvState { state })
        })
        .await
    }

    async fn load_state(
        &self,
        request: Request<pb::LoadStateRequest>,
    ) -> Result<Response<pb::Observation>, Status> {
        self.unary("LoadState", request, |tenant, r| async move {
            let obs = self.sim.load_state(&tenant, &r.env_id, r.state).await?;
            Ok(convert::observation(&obs))
        })
        .await
    }

    async fn set_joint_state(
        &self,
        request: Request<pb::SetJointStateRequest>,
    ) -> Result<Response<pb::SetJointStateResult>, Status> {
        self.unary("SetJointState", request, |tenant, r| async move {
            let state = JointState {
                positions: r.joint_positions,
                velocities: r.joint_velocities,
                base: r.base_state,
            };
            let (obs, warnings) = self.sim.set_joint_state(&tenant, &r.env_id, state).await?;
            Ok(pb::SetJointStateResult {
                observation: Some(convert::observation(&obs)),
                warnings,
            })
        })
        .await
    }

    async fn get_bodies(
        &self,
        request: Request<pb::EnvRef>,
    ) -> Result<Response<pb::Bodies>, Status> {
        self.unary("GetBodies", request, |tenant, r| async move {
            self.sim
                .bodies(&tenant, &r.env_id)
                .await
                .map(convert::bodies)
        })
        .await
    }

    async fn save_batch_state(
        &self,
        request: Request<pb::BatchStateRequest>,
    ) -> Result<Response<pb::BatchState>, Status> {
        self.unary("SaveBatchState", request, |tenant, r| async move {
            let states = self
                .sim
                .save_batch_state(&tenant, &r.batch_id, r.env_indices)
                .await?;
            Ok(pb::BatchState { states })
        })
        .await
    }

    async fn load_batch_state(
        &self,
        request: Request<pb::LoadBatchStateRequest>,
    ) -> Result<Response<pb::BatchObservation>, Status> {
        self.unary("LoadBatchState", request, |tenant, r| async move {
            self.sim
                .load_batch_state(&tenant, &r.batch_id, r.env_indices, r.states)
                .await
                .map(convert::batch_observation)
        })
        .await
    }

    async fn fork(
        &self,
        request: Request<pb::ForkRequest>,
    ) -> Result<Response<pb::BatchInfo>, Status> {
        self.unary("Fork", request, |tenant, r| async move {
            let request = ForkRequest::try_from(r)?;
            self.sim.fork(&tenant, request).await.map(batch_info)
        })
        .await
    }

    async fn convert_document(
        &self,
        request: Request<pb::ConvertDocumentRequest>,
    ) -> Result<Response<pb::ConvertedDocument>, Status> {
        self.unary("ConvertDocument", request, |_tenant, r| async move {
            let format = convert::document_format(r.format)?;
            let (document_json, warnings, format) = self
                .sim
                .convert(r.document_json, format, r.assets, r.document_path)
                .await?;
            Ok(pb::ConvertedDocument {
                document_json,
                warnings,
                format: convert::format_to_proto(format) as i32,
            })
        })
        .await
    }

    async fn list_models(
        &self,
        request: Request<pb::ListModelsRequest>,
    ) -> Result<Response<pb::ModelList>, Status> {
        self.unary("ListModels", request, |_tenant, _r| async move {
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
            Ok(pb::ModelList { models })
        })
        .await
    }

    async fn render(
        &self,
        request: Request<pb::RenderRequest>,
    ) -> Result<Response<pb::Image>, Status> {
        self.unary("Render", request, |tenant, r| async move {
            let target = RenderOf::try_from(r)?;
            self.sim.render(&tenant, target).await.map(convert::image)
        })
        .await
    }

    async fn observe_batch(
        &self,
        request: Request<pb::BatchRef>,
    ) -> Result<Response<pb::BatchObservation>, Status> {
        self.unary("ObserveBatch", request, |tenant, r| async move {
            self.sim
                .observe_batch(&tenant, &r.batch_id)
                .await
                .map(convert::batch_observation)
        })
        .await
    }

    async fn close_batch(
        &self,
        request: Request<pb::BatchRef>,
    ) -> Result<Response<pb::CloseBatchResponse>, Status> {
        self.unary("CloseBatch", request, |tenant, r| async move {
            self.sim.close_batch(&tenant, &r.batch_id).await?;
            Ok(pb::CloseBatchResponse {})
        })
        .await
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
        self.unary("GetServerInfo", request, |tenant, _r| async move {
            Ok(convert::server_info(&self.sim.status(&tenant)))
        })
        .await
    }
}
