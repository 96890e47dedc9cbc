//! A DOF's values in the user's units (degrees, millimetres) and in SI (radians, metres).

use gymfleet_assembly::{DofKind, MM_PER_M};

/// The units values are read out in: the document's (degrees, millimetres) or SI
/// (radians, metres). Forces and torques are SI in both.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Units {
    /// Degrees and millimetres (and deg/s, mm/s), as documents write them.
    #[default]
    Document,
    /// Radians and metres (and rad/s, m/s), as MuJoCo and Gymnasium report them.
    Si,
}

impl Units {
    /// A length (or linear velocity) in metres, in these units.
    pub fn length(self, metres: f64) -> f64 {
        match self {
            Units::Document => to_mm(metres),
            Units::Si => metres,
        }
    }

    /// An angle (or angular velocity) in radians, in these units.
    pub fn angle(self, radians: f64) -> f64 {
        match self {
            Units::Document => radians.to_degrees(),
            Units::Si => radians,
        }
    }

    /// A DOF's SI value (rad or m, and their rates), in these units.
    pub fn dof(self, kind: DofKind, si: f64) -> f64 {
        match kind {
            DofKind::Angular => self.angle(si),
            DofKind::Linear => self.length(si),
        }
    }

    /// A DOF's value as a document writes it (deg or mm), in these units.
    pub fn from_document(self, kind: DofKind, user: f64) -> f64 {
        match self {
            Units::Document => user,
            Units::Si => to_si(kind, user),
        }
    }

    /// A value in these units as a document writes it (deg or mm).
    pub fn to_document(self, kind: DofKind, value: f64) -> f64 {
        match self {
            Units::Document => value,
            Units::Si => from_si(kind, value),
        }
    }

    /// A DOF's value in these units, in SI (rad or m, and their rates).
    pub fn to_si(self, kind: DofKind, value: f64) -> f64 {
        match self {
            Units::Document => to_si(kind, value),
            Units::Si => value,
        }
    }

    /// The lower-case name: `"document"` or `"si"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Units::Document => "document",
            Units::Si => "si",
        }
    }
}

/// A position (or velocity, target, offset) of a DOF in user units (deg or mm) in SI
/// (rad or m).
pub(crate) fn to_si(kind: DofKind, user: f64) -> f64 {
    match kind {
        DofKind::Angular => user.to_radians(),
        DofKind::Linear => user / MM_PER_M,
    }
}

/// A position of a DOF in SI (rad or m), in user units (deg or mm).
pub(crate) fn from_si(kind: DofKind, si: f64) -> f64 {
    match kind {
        DofKind::Angular => si.to_degrees(),
        DofKind::Linear => si * MM_PER_M,
    }
}

/// A length in mm, in m.
pub(crate) fn to_m(millimetres: f64) -> f64 {
    millimetres / MM_PER_M
}

/// A length in m, in mm.
pub(crate) fn to_mm(metres: f64) -> f64 {
    metres * MM_PER_M
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degrees_and_millimetres_convert() {
        assert_eq!(to_si(DofKind::Angular, 180.0), std::f64::consts::PI);
        assert_eq!(to_si(DofKind::Linear, 25.0), 0.025);
        assert_eq!(to_mm(0.025), 25.0);
        assert_eq!(to_m(25.0), 0.025);
    }
}
