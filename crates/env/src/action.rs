//! Action types and validation.

use std::fmt;
use std::str::FromStr;

use gymfleet_physics::ActionMode;

use crate::error::{EnvError, Result};

/// How the values of a step are interpreted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ActionType {
    /// Efforts: N·m for angular DOFs, N for linear ones.
    #[default]
    Torque,
    /// Targets in deg or mm, reached through PD motors.
    Position,
    /// Targets in deg/s or mm/s.
    Velocity,
}

impl ActionType {
    /// The lowercase name used by the MCP tools.
    pub fn as_str(self) -> &'static str {
        match self {
            ActionType::Torque => "torque",
            ActionType::Position => "position",
            ActionType::Velocity => "velocity",
        }
    }

    pub(crate) fn mode(self) -> ActionMode {
        match self {
            ActionType::Torque => ActionMode::Torque,
            ActionType::Position => ActionMode::Position,
            ActionType::Velocity => ActionMode::Velocity,
        }
    }
}

impl fmt::Display for ActionType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for ActionType {
    type Err = EnvError;

    fn from_str(s: &str) -> Result<Self> {
        match s {
            "torque" => Ok(ActionType::Torque),
            "position" => Ok(ActionType::Position),
            "velocity" => Ok(ActionType::Velocity),
            other => Err(EnvError::UnknownActionType {
                got: other.to_string(),
            }),
        }
    }
}

/// Checks an action's length and finiteness.
pub(crate) fn validate(values: &[f32], action_dim: usize) -> Result<()> {
    if values.len() != action_dim {
        return Err(EnvError::ActionLength {
            expected: action_dim,
            got: values.len(),
        });
    }
    if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(EnvError::NonFiniteAction { index, value });
    }
    Ok(())
}

/// Σ a² over an action's values, in f64: the action cost of every task.
pub(crate) fn sum_of_squares(values: &[f32]) -> f64 {
    values.iter().map(|&a| f64::from(a) * f64::from(a)).sum()
}
