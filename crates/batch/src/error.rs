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
    /// A list of env indices (for a partial reset) is not ascending, distinct and below
    /// `n_envs`.
    #[error("env_indices[{position}]: {reason}")]
    EnvIndices {
        /// The offending entry's position in the list.
        position: usize,
        /// What was expected and what was given.
        reason: String,
    },
    /// A batch load got a different number of states than of env indices.
    #[error("states: expected one state per env index ({indices}), got {states}")]
    StateCount {
        /// How many envs the indices name (every env when none are given).
        indices: usize,
        /// How many states were given.
        states: usize,
    },
    /// A step's mocap targets have the wrong number of values.
    #[error(
        "mocap_poses: expected {expected} values ({n_envs} {} × {bodies} mocap bodies × 7: x, y, z, qw, qx, qy, qz), or none to keep the targets, got {got}",
        plural(*.n_envs, "env", "envs")
    )]
    MocapPosesLength {
        /// `n_envs × bodies × 7`.
        expected: usize,
        /// How many were given.
        got: usize,
        /// Environments in the batch.
        n_envs: usize,
        /// Mocap bodies per environment.
        bodies: usize,
    },
    /// A reset names a keyframe the batch's document does not have; nothing was reset.
    #[error(transparent)]
    Keyframe(EnvError),
    /// One environment failed; the others were stepped.
    #[error("env {env}: {source}")]
    Env {
        /// Index of the failing environment in the batch.
        env: usize,
        /// What went wrong.
        source: EnvError,
    },
    /// More environments than a batch can index (`u32`).
    #[error("n_envs: expected at most {max} environments per batch, got {n_envs}")]
    TooManyEnvs {
        /// The requested size.
        n_envs: usize,
        /// The largest size.
        max: u64,
    },
    /// The step pool's threads could not be started.
    #[error("step pool: cannot start {threads} step threads: {reason}")]
    PoolStart {
        /// How many threads were asked for.
        threads: usize,
        /// The operating system's reason.
        reason: String,
    },
    /// Stepping or resetting envs `first..=last` panicked (a bug): their state can no
    /// longer be trusted until the batch is reset.
    #[error(
        "step pool: envs {first}..={last} panicked ({message}); reset the batch before \
         stepping it again"
    )]
    Panicked {
        /// The first env of the chunk that panicked.
        first: usize,
        /// The last env of that chunk.
        last: usize,
        /// The panic's message.
        message: String,
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
