//! Errors of batch creation and stepping.

use gymfleet_env::EnvError;

/// Why a batch could not be created or stepped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BatchError {
    /// A batch was asked for zero environments.
    #[error("n_envs: expected at least 1 environment, got 0")]
    NoEnvs,
    /// The flat action array has the wrong length.
    #[error(
        "actions: expected {expected} {} ({n_envs} {} × {action_dim} DOF), got {got}",
        plural(*.expected, "value", "values"),
        plural(*.n_envs, "env", "envs")
    )]
    ActionLength {
        /// `n_envs × action_dim`.
        expected: usize,
        /// How many values were given.
        got: usize,
        /// Environments in the batch.
        n_envs: usize,
        /// Values per environment.
        action_dim: usize,
    },
    /// An action value is NaN or infinite.
    #[error(
        "actions[{flat_index}] (env {env}, value {index}): expected a finite number, got {value}"
    )]
    NonFiniteAction {
        /// The environment the value belongs to.
        env: usize,
        /// Position of the value within that environment's action.
        index: usize,
        /// The bad value.
        value: f32,
        /// Position of the value in the flat action array: `env × action_dim + index`.
        flat_index: usize,
    },
    /// One environment failed; the others were stepped.
    #[error("env {env}: {source}")]
    Env {
        /// Index of the failing environment in the batch.
        env: usize,
        /// What went wrong.
        source: EnvError,
    },
    /// The thread pool could not be built, or a step panicked on it.
    #[error("step pool: {reason}")]
    Pool {
        /// What went wrong.
        reason: String,
    },
}

fn plural(n: usize, one: &'static str, many: &'static str) -> &'static str {
    if n == 1 {
        one
    } else {
        many
    }
}

/// Result alias for this crate.
pub type Result<T, E = BatchError> = std::result::Result<T, E>;
