//! [`Batch`]: a handle on one server-side batch, and the typed views of its replies,
//! [`BatchStep`] and [`BatchObservations`], which own the decoded vectors and hand out
//! per-env slices without copying.

use std::sync::Arc;

use gymfleet_proto::v1 as pb;

use crate::client::Client;
use crate::error::{ClientError, Result};
use crate::options::BatchOptions;
use crate::types::{ActionType, BatchInfo};

impl Client {
    /// Creates a batch of identical environments.
    pub async fn create_batch(&self, options: BatchOptions) -> Result<Batch> {
        let request = options.into_request();
        let (document, assets) = request
            .options
            .as_ref()
            .map_or((0, 0), |o| (o.document_json.len(), o.assets.len()));
        self.check_request_size(&request, document, assets)?;
        let info = self.rpc().create_batch(request).await?;
        let info = BatchInfo::try_from(info.into_inner())?;
        Ok(Batch::new(self.clone(), info))
    }
}

/// A batch of identical environments on the server, stepped together.
///
/// ```no_run
/// use gymfleet_client::{ActionType, BatchOptions, Client};
///
/// # async fn demo() -> gymfleet_client::Result<()> {
/// let client = Client::connect("http://127.0.0.1:50051").await?;
/// let document = std::fs::read_to_string("models/arm2.json").expect("model");
/// let batch = client
///     .create_batch(BatchOptions::new(document, 16).end_effectors(["forearm"]))
///     .await?;
/// let actions = vec![0.5_f32; batch.info().n_envs * batch.info().action_dim];
/// let step = batch.step(ActionType::Torque, &actions).await?;
/// let first_env: &[f32] = step.obs(0);
/// assert_eq!(first_env.len(), batch.info().observation_dim);
/// batch.close().await?;
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone)]
pub struct Batch {
    pub(crate) client: Client,
    /// Shared, so that a clone (one per shard and call, for a fleet's spawned tasks) costs
    /// no copy of the joints' names and limits.
    info: Arc<BatchInfo>,
}

impl Batch {
    pub(crate) fn new(client: Client, info: BatchInfo) -> Self {
        Batch {
            client,
            info: Arc::new(info),
        }
    }

    /// What the server said about the batch when it was created.
    pub fn info(&self) -> &BatchInfo {
        &self.info
    }

    /// Its id, `"batch_<n>"`.
    pub fn id(&self) -> &str {
        &self.info.batch_id
    }

    /// The address of the server the batch lives on, as given to [`Client::connect`].
    pub fn server(&self) -> &str {
        self.client.addr()
    }

    pub(crate) fn client(&self) -> &Client {
        &self.client
    }

    fn batch_ref(&self) -> pb::BatchRef {
        pb::BatchRef {
            batch_id: self.info.batch_id.clone(),
        }
    }

    /// The one builder of this batch's step requests (whole or some envs, unary or
    /// streamed, with or without mocap targets): the values are moved in, not copied.
    pub(crate) fn step_request(
        &self,
        action_type: ActionType,
        actions: Vec<f32>,
        mocap_poses: Vec<f32>,
        env_indices: Vec<u32>,
    ) -> pb::StepBatchRequest {
        pb::StepBatchRequest {
            batch_id: self.info.batch_id.clone(),
            action_type: pb::ActionType::from(action_type) as i32,
            actions,
            mocap_poses,
            env_indices,
        }
    }

    /// Steps the envs `env_indices` (batch indices, ascending and distinct) once, with
    /// `actions` holding one row per listed env in that order; the other envs do not
    /// change, and each listed env steps as in [`Batch::step`]. The result has one row per
    /// listed env ([`BatchStep::env_indices`]).
    pub async fn step_envs(
        &self,
        action_type: ActionType,
        env_indices: &[u32],
        actions: &[f32],
    ) -> Result<BatchStep> {
        let result = self
            .step_envs_raw(action_type, env_indices.to_vec(), actions.to_vec())
            .await?;
        BatchStep::new(result, &self.info)
    }

