//! *(ext)* Actuators: what drives a joint or a tendon, as MuJoCo's `<actuator>` elements
//! do. A document's actions are then, after the values of the joints it actuates directly,
//! one control value per actuator in list order (MuJoCo's `ctrl`), whatever the action
//! type.

use serde::{Deserialize, Serialize};

/// An actuator's kind: MuJoCo's shortcuts, or `general` with its gain, bias and dynamics
/// written out.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ActuatorKind {
    /// A force or torque of `gear × ctrl` (MuJoCo's `<motor>`).
    #[default]
    Motor,
    /// A position servo: `kp · (ctrl − length) − kv · velocity` (`<position>`).
    Position,
    /// A velocity servo: `kv · (ctrl − velocity)` (`<velocity>`).
    Velocity,
    /// An integrated-velocity servo: the activation integrates ctrl, and the servo holds
    /// the length at it (`<intvelocity>`).
    Intvelocity,
    /// A damper whose coefficient ctrl scales: `−kv · ctrl · velocity` (`<damper>`).
    Damper,
    /// A pneumatic or hydraulic cylinder: a first-order filter on ctrl, times its area,
    /// plus a bias (`<cylinder>`).
    Cylinder,
    /// `gain · input + bias`, each affine in length and velocity, the input ctrl or an
    /// activation (`<general>`).
    General,
}

impl ActuatorKind {
    /// The name as written.
    pub fn as_str(self) -> &'static str {
        match self {
            ActuatorKind::Motor => "motor",
            ActuatorKind::Position => "position",
            ActuatorKind::Velocity => "velocity",
            ActuatorKind::Intvelocity => "intvelocity",
            ActuatorKind::Damper => "damper",
            ActuatorKind::Cylinder => "cylinder",
            ActuatorKind::General => "general",
        }
    }
}

/// How an actuator's activation evolves (MuJoCo's `dyntype`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DynamicsKind {
    /// No activation: the force reads ctrl directly.
    #[default]
    None,
    /// `d act / dt = ctrl`.
    Integrator,
    /// `d act / dt = (ctrl − act) / timeconst`, integrated by Euler steps.
    Filter,
    /// The same filter, integrated exactly over each step.
    Filterexact,
}

/// One actuator. Lengths and velocities are SI (m or rad, m/s or rad/s) whatever the
/// document's units, as MuJoCo's: an actuator's length is `gear ×` its joint's position
/// (as observed, `reference` included) or its tendon's length.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorDef {
    /// The actuator's name (unique among actuators).
    pub name: String,
    /// Its kind; default `motor`.
    #[serde(rename = "type", default, skip_serializing_if = "is_motor")]
    pub kind: ActuatorKind,
    /// The revolute or prismatic joint it drives (or `tendon`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint: Option<String>,
    /// The fixed tendon it pulls, spreading its force over the tendon's joints by their
    /// coefficients (or `joint`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tendon: Option<String>,
    /// The transmission's gear: length = gear × the joint's position or the tendon's
    /// length, and the joint gets gear × the force; default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gear: Option<f64>,
    /// Controls are clamped into `[min, max]` (MuJoCo's `ctrlrange` with `ctrllimited`);
    /// default unclamped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ctrl_range: Option<[f64; 2]>,
    /// The force is clamped into `[min, max]` (`forcerange`); default unclamped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force_range: Option<[f64; 2]>,
    /// The activation is clamped into `[min, max]` (`actrange`; actuators with an
    /// activation only); default unclamped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub act_range: Option<[f64; 2]>,
    /// Position gain (`position`, `intvelocity`; default 1), N/m or N·m/rad per gear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kp: Option<f64>,
    /// Velocity gain (`position`, `intvelocity`: default 0; `velocity`: default 1;
    /// `damper`: default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kv: Option<f64>,
    /// Instead of `kv`, the damping as a ratio of critical damping for the actuator's
    /// reflected inertia at the document's pose (`position`, `intvelocity`, and a
    /// `general` whose `gain[0] = −bias[1]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dampratio: Option<f64>,
    /// The activation filter's time constant, s (`position`: 0, none; `cylinder`: 1;
    /// `general` with a filter: 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timeconst: Option<f64>,
    /// A cylinder's area (default 1), m².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub area: Option<f64>,
    /// Instead of `area`, a cylinder's bore, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter: Option<f64>,
    /// `general`: the gain, `[constant, per length, per velocity]`; default `[1, 0, 0]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gain: Option<[f64; 3]>,
    /// `general` and `cylinder`: the bias force, `[constant, per length, per
    /// velocity]`; default zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias: Option<[f64; 3]>,
    /// `general`: the activation dynamics; default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamics: Option<DynamicsKind>,
}

fn is_motor(kind: &ActuatorKind) -> bool {
    *kind == ActuatorKind::Motor
}

impl ActuatorDef {
    /// A motor named `name` on `joint`, every option unset.
    pub fn motor(name: impl Into<String>, joint: impl Into<String>) -> Self {
        ActuatorDef {
            name: name.into(),
            kind: ActuatorKind::Motor,
            joint: Some(joint.into()),
            tendon: None,
            gear: None,
            ctrl_range: None,
            force_range: None,
            act_range: None,
            kp: None,
            kv: None,
            dampratio: None,
            timeconst: None,
            area: None,
            diameter: None,
            gain: None,
            bias: None,
            dynamics: None,
        }
    }
}
