//! A validated actuator (`crate::actuators` checks and reduces the document's).

use crate::document::ActuatorKind;

/// What an actuator drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transmission {
    /// A revolute or prismatic joint (index in document order).
    Joint(usize),
    /// A fixed tendon (index in document order).
    Tendon(usize),
}

/// How an actuator's activation evolves (MuJoCo's `dyntype` and `dynprm[0]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dynamics {
    /// No activation: the force reads the control.
    None,
    /// `d act / dt = ctrl`.
    Integrator,
    /// `d act / dt = (ctrl − act) / timeconst`, Euler steps.
    Filter {
        /// Seconds, > 0.
        timeconst: f64,
    },
    /// The same filter, integrated exactly.
    FilterExact {
        /// Seconds, > 0.
        timeconst: f64,
    },
}

/// A validated actuator in MuJoCo's general form (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct Actuator {
    /// Its name.
    pub name: String,
    /// Its kind as written.
    pub kind: ActuatorKind,
    /// What it drives.
    pub transmission: Transmission,
    /// Length = gear × the joint's position or the tendon's length; the joint (or each
    /// of the tendon's joints, times its coefficient) gets gear × the force.
    pub gear: f64,
    /// Controls are clamped into it.
    pub ctrl_range: Option<[f64; 2]>,
    /// The force is clamped into it.
    pub force_range: Option<[f64; 2]>,
    /// The activation is clamped into it.
    pub act_range: Option<[f64; 2]>,
    /// `[constant, per length, per velocity]`.
    pub gain: [f64; 3],
    /// `[constant, per length, per velocity]`; with `dampratio`, `bias[2]` is set when the
    /// world is built.
    pub bias: [f64; 3],
    /// The activation's dynamics.
    pub dynamics: Dynamics,
    /// A damping ratio from which the world sets `bias[2]` (MuJoCo's `dampratio`):
    /// `−dampratio · 2 · √(kp · m)`, `m` the actuator's reflected inertia at the
    /// document's pose.
    pub dampratio: Option<f64>,
}

impl Actuator {
    /// Whether it has an activation (a state of its own).
    pub fn has_activation(&self) -> bool {
        self.dynamics != Dynamics::None
    }

    /// Whether its force changes within a step under a held control: through its length
    /// or velocity, or its activation.
    pub fn depends_on_state(&self) -> bool {
        self.has_activation()
            || self.gain[1] != 0.0
            || self.gain[2] != 0.0
            || self.bias[1] != 0.0
            || self.bias[2] != 0.0
            || self.dampratio.is_some()
    }
}