    /// A fleet shard's part of a step of some envs: the listed envs' checked raw reply,
    /// or (none listed) an empty reply without a call.
    pub(crate) async fn step_listed(
        &self,
        action_type: ActionType,
        env_indices: Vec<u32>,
        actions: Vec<f32>,
    ) -> Result<pb::BatchStepResult> {
        if env_indices.is_empty() {
            return Ok(pb::BatchStepResult::default());
        }
        self.step_envs_raw(action_type, env_indices, actions).await
    }

    /// [`Batch::step_envs`] with owned values, returning the checked raw reply (the fleet
    /// batch merges those of its shards).
    pub(crate) async fn step_envs_raw(
        &self,
        action_type: ActionType,
        env_indices: Vec<u32>,
        actions: Vec<f32>,
    ) -> Result<pb::BatchStepResult> {
        let request = self.step_request(action_type, actions, Vec::new(), env_indices);
        let listed = request.env_indices.clone();
        let result = self.client.rpc().step_batch(request).await?.into_inner();
        if result.env_indices != listed {
            return Err(ClientError::protocol(
                "batch reply: env_indices differ from the request's",
            ));
        }
        BatchStep::new(result, &self.info).map(BatchStep::into_raw)
    }

    /// Steps every env once. `actions` holds `n_envs × action_dim` values, row-major.
    pub async fn step(&self, action_type: ActionType, actions: &[f32]) -> Result<BatchStep> {
        self.step_with_mocap(action_type, actions, &[]).await
    }

    /// [`Batch::step`], moving every env's mocap bodies (`info().mocap_bodies`) to
    /// `mocap_poses` by the end of the step: `n_envs × mocap bodies × 7` values, row-major
    /// per env, each `[x, y, z, qw, qx, qy, qz]` (world mm, or m with SI units). Empty:
    /// every target stays as it is.
    pub async fn step_with_mocap(
        &self,
        action_type: ActionType,
        actions: &[f32],
        mocap_poses: &[f32],
    ) -> Result<BatchStep> {
        self.step_owned(action_type, actions.to_vec(), mocap_poses.to_vec())
            .await
    }

    /// [`Batch::step_with_mocap`] with owned values, which go into the request as they are.
    pub async fn step_owned(
        &self,
        action_type: ActionType,
        actions: Vec<f32>,
        mocap_poses: Vec<f32>,
    ) -> Result<BatchStep> {
        let request = self.step_request(action_type, actions, mocap_poses, Vec::new());
        let result = self.client.rpc().step_batch(request).await?;
        BatchStep::new(result.into_inner(), &self.info)
    }

    /// [`Batch::step_with_mocap`] with owned values, returning the checked raw reply (the
    /// fleet batch merges those of its shards).
    pub(crate) async fn step_raw(
        &self,
        action_type: ActionType,
        actions: Vec<f32>,
        mocap_poses: Vec<f32>,
    ) -> Result<pb::BatchStepResult> {
        // Validates the shapes; the fleet merge relies on them.
        self.step_owned(action_type, actions, mocap_poses)
            .await
            .map(BatchStep::into_raw)
    }

    /// Resets every env; with `seed`, env `i` is reseeded with `seed + i` first.
    pub async fn reset(&self, seed: Option<u64>) -> Result<BatchObservations> {
        self.reset_with_offset(seed, 0).await
    }

    /// [`Batch::reset`] with env `i` reseeded with `seed + seed_offset + i`.
    pub async fn reset_with_offset(
        &self,
        seed: Option<u64>,
        seed_offset: u64,
    ) -> Result<BatchObservations> {
        self.reset_envs(seed, seed_offset, &[]).await
    }

