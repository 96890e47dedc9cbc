//! The server's limits, each written once: its name (the `ServerConfig` field, the
//! `ServerLimits` field on the wire and the refusal metric's `reason` label), its flag, its
//! environment variable, and what 0 means (no limit).

use std::fmt;

use crate::config::{
    ServerConfig, DEFAULT_MAX_BATCH_SIZE, DEFAULT_MAX_DOCUMENT_BYTES, DEFAULT_MAX_DOFS,
    DEFAULT_MAX_END_EFFECTORS, DEFAULT_MAX_ENVS, DEFAULT_MAX_INSTANCES, DEFAULT_MAX_JOINTS,
    DEFAULT_MAX_MESSAGE_BYTES, DEFAULT_MAX_STEP_WORK,
};

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
}

impl Limit {
    /// Every limit.
    pub const ALL: [Limit; 10] = [
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
        }
    }

    /// Its value in `config`; 0 = no limit.
    pub fn of(self, config: &ServerConfig) -> usize {
        match self {
            Limit::Envs => config.max_envs,
            Limit::TenantEnvs => config.tenant_max_envs,
            Limit::BatchSize => config.max_batch_size,
            Limit::DocumentBytes => config.max_document_bytes,
            Limit::MessageBytes => config.max_message_bytes,
            Limit::Instances => config.max_instances,
            Limit::Joints => config.max_joints,
            Limit::Dofs => config.max_dofs,
            Limit::EndEffectors => config.max_end_effectors,
            Limit::StepWork => config.max_step_work,
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
        let config = ServerConfig {
            max_joints: 7,
            ..ServerConfig::default()
        };
        assert_eq!(Limit::Joints.of(&config), 7);
        // The defaults of a server built in code are the command line's.
        let config = ServerConfig::default();
        for limit in Limit::ALL {
            assert_eq!(limit.of(&config), limit.default_value(), "{limit:?}");
        }
    }
}
