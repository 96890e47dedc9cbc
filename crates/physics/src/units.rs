//! A DOF's values in the user's units (degrees, millimetres) and in SI (radians, metres).

use gymfleet_assembly::{DofKind, MM_PER_M};

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
