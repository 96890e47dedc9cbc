//! What the dashboard (`crate::dashboard`) reads of the [`Simulation`]: the same
//! registries the gRPC service uses, through lookups that never mark an entry used
//! (watching an abandoned env must not keep it from being reclaimed). A scene is read
//! like `GetScene` reads one: under the entry's lock, on the pool.

use gymfleet_env::Scene;

use super::Simulation;
use crate::domain::DrawsOf;
use crate::error::{EntityKind, Result, ServerError};
use crate::pool::{self, Lane};
use crate::registry::Watched;
use crate::tenant::Tenant;

/// The open envs and batches of one tenant: how many of each, and the first of each in
/// id order.
pub(crate) struct Watching {
    pub(crate) envs: (usize, Vec<Watched>),
    pub(crate) batches: (usize, Vec<Watched>),
}

/// The pool job's name in logs (a panic, which reading a scene should never cause).
const OPERATION: &str = "DashboardScene";

impl Simulation {
    /// `tenant`'s envs and batches, at most `limit` of each; none is marked used.
    pub(crate) fn watching(&self, tenant: &Tenant, limit: usize) -> Watching {
        Watching {
            envs: self.envs.watch(tenant, limit),
            batches: self.batches.watch(tenant, limit),
        }
    }

    /// The scene of `tenant`'s env, or of env `index` of its batch, read on the pool under
    /// the entry's lock; the entry is not marked used.
    pub(crate) async fn watch_scene(&self, tenant: &Tenant, of: DrawsOf) -> Result<Scene> {
        match of {
            DrawsOf::Env(id) => {
                let slot = self.envs.peek(tenant, &id)?.lock(EntityKind::Env).await?;
                // The job owns the lock guard: the lock is held until it has read.
                pool::run(&self.pool, Lane::Env, OPERATION, move || {
                    let held = slot.as_ref().ok_or(ServerError::NotFound {
                        kind: EntityKind::Env,
                        id,
                    })?;
                    Ok(held.value.env.scene())
                })
                .await
            }
            DrawsOf::BatchEnv(id, index) => {
                let entry = self.batches.peek(tenant, &id)?;
                let slot = entry.lock(EntityKind::Batch).await?;
                pool::run(&self.pool, Lane::Env, OPERATION, move || {
                    let held = slot.as_ref().ok_or(ServerError::NotFound {
                        kind: EntityKind::Batch,
                        id,
                    })?;
                    let n_envs = held.value.batch.n_envs();
                    held.value
                        .batch
                        .scene(index)
                        .ok_or(ServerError::EnvIndex { index, n_envs })
                })
                .await
            }
        }
    }
}