    /// Resets only the envs in `env_indices` (ascending, distinct, each below `n_envs`;
    /// empty: every env), reseeding env `i` with `seed + seed_offset + i` when `seed` is
    /// given. Returns every env's observation: the others' current ones, and they keep
    /// their state. This is how envs that ended under [`crate::Autoreset::Disabled`] are
    /// reset without touching the rest.
    pub async fn reset_envs(
        &self,
        seed: Option<u64>,
        seed_offset: u64,
        env_indices: &[u32],
    ) -> Result<BatchObservations> {
        self.reset_envs_to(seed, seed_offset, env_indices, "").await
    }

    /// [`Batch::reset_envs`] from the document's keyframe named `keyframe` (one of
    /// `info().keyframes`), the reset's noise on top; `""`: the document's
    /// `initial_keyframe`, if any.
    pub async fn reset_envs_to(
        &self,
        seed: Option<u64>,
        seed_offset: u64,
        env_indices: &[u32],
        keyframe: &str,
    ) -> Result<BatchObservations> {
        let request = pb::ResetBatchRequest {
            batch_id: self.info.batch_id.clone(),
            seed,
            seed_offset,
            env_indices: env_indices.to_vec(),
            keyframe: keyframe.to_string(),
        };
        let observation = self.client.rpc().reset_batch(request).await?;
        BatchObservations::new(observation.into_inner(), &self.info)
    }

    /// The current observation of every env, without stepping.
    pub async fn observe(&self) -> Result<BatchObservations> {
        let observation = self.client.rpc().observe_batch(self.batch_ref()).await?;
        BatchObservations::new(observation.into_inner(), &self.info)
    }

    /// Env `env_index`'s domain-randomisation factors for its current episode.
    pub async fn randomization(&self, env_index: usize) -> Result<crate::RandomizationDraws> {
        let request = pb::RandomizationRequest {
            batch_id: self.info.batch_id.clone(),
            env_index: u32::try_from(env_index).unwrap_or(u32::MAX),
            ..Default::default()
        };
        let draws = self.client.rpc().get_randomization(request).await?;
        Ok(draws.into_inner().into())
    }

    /// Frees the batch on the server. Later calls on it are
    /// [`crate::ClientError::NotFound`].
    pub async fn close(&self) -> Result<()> {
        self.client.rpc().close_batch(self.batch_ref()).await?;
        Ok(())
    }
}

fn check_len(what: &str, got: usize, expected: usize) -> Result<()> {
    if got == expected {
        Ok(())
    } else {
        Err(ClientError::protocol(format!(
            "batch reply: expected {expected} {what}, got {got}"
        )))
    }
}

/// The result of one batch step, as received: the decoded vectors, with per-env views.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchStep {
    result: pb::BatchStepResult,
    n_envs: usize,
    observation_dim: usize,
}

impl BatchStep {
    /// Checks the reply's shapes against the batch, so the views below cannot fail.
    pub(crate) fn new(result: pb::BatchStepResult, info: &BatchInfo) -> Result<Self> {
        let dim = info.observation_dim;
        let listed = &result.env_indices;
        if listed.iter().any(|&i| i as usize >= info.n_envs) || !listed.is_sorted_by(|a, b| a < b) {
            return Err(ClientError::protocol(
                "batch reply: env_indices are out of range or not ascending",
            ));
        }
        // The rows: every env's, or the listed envs'.
        let n = if listed.is_empty() {
            info.n_envs
        } else {
            listed.len()
        };
        check_len("observation values", result.observations.len(), n * dim)?;
        check_len("rewards", result.rewards.len(), n)?;
        check_len("term values", result.terms.len(), n * info.term_names.len())?;
        check_len("terminated flags", result.terminated.len(), n)?;
        check_len("truncated flags", result.truncated.len(), n)?;
        check_len(
            "final observation values",
            result.final_observations.len(),
            result.final_env_indices.len() * dim,
        )?;
        if result
            .final_env_indices
            .iter()
            .any(|&i| i as usize >= info.n_envs)
            || !result.final_env_indices.is_sorted_by(|a, b| a < b)
        {
            return Err(ClientError::protocol(
                "batch reply: final_env_indices are out of range or not ascending",
            ));
        }
        Ok(BatchStep {
            result,
            n_envs: n,
            observation_dim: dim,
        })
    }

