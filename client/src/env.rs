//! [`Env`]: a handle on one server-side environment.

use gymfleet_proto::v1 as pb;

use crate::client::Client;
use crate::error::Result;
use crate::options::EnvOptions;
use crate::types::{ActionType, EnvInfo, Observation, StepResult};

impl Client {
    /// Creates one environment.
    pub async fn create_env(&self, options: EnvOptions) -> Result<Env> {
        let request = options.into_request();
        let (document, assets) = request
            .options
            .as_ref()
            .map_or((0, 0), |o| (o.document_json.len(), o.assets.len()));
        self.check_request_size(&request, document, assets)?;
        let info = self.rpc().create_env(request).await?;
        Ok(Env::new(self.clone(), info.into_inner().into()))
    }
}

/// One environment on the server. Calls on one env are serialised by the server.
///
/// The env lives until [`Env::close`], or until the server reclaims it after its idle
/// TTL. Dropping the handle does not close it.
#[derive(Debug, Clone)]
pub struct Env {
    pub(crate) client: Client,
    info: EnvInfo,
}

impl Env {
    pub(crate) fn new(client: Client, info: EnvInfo) -> Self {
        Env { client, info }
    }

    /// What the server said about the env when it was created.
    pub fn info(&self) -> &EnvInfo {
        &self.info
    }

    /// Its id, `"sim_<n>"`.
    pub fn id(&self) -> &str {
        &self.info.env_id
    }

    /// The address of the server the env lives on, as given to [`Client::connect`]. An
    /// env's state lives on that one server only.
    pub fn server(&self) -> &str {
        self.client.addr()
    }

    pub(crate) fn env_ref(&self) -> pb::EnvRef {
        pb::EnvRef {
            env_id: self.info.env_id.clone(),
        }
    }

    /// Restores the initial state and returns the first observation; `seed` reseeds the
    /// env's generator first.
    pub async fn reset(&self, seed: Option<u64>) -> Result<Observation> {
        self.reset_to(seed, "").await
    }

    /// [`Env::reset`] from the document's keyframe named `keyframe` (one of
    /// `info().keyframes`), the reset's noise on top; `""`: the document's
    /// `initial_keyframe`, if any. An unknown name is [`crate::ClientError::InvalidArgument`].
    pub async fn reset_to(&self, seed: Option<u64>, keyframe: &str) -> Result<Observation> {
        let request = pb::ResetRequest {
            env_id: self.info.env_id.clone(),
            seed,
            keyframe: keyframe.to_string(),
        };
        let observation = self.client.rpc().reset(request).await?;
        observation.into_inner().try_into()
    }

    /// Applies `values` (one per DOF, `info().action_dim` of them) for one step.
    pub async fn step(&self, action_type: ActionType, values: &[f32]) -> Result<StepResult> {
        self.step_with_mocap(action_type, values, &[]).await
    }

    /// [`Env::step`], moving the env's mocap bodies (`info().mocap_bodies`) to
    /// `mocap_poses` by the end of the step: 7 values each, `[x, y, z, qw, qx, qy, qz]`
    /// (world mm, or m with SI units). Empty: every target stays as it is.
    pub async fn step_with_mocap(
        &self,
        action_type: ActionType,
        values: &[f32],
        mocap_poses: &[f32],
    ) -> Result<StepResult> {
        self.step_owned(action_type, values.to_vec(), mocap_poses.to_vec())
            .await
    }

    /// [`Env::step_with_mocap`] with owned values, which go into the request as they are.
    pub async fn step_owned(
        &self,
        action_type: ActionType,
        values: Vec<f32>,
        mocap_poses: Vec<f32>,
    ) -> Result<StepResult> {
        let request = pb::StepRequest {
            env_id: self.info.env_id.clone(),
            action_type: pb::ActionType::from(action_type) as i32,
            values,
            mocap_poses,
        };
        let result = self.client.rpc().step(request).await?;
        result.into_inner().try_into()
    }

    /// Sets where mocap body `body` (one of `info().mocap_bodies`) is to be at the end of
    /// the next step, and stay: `[x, y, z, qw, qx, qy, qz]`, world mm (m with SI units).
    pub async fn set_mocap_pose(&self, body: &str, pose: [f32; 7]) -> Result<()> {
        let request = pb::SetMocapPoseRequest {
            env_id: self.info.env_id.clone(),
            body: body.to_string(),
            pose: pose.to_vec(),
        };
        self.client.rpc().set_mocap_pose(request).await?;
        Ok(())
    }

    /// Replaces heightfield `name`'s heights (one of `info().heightfields`): rows × columns
    /// values in [0, 1], row 0 at −y, as MuJoCo's `hfield_data`. The terrain stays through
    /// resets and travels in saved states.
    pub async fn set_heightfield(&self, name: &str, heights: &[f32]) -> Result<()> {
        let request = pb::SetHeightfieldRequest {
            env_id: self.info.env_id.clone(),
            name: name.to_string(),
            heights: heights.to_vec(),
            ..Default::default()
        };
        self.client.rpc().set_heightfield(request).await?;
        Ok(())
    }

    /// The current observation, without stepping.
    pub async fn observe(&self) -> Result<Observation> {
        let observation = self.client.rpc().observe(self.env_ref()).await?;
        observation.into_inner().try_into()
    }

    /// The domain-randomisation factors it drew at its last reset;
    /// [`crate::ClientError::FailedPrecondition`] if it was created without
    /// [`crate::EnvOptions::randomize`].
    pub async fn randomization(&self) -> Result<crate::RandomizationDraws> {
        let request = pb::RandomizationRequest {
            env_id: self.info.env_id.clone(),
            ..Default::default()
        };
        let draws = self.client.rpc().get_randomization(request).await?;
        Ok(draws.into_inner().into())
    }

    /// Frees the env on the server. Later calls on it (from any handle) are
    /// [`crate::ClientError::NotFound`].
    pub async fn close(&self) -> Result<()> {
        self.client.rpc().close(self.env_ref()).await?;
        Ok(())
    }
}
