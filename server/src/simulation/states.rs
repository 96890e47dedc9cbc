//! Saved states: save and load one env or a batch's envs, and fork an env into a batch.

use gymfleet_batch::EnvBatch;
use gymfleet_env::SavedState;

use crate::domain::{BatchObservations, Created, EnvRequest, ForkRequest, Observed};
use crate::error::{EntityKind, Result, ServerError};
use crate::limit::Limit;
use crate::pool::{self, Lane};
use crate::registry::clear_done;
use crate::tenant::Tenant;

use super::batches::batch_observation;
use super::documents::build_env;
use super::limits::check_reply_size;
use super::Simulation;

impl Simulation {
    /// Saves an env's state (re-seating it; see `gymfleet_env::SavedState`).
    pub(crate) async fn save_state(&self, tenant: &Tenant, id: &str) -> Result<Vec<u8>> {
        self.on_env(tenant, id, "SaveState", |open| {
            Ok(open.env.save()?.encode())
        })
        .await
    }

    /// Loads a state into an env of the same document and options; its observation.
    pub(crate) async fn load_state(
        &self,
        tenant: &Tenant,
        id: &str,
        state: Vec<u8>,
    ) -> Result<Observed> {
        self.on_env(tenant, id, "LoadState", move |open| {
            let state = SavedState::decode(&state)?;
            open.env.load(&state)?;
            open.was_done.fill(false);
            Ok(open.observation())
        })
        .await
    }

    /// Saves the states of envs `env_indices` of a batch (empty: every env), refusing a
    /// reply over the message limit.
    pub(crate) async fn save_batch_state(
        &self,
        tenant: &Tenant,
        id: &str,
        env_indices: Vec<u32>,
    ) -> Result<Vec<Vec<u8>>> {
        let max = self.config.max_message_bytes;
        self.on_batch(tenant, id, Lane::Batch, "SaveBatchState", move |open| {
            let states: Vec<Vec<u8>> = open
                .batch
                .save_states(&env_indices)?
                .iter()
                .map(SavedState::encode)
                .collect();
            // Each state also costs a few bytes of framing on the wire.
            let bytes = states.iter().map(|s| s.len() + 8).sum::<usize>();
            if max != 0 && bytes > max {
                return Err(ServerError::StatesTooLarge {
                    bytes,
                    max,
                    count: states.len(),
                });
            }
            Ok(states)
        })
        .await
    }

    /// Loads states into envs `env_indices` of a batch (empty: every env); every env's
    /// observation.
    pub(crate) async fn load_batch_state(
        &self,
        tenant: &Tenant,
        id: &str,
        env_indices: Vec<u32>,
        states: Vec<Vec<u8>>,
    ) -> Result<BatchObservations> {
        let batch_id = id.to_string();
        self.on_batch(tenant, id, Lane::Batch, "LoadBatchState", move |open| {
            let decoded = states
                .iter()
                .enumerate()
                .map(|(k, bytes)| {
                    SavedState::decode(bytes).map_err(|err| ServerError::InvalidArgument {
                        field: "states",
                        reason: format!("states[{k}]: {err}"),
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            open.batch.load_states(&env_indices, &decoded)?;
            clear_done(&mut open.was_done, Some(&env_indices));
            let mut observations = Vec::new();
            open.batch.observe(&mut observations);
            Ok(batch_observation(batch_id, &open.batch, observations))
        })
        .await
    }

    /// A new batch of `n_envs` copies of a saved state, built through the same checks as
    /// `CreateBatch` (the state's document and options against every server limit).
    pub(crate) async fn fork(&self, tenant: &Tenant, request: ForkRequest) -> Result<Created> {
        let ForkRequest {
            state,
            n_envs,
            autoreset,
        } = request;
        let max = self.config.limit(Limit::BatchSize);
        if Limit::exceeded(max, n_envs) {
            return Err(ServerError::BatchTooLarge { n_envs, max });
        }
        // Decoding checksums the whole state: CPU work, so on the pool.
        let state = pool::run(&self.pool, Lane::Env, "Fork", move || {
            Ok(SavedState::decode(&state)?)
        })
        .await?;
        self.check_document_in("state.document", state.document())?;
        let reservation = self.reserve(tenant, n_envs, EntityKind::Batch)?;
        let pool = self.pool.clone();
        let config = self.config.clone();
        let (batch, links) = pool::run(&self.pool, Lane::Batch, "Fork", move || {
            let request = EnvRequest {
                document: state.document().to_string(),
                format: Some(gymfleet_import::Format::Json),
                model: None,
                assets: Vec::new(),
                document_path: String::new(),
                config: state.config().clone(),
            };
            let (mut template, links) = build_env(request, &config, n_envs)?;
            check_reply_size(&config, n_envs, template.spec().observation_dim)?;
            template.load(&state)?;
            let batch = EnvBatch::copies_of(&template, n_envs, autoreset, &pool)?;
            Ok((batch, links))
        })
        .await?;
        Ok(self.open_batch(tenant, batch, links, reservation, "forked batch"))
    }
}
