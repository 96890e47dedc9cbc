//! A heightfield replaced in chosen envs of a batch ([`gymfleet_env::RobotEnv::set_heightfield`]):
//! the same heights for each, checked once before any env changes.

use crate::batch::EnvBatch;
use crate::error::{BatchError, Result};

impl EnvBatch {
    /// Replaces heightfield `name`'s heights in envs `env_indices` (ascending, distinct,
    /// below `n_envs`; empty: every env). A bad index, name, count or height changes
    /// nothing.
    pub fn set_heightfield(
        &mut self,
        env_indices: &[u32],
        name: &str,
        heights: &[f32],
    ) -> Result<()> {
        let indices = self.indices_or_all(env_indices)?;
        // Every env has the batch's document: one check holds for all.
        if let Some(&first) = indices.first() {
            self.with_env(first, |e| e.check_heightfield(name, heights).map(|_| ()))
                .expect("the index was checked")
                .map_err(|source| BatchError::Env { env: first, source })?;
        }
        for i in indices {
            self.with_env_mut(i, |e| e.set_heightfield(name, heights))
                .expect("the index was checked")
                .map_err(|source| BatchError::Env { env: i, source })?;
        }
        Ok(())
    }
}
