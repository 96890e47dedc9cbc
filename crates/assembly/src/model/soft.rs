//! MuJoCo's soft constraints of a validated assembly: a material's compliant contacts and a
//! joint's compliant limits.

/// A material's compliant contact (see `SoftContactDef`), lengths in mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoftContact {
    /// `[timeconst s, dampratio]`, or `[-stiffness, -damping]`.
    pub solref: [f64; 2],
    /// `[dmin, dmax, width mm, midpoint, power]`.
    pub solimp: [f64; 5],
    /// Mixing weight.
    pub solmix: f64,
    /// Priority.
    pub priority: i32,
    /// mm.
    pub margin: f64,
    /// mm.
    pub gap: f64,
    /// MuJoCo's pyramidal friction cone (else elliptic).
    pub pyramidal: bool,
    /// MuJoCo's `impratio`.
    pub impratio: f64,
    /// MuJoCo's `condim`: 1, 3, 4 or 6.
    pub condim: u32,
    /// Torsional friction, mm.
    pub torsional_friction: f64,
    /// Rolling friction, mm.
    pub rolling_friction: f64,
}

impl Default for SoftContact {
    /// MuJoCo's defaults.
    fn default() -> Self {
        SoftContact {
            solref: [0.02, 1.0],
            solimp: [0.9, 0.95, 1.0, 0.5, 2.0],
            solmix: 1.0,
            priority: 0,
            margin: 0.0,
            gap: 0.0,
            pyramidal: true,
            impratio: 1.0,
            condim: 3,
            torsional_friction: 5.0,
            rolling_friction: 0.1,
        }
    }
}

/// A joint's compliant limits (see `SoftLimitDef`), in radians or metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoftLimit {
    /// `[timeconst s, dampratio]`, or `[-stiffness, -damping]`.
    pub solref: [f64; 2],
    /// `[dmin, dmax, width rad or m, midpoint, power]`.
    pub solimp: [f64; 5],
    /// rad or m.
    pub margin: f64,
}
