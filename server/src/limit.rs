//! The server's limits, each written once: its name (the `ServerConfig` field, the
//! `ServerLimits` field on the wire and the refusal metric's `reason` label), its flag, its
//! environment variable, its default, and what 0 means (no limit). A leaf: a
//! `ServerConfig` holds each limit's value (`ServerConfig::limit`).

use std::fmt;

/// Default largest gRPC message, decoded or encoded: 64 MiB (tonic's own default is 4 MiB).
pub const DEFAULT_MAX_MESSAGE_BYTES: usize = 64 * 1024 * 1024;
/// Default largest `document_json`: 8 MiB.
pub const DEFAULT_MAX_DOCUMENT_BYTES: usize = 8 * 1024 * 1024;
/// Default most environments held at once, single envs and batch members together.
pub const DEFAULT_MAX_ENVS: usize = 65_536;
/// Default most environments in one batch.
pub const DEFAULT_MAX_BATCH_SIZE: usize = 16_384;
/// Default most instances (bodies) per document: far more than a real robot has.
pub const DEFAULT_MAX_INSTANCES: usize = 512;
/// Default most joints per document, fixed ones included.
pub const DEFAULT_MAX_JOINTS: usize = 512;
/// Default most DOFs per document: a humanoid has ~30–60. A step's cost grows faster
/// than linearly with the DOFs of a chain (a 20-DOF chain costs ~160 µs a step, a few
/// hundred cost seconds), so this bounds the work one env step can ask for.
pub const DEFAULT_MAX_DOFS: usize = 128;
/// Default most work one step call may ask for, in DOF-substeps (envs × substeps ×
/// DOFs): 10 million, e.g. 16 384 six-DOF arms at 100 substeps, or 16 384 humanoids of
/// 60 DOFs at 10. At ~1–2 µs per DOF-substep that bounds a call to seconds, not hours.
pub const DEFAULT_MAX_STEP_WORK: usize = 10_000_000;
/// Default most contact work one env step may ask of the solver, in contact point-substeps
/// (the contact points its collision detection finds × substeps): 100 000, e.g. 20 000
/// points at the default 5 substeps, hundreds of times what a robot on a floor or a
/// manipulation scene finds. Issue O1's pile of 300 overlapping 2 mm cubes finds 179 400
/// points (897 000 point-substeps), and one of its steps takes about 0.3 s in a debug build.
pub const DEFAULT_MAX_CONTACT_WORK: usize = 100_000;
/// Default most observed end effectors per env.
pub const DEFAULT_MAX_END_EFFECTORS: usize = 64;

/// One of the server's limits. Every one is a count; 0 means "no limit".
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Limit {
    /// Environments held at once, single envs plus batch members (`--max-envs`).
    Envs,
    /// Environments one tenant holds at once (`--tenant-max-envs`).
    TenantEnvs,
    /// Environments in one batch (`--max-batch-size`).
    BatchSize,
    /// Bytes of an accepted document (`--max-document-bytes`).
    DocumentBytes,
    /// Bytes of a gRPC message, decoded or encoded (`--max-message-bytes`; 0 keeps tonic's
    /// 4 MiB).
    MessageBytes,
    /// Instances per document (`--max-instances`).
    Instances,
    /// Joints per document, fixed ones included (`--max-joints`).
    Joints,
    /// Degrees of freedom per document (`--max-dofs`).
    Dofs,
    /// Observed end effectors per env (`--max-end-effectors`).
    EndEffectors,
    /// DOF-substeps of work per step call (`--max-step-work`).
    StepWork,
    /// Contact point-substeps of solver work per env step (`--max-contact-work`).
    ContactWork,
}

impl Limit {
    /// Every limit.
    pub const ALL: [Limit; 11] = [
        Limit::Envs,
        Limit::TenantEnvs,
        Limit::BatchSize,
        Limit::DocumentBytes,
        Limit::MessageBytes,
        Limit::Instances,
        Limit::Joints,
        Limit::Dofs,
        Limit::EndEffectors,
        Limit::StepWork,
        Limit::ContactWork,
    ];

