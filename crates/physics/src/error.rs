//! Errors of world construction, actuation and state restore.

/// Why a world could not be built or driven.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    /// PD gain overrides do not match the DOF count or are not usable numbers.
    #[error("{field}: {reason}")]
    BadGains {
        /// `pd_gains.kp` or `pd_gains.kd`.
        field: &'static str,
        /// What was expected.
        reason: String,
    },
    /// An option such as the substep length is out of range.
    #[error("{field}: {reason}")]
    BadOption {
        /// The option's name.
        field: &'static str,
        /// What was expected.
        reason: String,
    },
    /// A saved dynamic state does not fit the world or holds an unusable value.
    #[error("state.{path}: {reason}")]
    BadState {
        /// The field, e.g. `world.joints[2].coords[3]`.
        path: String,
        /// What was expected.
        reason: String,
    },
}

/// Result alias for this crate.
pub type Result<T, E = PhysicsError> = std::result::Result<T, E>;