    /// The envs this step's rows belong to, when it stepped some of the batch
    /// ([`Batch::step_envs`]); empty: every env, in order.
    pub fn env_indices(&self) -> &[u32] {
        &self.result.env_indices
    }

    /// Batch steps applied since the batch was created, this one included.
    pub fn step_index(&self) -> u64 {
        self.result.step_index
    }

    /// Number of envs (rows).
    pub fn n_envs(&self) -> usize {
        self.n_envs
    }

    /// Values per env observation.
    pub fn observation_dim(&self) -> usize {
        self.observation_dim
    }

    /// All observations, `n_envs × observation_dim`, row-major.
    pub fn observations(&self) -> &[f32] {
        &self.result.observations
    }

    /// Env `env`'s observation row.
    ///
    /// # Panics
    ///
    /// If `env >= n_envs()`, like slice indexing.
    pub fn obs(&self, env: usize) -> &[f32] {
        let d = self.observation_dim;
        &self.result.observations[env * d..(env + 1) * d]
    }

    /// One reward per env.
    pub fn rewards(&self) -> &[f32] {
        &self.result.rewards
    }

    /// A terms task's values, `n_envs × term_names.len()`, row-major (the step's values,
    /// before a same-step autoreset).
    pub fn terms(&self) -> &[f32] {
        &self.result.terms
    }

    /// One flag per env: ended for a task or physics reason.
    pub fn terminated(&self) -> &[bool] {
        &self.result.terminated
    }

    /// One flag per env: reached `max_steps`.
    pub fn truncated(&self) -> &[bool] {
        &self.result.truncated
    }

    /// Same-step autoreset: the envs that finished and were reset in this step, ascending.
    pub fn final_env_indices(&self) -> &[u32] {
        &self.result.final_env_indices
    }

    /// Same-step autoreset: the last observation of env `env`'s finished episode, if it
    /// finished in this step.
    pub fn final_observation(&self, env: usize) -> Option<&[f32]> {
        let env = u32::try_from(env).ok()?;
        let row = self.result.final_env_indices.binary_search(&env).ok()?;
        let d = self.observation_dim;
        Some(&self.result.final_observations[row * d..(row + 1) * d])
    }

    /// Every env that terminated in this step for a reason, by batch index, ascending.
    pub fn termination_reasons(&self) -> impl Iterator<Item = (u32, &str)> + '_ {
        self.result
            .termination_reasons
            .iter()
            .map(|(&env, why)| (env, why.as_str()))
    }

    /// Why env `env` terminated in this step, if it did for a reason.
    pub fn termination_reason(&self, env: usize) -> Option<&str> {
        let env = u32::try_from(env).ok()?;
        self.result
            .termination_reasons
            .get(&env)
            .map(String::as_str)
    }

    /// Why env `env` terminated in this step, typed, if it did for a reason (`None` also
    /// from a server that sends only the strings).
    pub fn termination(&self, env: usize) -> Option<crate::TerminationReason> {
        let env = u32::try_from(env).ok()?;
        crate::types::typed_termination(*self.result.terminations.get(&env)?)
    }

    /// Takes the observations out, `n_envs × observation_dim`, without copying.
    pub fn into_observations(self) -> Vec<f32> {
        self.result.observations
    }

    pub(crate) fn into_raw(self) -> pb::BatchStepResult {
        self.result
    }
}

/// The observations of every env of a batch (from reset or observe).
#[derive(Debug, Clone, PartialEq)]
pub struct BatchObservations {
    observations: Vec<f32>,
    n_envs: usize,
    observation_dim: usize,
}

