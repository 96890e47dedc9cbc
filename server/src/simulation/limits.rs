//! The limits a request is checked against before anything is built: structure (instances,
//! joints, DOFs, end effectors), step work, reply size, document bytes, and the envs a
//! tenant and the server may hold.

use std::sync::{Arc, PoisonError};

use crate::config::ServerConfig;
use crate::error::{EntityKind, Result, ServerError};
use crate::registry::{EnvCapacity, Reservation};
use crate::tenant::Tenant;

use super::Simulation;

/// Refuses a document or env past a structural limit, before anything is built.
pub(super) fn check_structure(
    config: &ServerConfig,
    assembly: &gymfleet_assembly::Assembly,
    end_effectors: usize,
) -> Result<()> {
    let checks = [
        (
            "assembly.instances",
            assembly.instances.len(),
            config.max_instances,
            "--max-instances",
            "GYMFLEET_MAX_INSTANCES",
        ),
        (
            "assembly.joints",
            assembly.joints.len(),
            config.max_joints,
            "--max-joints",
            "GYMFLEET_MAX_JOINTS",
        ),
        (
            "degrees of freedom",
            assembly.total_dof(),
            config.max_dofs,
            "--max-dofs",
            "GYMFLEET_MAX_DOFS",
        ),
        (
            "end_effector_ids",
            end_effectors,
            config.max_end_effectors,
            "--max-end-effectors",
            "GYMFLEET_MAX_END_EFFECTORS",
        ),
    ];
    for (what, count, max, flag, var) in checks {
        if max != 0 && count > max {
            return Err(ServerError::TooComplex {
                what,
                count,
                max,
                flag,
                var,
            });
        }
    }
    Ok(())
}

/// Refuses envs whose steps would ask for more work than `--max-step-work`: `n_envs`
/// envs × `substeps` integration substeps × `dofs` degrees of freedom per step call.
pub(super) fn check_step_work(
    config: &ServerConfig,
    n_envs: usize,
    substeps: u32,
    dofs: usize,
) -> Result<()> {
    let max = config.max_step_work;
    let substeps = usize::try_from(substeps).unwrap_or(usize::MAX);
    let work = n_envs.saturating_mul(substeps).saturating_mul(dofs.max(1));
    if max != 0 && work > max {
        return Err(ServerError::TooMuchWork {
            work,
            n_envs,
            substeps,
            dofs: dofs.max(1),
            max,
        });
    }
    Ok(())
}

/// Refuses a batch whose step reply could exceed the message limit: observations and
/// same-step final observations (`n_envs × observation_dim` floats each, at most), plus
/// the per-env rewards and flags.
pub(super) fn check_reply_size(
    config: &ServerConfig,
    n_envs: usize,
    observation_dim: usize,
) -> Result<()> {
    let max = config.max_message_bytes;
    let bytes = n_envs
        .saturating_mul(observation_dim)
        .saturating_mul(2 * 4)
        .saturating_add(n_envs.saturating_mul(4 + 4 + 2));
    if max != 0 && bytes > max {
        return Err(ServerError::ReplyTooLarge {
            bytes,
            max,
            n_envs,
            observation_dim,
        });
    }
    Ok(())
}

impl Simulation {
    /// `tenant`'s quota.
    pub(super) fn quota(&self, tenant: &Tenant) -> Arc<EnvCapacity> {
        let mut quotas = self.quotas.lock().unwrap_or_else(PoisonError::into_inner);
        let quota = quotas.entry(tenant.clone()).or_insert_with(|| {
            EnvCapacity::for_tenant(self.config.tenant_max_envs, tenant.clone())
        });
        Arc::clone(quota)
    }

    /// Reserves `n` environments for `tenant`: in its quota and in the server's capacity.
    pub(super) fn reserve(
        &self,
        tenant: &Tenant,
        n: usize,
        kind: EntityKind,
    ) -> Result<Reservation> {
        self.quota(tenant).reserve_within(&self.capacity, n, kind)
    }

    pub(super) fn check_document(&self, document: &str) -> Result<()> {
        self.check_document_in("document_json", document)
    }

    /// [`Simulation::check_document`] for a document found in `field`.
    pub(super) fn check_document_in(&self, field: &'static str, document: &str) -> Result<()> {
        let max = self.config.max_document_bytes;
        if max != 0 && document.len() > max {
            return Err(ServerError::DocumentTooLarge {
                field,
                bytes: document.len(),
                max,
            });
        }
        Ok(())
    }
}
