//! MuJoCo's soft constraints in a document *(ext)*: a material's compliant contacts and a
//! joint's compliant limits (vendored Rapier patches 43 and 44).

use serde::{Deserialize, Serialize};

/// *(ext)* A material's compliant contact, MuJoCo's soft constraint: a contact pushes back
/// like a damped spring whose time constant and damping ratio are `solref`, with an
/// impedance `solimp` that grows with depth. Of two materials in contact, the one of
/// higher `priority` decides; at equal priority their parameters are mixed by `solmix`. A
/// rigid material meeting a compliant one takes its parameters.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SoftContactDef {
    /// `[timeconst s, dampratio]` (default `[0.02, 1]`), or `[-stiffness, -damping]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solref: Option<[f64; 2]>,
    /// `[dmin, dmax, width mm, midpoint, power]` (default `[0.9, 0.95, 1, 0.5, 2]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solimp: Option<[f64; 5]>,
    /// Weight in the mix with another material of the same priority (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solmix: Option<f64>,
    /// Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub priority: Option<i32>,
    /// Distance in mm below which the contact acts (default 0); two materials' add up.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
    /// Distance in mm beyond the margin in which a contact is found but pushes nothing
    /// (default 0); two materials' add up.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<f64>,
    /// MuJoCo's friction cone (default `pyramidal`, whose contacts stiffen as friction
    /// falls: as soft as `solref` says at friction 1, rigid without friction).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cone: Option<FrictionCone>,
    /// MuJoCo's `impratio` (default 1): the pyramid's friction over normal impedance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub impratio: Option<f64>,
    /// MuJoCo's `condim` (default 3): 1 frictionless, 3 sliding friction, 4 with torsional
    /// friction, 6 with rolling friction too. Of two materials the higher priority's acts,
    /// else the larger.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub condim: Option<u32>,
    /// Torsional friction in mm (default 5, MuJoCo's 0.005 m): at `condim` 4 and 6 the
    /// torque about the contact normal is at most this times the normal force.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torsional_friction: Option<f64>,
    /// Rolling friction in mm (default 0.1, MuJoCo's 0.0001 m), at `condim` 6.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_friction: Option<f64>,
}

/// *(ext)* MuJoCo's friction cone (`<option cone>`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionCone {
    /// MuJoCo's default.
    #[default]
    Pyramidal,
    /// `cone="elliptic"`.
    Elliptic,
}

/// *(ext)* A joint's compliant limits (MuJoCo's soft constraint, as in [`SoftContactDef`]).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SoftLimitDef {
    /// `[timeconst s, dampratio]` (default `[0.02, 1]`), or `[-stiffness, -damping]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solref: Option<[f64; 2]>,
    /// `[dmin, dmax, width, midpoint, power]`, the width in deg or mm (default
    /// `[0.9, 0.95, 0.0573 deg or 1 mm, 0.5, 2]`, MuJoCo's 0.001 rad or m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solimp: Option<[f64; 5]>,
    /// Distance from a limit, deg or mm, at which it starts to act (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
}