impl BatchObservations {
    pub(crate) fn new(reply: pb::BatchObservation, info: &BatchInfo) -> Result<Self> {
        let (n, dim) = (info.n_envs, info.observation_dim);
        check_len("envs", reply.n_envs as usize, n)?;
        check_len(
            "values per observation",
            reply.observation_dim as usize,
            dim,
        )?;
        check_len("observation values", reply.observations.len(), n * dim)?;
        Ok(BatchObservations {
            observations: reply.observations,
            n_envs: n,
            observation_dim: dim,
        })
    }

    /// Number of envs (rows).
    pub fn n_envs(&self) -> usize {
        self.n_envs
    }

    /// Values per env observation.
    pub fn observation_dim(&self) -> usize {
        self.observation_dim
    }

    /// All observations, `n_envs × observation_dim`, row-major.
    pub fn observations(&self) -> &[f32] {
        &self.observations
    }

    /// Env `env`'s observation row.
    ///
    /// # Panics
    ///
    /// If `env >= n_envs()`, like slice indexing.
    pub fn obs(&self, env: usize) -> &[f32] {
        let d = self.observation_dim;
        &self.observations[env * d..(env + 1) * d]
    }

    /// Takes the observations out without copying.
    pub fn into_observations(self) -> Vec<f32> {
        self.observations
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(n_envs: usize, observation_dim: usize) -> BatchInfo {
        BatchInfo {
            batch_id: "batch_1".into(),
            n_envs,
            env: crate::EnvInfo {
                observation_dim,
                ..Default::default()
            },
            ..BatchInfo::default()
        }
    }

    fn reply(n: usize, dim: usize) -> pb::BatchStepResult {
        pb::BatchStepResult {
            batch_id: "batch_1".into(),
            step_index: 1,
            observations: (0..n * dim).map(|v| v as f32).collect(),
            rewards: vec![0.0; n],
            terminated: vec![false; n],
            truncated: vec![true; n],
            final_env_indices: vec![1],
            final_observations: vec![-1.0; dim],
            termination_reasons: [(0, "physics_diverged".to_string())].into(),
            terminations: [(0, pb::TerminationReason::PhysicsDiverged as i32)].into(),
            terms: Vec::new(),
            env_indices: Vec::new(),
        }
    }

    #[test]
    fn views_slice_the_owned_vectors() {
        let step = BatchStep::new(reply(3, 2), &info(3, 2)).unwrap();
        assert_eq!(step.obs(0), [0.0, 1.0]);
        assert_eq!(step.obs(2), [4.0, 5.0]);
        assert_eq!(step.final_observation(1), Some(&[-1.0, -1.0][..]));
        assert_eq!(step.final_observation(0), None);
        assert_eq!(step.termination_reason(0), Some("physics_diverged"));
        assert_eq!(step.termination_reason(1), None);
        assert_eq!(
            step.termination(0),
            Some(crate::TerminationReason::PhysicsDiverged)
        );
        assert_eq!(step.termination(1), None);
        assert_eq!(step.truncated(), [true; 3]);
        assert_eq!(step.into_observations().len(), 6);
    }

    #[test]
    fn replies_of_the_wrong_shape_are_protocol_errors() {
        let mut short = reply(3, 2);
        short.observations.pop();
        assert!(matches!(
            BatchStep::new(short, &info(3, 2)),
            Err(ClientError::Protocol { .. })
        ));
        let mut bad_final = reply(3, 2);
        bad_final.final_env_indices = vec![3];
        assert!(BatchStep::new(bad_final, &info(3, 2)).is_err());
        let obs = pb::BatchObservation {
            batch_id: "batch_1".into(),
            n_envs: 2,
            observation_dim: 2,
            observations: vec![0.0; 4],
        };
        assert!(BatchObservations::new(obs.clone(), &info(2, 2)).is_ok());
        assert!(BatchObservations::new(obs, &info(3, 2)).is_err());
    }
}