    /// Its name, flag (without the dashes) and environment variable.
    const fn names(self) -> (&'static str, &'static str, &'static str) {
        match self {
            Limit::Envs => ("max_envs", "max-envs", "GYMFLEET_MAX_ENVS"),
            Limit::TenantEnvs => (
                "tenant_max_envs",
                "tenant-max-envs",
                "GYMFLEET_TENANT_MAX_ENVS",
            ),
            Limit::BatchSize => (
                "max_batch_size",
                "max-batch-size",
                "GYMFLEET_MAX_BATCH_SIZE",
            ),
            Limit::DocumentBytes => (
                "max_document_bytes",
                "max-document-bytes",
                "GYMFLEET_MAX_DOCUMENT_BYTES",
            ),
            Limit::MessageBytes => (
                "max_message_bytes",
                "max-message-bytes",
                "GYMFLEET_MAX_MESSAGE_BYTES",
            ),
            Limit::Instances => ("max_instances", "max-instances", "GYMFLEET_MAX_INSTANCES"),
            Limit::Joints => ("max_joints", "max-joints", "GYMFLEET_MAX_JOINTS"),
            Limit::Dofs => ("max_dofs", "max-dofs", "GYMFLEET_MAX_DOFS"),
            Limit::EndEffectors => (
                "max_end_effectors",
                "max-end-effectors",
                "GYMFLEET_MAX_END_EFFECTORS",
            ),
            Limit::StepWork => ("max_step_work", "max-step-work", "GYMFLEET_MAX_STEP_WORK"),
            Limit::ContactWork => (
                "max_contact_work",
                "max-contact-work",
                "GYMFLEET_MAX_CONTACT_WORK",
            ),
        }
    }

    /// Its name: the `ServerConfig` and `ServerLimits` field, and the refusal metric's
    /// `reason` label, e.g. `max_batch_size`.
    pub const fn name(self) -> &'static str {
        self.names().0
    }

    /// Its command-line flag without the leading dashes, e.g. `max-batch-size`.
    pub const fn flag(self) -> &'static str {
        self.names().1
    }

    /// The environment variable its flag also reads, e.g. `GYMFLEET_MAX_BATCH_SIZE`.
    pub const fn var(self) -> &'static str {
        self.names().2
    }

    /// Its default: the server's when neither the flag nor the variable is given.
    pub const fn default_value(self) -> usize {
        match self {
            Limit::Envs => DEFAULT_MAX_ENVS,
            Limit::TenantEnvs => 0,
            Limit::BatchSize => DEFAULT_MAX_BATCH_SIZE,
            Limit::DocumentBytes => DEFAULT_MAX_DOCUMENT_BYTES,
            Limit::MessageBytes => DEFAULT_MAX_MESSAGE_BYTES,
            Limit::Instances => DEFAULT_MAX_INSTANCES,
            Limit::Joints => DEFAULT_MAX_JOINTS,
            Limit::Dofs => DEFAULT_MAX_DOFS,
            Limit::EndEffectors => DEFAULT_MAX_END_EFFECTORS,
            Limit::StepWork => DEFAULT_MAX_STEP_WORK,
            Limit::ContactWork => DEFAULT_MAX_CONTACT_WORK,
        }
    }

    /// Whether `count` is over the limit `max` (0 = no limit, never over).
    pub fn exceeded(max: usize, count: usize) -> bool {
        max != 0 && count > max
    }
}

/// How to raise it: `--max-batch-size (GYMFLEET_MAX_BATCH_SIZE)`, as error messages say.
impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "--{} ({})", self.flag(), self.var())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_limit_spells_its_name_flag_and_variable_alike() {
        for limit in Limit::ALL {
            let name = limit.name();
            assert_eq!(limit.flag(), name.replace('_', "-"), "{limit:?}");
            assert_eq!(
                limit.var(),
                format!("GYMFLEET_{}", name.to_uppercase()),
                "{limit:?}"
            );
        }
        assert_eq!(
            Limit::BatchSize.to_string(),
            "--max-batch-size (GYMFLEET_MAX_BATCH_SIZE)"
        );
    }

    #[test]
    fn zero_means_no_limit() {
        assert!(!Limit::exceeded(0, usize::MAX));
        assert!(!Limit::exceeded(4, 4));
        assert!(Limit::exceeded(4, 5));
        let config = crate::ServerConfig {
            max_joints: 7,
            ..crate::ServerConfig::default()
        };
        assert_eq!(config.limit(Limit::Joints), 7);
        // The defaults of a server built in code are the command line's.
        let config = crate::ServerConfig::default();
        for limit in Limit::ALL {
            assert_eq!(config.limit(limit), limit.default_value(), "{limit:?}");
        }
    }
}
