//! Saved states (docs/design.md §6.4): [`EnvState`], `save_state`/`load_state` on an [`Env`]
//! or some envs of a [`Batch`], and [`Client::fork`], which makes a batch of copies of one
//! state on any server.

use std::fmt;

use gymfleet_proto::v1 as pb;

use crate::batch::{Batch, BatchObservations};
use crate::client::Client;
use crate::types::{Autoreset, BatchInfo, Observation};
use crate::{Env, Result};

/// One env's saved state: opaque, versioned, checksummed bytes holding its document and
/// options, its episode and its physics state. Self-contained: it loads or forks on any
/// server of the same version. Keep it as bytes ([`EnvState::as_bytes`]) anywhere; a
/// server checks every field before using it.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct EnvState(Vec<u8>);

impl EnvState {
    /// A state from bytes a server returned earlier (checked by the server on use).
    pub fn from_bytes(bytes: impl Into<Vec<u8>>) -> Self {
        EnvState(bytes.into())
    }

    /// The state's bytes.
    pub fn as_bytes(&self) -> &[u8] {
        &self.0
    }

    /// The state's bytes, owned.
    pub fn into_bytes(self) -> Vec<u8> {
        self.0
    }

    /// Its size in bytes.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether it has no bytes (no server returns such a state).
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl fmt::Debug for EnvState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "EnvState({} bytes)", self.0.len())
    }
}

impl Env {
    /// Saves the env's state. The env is re-seated from it (the server's env and every
    /// env loaded from the state then continue bitwise alike given the same actions).
    /// [`crate::ClientError::FailedPrecondition`] for a diverged env.
    pub async fn save_state(&self) -> Result<EnvState> {
        let state = self.client.rpc().save_state(self.env_ref()).await?;
        Ok(EnvState(state.into_inner().state))
    }

    /// Loads a state saved from an env of the same document and options (the seed may
    /// differ); returns the observation. A state that does not fit is
    /// [`crate::ClientError::InvalidArgument`] with the reason, and changes nothing.
    pub async fn load_state(&self, state: &EnvState) -> Result<Observation> {
        let request = pb::LoadStateRequest {
            env_id: self.id().to_string(),
            state: state.0.clone(),
        };
        let observation = self.client.rpc().load_state(request).await?;
        observation.into_inner().try_into()
    }
}

impl Batch {
    /// Replaces heightfield `name`'s heights in envs `env_indices` (ascending, distinct;
    /// empty: every env), as [`crate::Env::set_heightfield`] does in one env.
    pub async fn set_heightfield(
        &self,
        env_indices: &[u32],
        name: &str,
        heights: &[f32],
    ) -> Result<()> {
        let request = pb::SetHeightfieldRequest {
            batch_id: self.id().to_string(),
            env_indices: env_indices.to_vec(),
            name: name.to_string(),
            heights: heights.to_vec(),
            ..Default::default()
        };
        self.client.rpc().set_heightfield(request).await?;
        Ok(())
    }

    /// Saves the states of envs `env_indices` (ascending, distinct; empty: every env), in
    /// that order.
    pub async fn save_states(&self, env_indices: &[u32]) -> Result<Vec<EnvState>> {
        let request = pb::BatchStateRequest {
            batch_id: self.id().to_string(),
            env_indices: env_indices.to_vec(),
        };
        let states = self.client.rpc().save_batch_state(request).await?;
        Ok(states
            .into_inner()
            .states
            .into_iter()
            .map(EnvState)
            .collect())
    }

    /// Loads `states[k]` into env `env_indices[k]` (empty: every env, one state each); all
    /// are checked before any is loaded. Returns every env's observation.
    pub async fn load_states(
        &self,
        env_indices: &[u32],
        states: &[EnvState],
    ) -> Result<BatchObservations> {
        let request = pb::LoadBatchStateRequest {
            batch_id: self.id().to_string(),
            env_indices: env_indices.to_vec(),
            states: states.iter().map(|s| s.0.clone()).collect(),
        };
        let observation = self.client.rpc().load_batch_state(request).await?;
        BatchObservations::new(observation.into_inner(), self.info())
    }
}

impl Client {
    /// A new batch of `n_envs` copies of `state` on this server: each continues, given the
    /// same actions, bitwise as the env the state was saved from. The state carries its
    /// document, so it forks on any server.
    pub async fn fork(
        &self,
        state: &EnvState,
        n_envs: usize,
        autoreset: Autoreset,
    ) -> Result<Batch> {
        let request = pb::ForkRequest {
            state: state.0.clone(),
            n_envs: u32::try_from(n_envs).unwrap_or(u32::MAX),
            autoreset: pb::Autoreset::from(autoreset) as i32,
        };
        let info = self.rpc().fork(request).await?;
        let info = BatchInfo::try_from(info.into_inner())?;
        Ok(Batch::new(self.clone(), info))
    }
}
