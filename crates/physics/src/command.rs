//! The command a world holds between steps: the action mode and values, and the PD gains
//! that turn targets into efforts.

/// Natural frequency of the default PD gains, in Hz.
pub const DEFAULT_PD_FREQUENCY_HZ: f64 = 20.0;

/// How the values of an action are interpreted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum ActionMode {
    /// Efforts in N·m (angular DOF) or N (linear DOF).
    #[default]
    Torque,
    /// Targets in deg or mm, reached through PD motors.
    Position,
    /// Targets in deg/s or mm/s.
    Velocity,
}

/// PD gain overrides, one entry per DOF, in SI: `kp` in N·m/rad or N/m, `kd` in
/// N·m·s/rad or N·s/m.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct PdGains {
    /// Proportional gains (empty = defaults).
    pub kp: Vec<f64>,
    /// Derivative gains (empty = defaults).
    pub kd: Vec<f64>,
}

/// Gains resolved per DOF, defaults filled in.
#[derive(Debug, Clone, Default)]
pub(crate) struct ResolvedGains {
    /// The explicit PD frequency cap for ball joints (rad/s).
    pub(crate) ball_omega_cap: f64,
    /// Whether the user gave gains; ball joints then use them per axis.
    pub(crate) overridden: bool,
}

/// The held action.
#[derive(Debug, Clone, Default)]
pub(crate) struct Command {
    pub(crate) mode: ActionMode,
    /// One value per DOF (0 for a passive one).
    pub(crate) values: Vec<f32>,
    /// One control per actuator (MuJoCo's `ctrl`), unclamped.
    pub(crate) controls: Vec<f32>,
}
