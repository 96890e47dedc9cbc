//! The limits a request is checked against before anything is built: structure (instances,
//! joints, DOFs, end effectors), step work, reply size, document bytes, and the envs a
//! tenant and the server may hold.

use std::sync::{Arc, PoisonError};

use crate::config::ServerConfig;
use crate::error::{EntityKind, Result, ServerError};
use crate::limit::Limit;
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
            Limit::Instances,
        ),
        ("assembly.joints", assembly.joints.len(), Limit::Joints),
        ("degrees of freedom", assembly.total_dof(), Limit::Dofs),
        ("end_effector_ids", end_effectors, Limit::EndEffectors),
    ];
    for (what, count, limit) in checks {
        let max = config.limit(limit);
        if Limit::exceeded(max, count) {
            return Err(ServerError::TooComplex {
                what,
                count,
                max,
                limit,
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
    let max = config.limit(Limit::StepWork);
    let substeps = usize::try_from(substeps).unwrap_or(usize::MAX);
    let work = n_envs.saturating_mul(substeps).saturating_mul(dofs.max(1));
    if Limit::exceeded(max, work) {
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

/// Gives `env` the server's contact-work limit (its copies keep it), and refuses it when
/// its bodies already touch, where the document puts them, in more contact work than a
/// step may ask for: one collision detection of the initial state, on a copy.
pub(super) fn check_contact_work(
    config: &ServerConfig,
    env: &mut gymfleet_env::RobotEnv,
    substeps: u32,
) -> Result<()> {
    let max = config.limit(Limit::ContactWork);
    env.set_contact_work_limit(max);
    if max == 0 {
        return Ok(());
    }
    let (load, work) = env.initial_contact_work();
    if Limit::exceeded(max, work) {
        return Err(ServerError::ContactsAtStart {
            pairs: load.pairs,
            points: load.points,
            substeps,
            work,
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
    let max = config.limit(Limit::MessageBytes);
    let bytes = n_envs
        .saturating_mul(observation_dim)
        .saturating_mul(2 * 4)
        .saturating_add(n_envs.saturating_mul(4 + 4 + 2));
    if Limit::exceeded(max, bytes) {
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
            EnvCapacity::for_tenant(self.config.limit(Limit::TenantEnvs), tenant.clone())
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
        let max = self.config.limit(Limit::DocumentBytes);
        if Limit::exceeded(max, document.len()) {
            return Err(ServerError::DocumentTooLarge {
                field,
                bytes: document.len(),
                max,
            });
        }
        Ok(())
    }
}
