//! Rigid frames in f64 (glam): composing a description's nested poses into world
//! placements, and writing a rotation as the document's Euler angles.

use glam::{DMat3, DQuat, DVec3, EulerRot};
use gymfleet_assembly::{InertiaDef, InertialDef, Vec3};

/// A pose: `p_world = translation + rotation · p_local`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    pub(crate) translation: DVec3,
    pub(crate) rotation: DQuat,
}

impl Frame {
    pub(crate) const IDENTITY: Frame = Frame {
        translation: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
    };

    /// `self ∘ local`: a frame given in `self`'s coordinates, in `self`'s parent's.
    pub(crate) fn then(&self, local: &Frame) -> Frame {
        Frame {
            translation: self.translation + self.rotation * local.translation,
            rotation: (self.rotation * local.rotation).normalize(),
        }
    }

    /// A point given in this frame, in the parent's coordinates.
    pub(crate) fn point(&self, p: DVec3) -> DVec3 {
        self.translation + self.rotation * p
    }

    /// A direction given in this frame, in the parent's coordinates.
    pub(crate) fn direction(&self, d: DVec3) -> DVec3 {
        self.rotation * d
    }
}

/// The document's rotation of `q`: degrees about X, then Y, then Z, extrinsic
/// (`R = Rz · Ry · Rx`, glam's intrinsic `ZYX`).
pub(crate) fn euler_xyz_degrees(q: DQuat) -> [f64; 3] {
    let (z, y, x) = q.to_euler(EulerRot::ZYX);
    [x.to_degrees(), y.to_degrees(), z.to_degrees()]
}

/// The rotation taking local +Z onto `axis` (a unit vector), by the shortest arc.
pub(crate) fn z_onto(axis: DVec3) -> DQuat {
    DQuat::from_rotation_arc(DVec3::Z, axis)
}

/// A document's `inertial` for an instance placed at `instance` (m): `mass` (kg) with its
/// centre of mass at `at`'s origin and `tensor` (kg·m², about the centre of mass along
/// `at`'s axes), moved into the instance's frame (centre of mass in mm: `mm` per metre).
pub(crate) fn inertial_def(
    mass: f64,
    at: &Frame,
    tensor: DMat3,
    instance: &Frame,
    mm: f64,
) -> InertialDef {
    let back = instance.rotation.inverse();
    let com = back * (at.translation - instance.translation) * mm;
    let relative = DMat3::from_quat(back * at.rotation);
    let c = (relative * tensor * relative.transpose()).to_cols_array_2d();
    InertialDef {
        mass,
        center_of_mass: Some(vec3(com)),
        inertia: Some(InertiaDef {
            xx: c[0][0],
            yy: c[1][1],
            zz: c[2][2],
            xy: c[1][0],
            xz: c[2][0],
            yz: c[2][1],
        }),
    }
}

/// A vector as a document writes it.
pub(crate) fn vec3(v: DVec3) -> Vec3 {
    Vec3 {
        x: v.x,
        y: v.y,
        z: v.z,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_angles_round_trip_the_documents_convention() {
        let q = DQuat::from_rotation_z(0.3)
            * DQuat::from_rotation_y(-0.7)
            * DQuat::from_rotation_x(1.1);
        let [x, y, z] = euler_xyz_degrees(q);
        let back = DQuat::from_rotation_z(z.to_radians())
            * DQuat::from_rotation_y(y.to_radians())
            * DQuat::from_rotation_x(x.to_radians());
        assert!(
            q.abs_diff_eq(back, 1e-12) || q.abs_diff_eq(-back, 1e-12),
            "{q} vs {back}"
        );
        assert!((x - 1.1f64.to_degrees()).abs() < 1e-9);
    }

    #[test]
    fn composing_frames_places_points() {
        let parent = Frame {
            translation: DVec3::new(1.0, 0.0, 0.0),
            rotation: DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        };
        let child = Frame {
            translation: DVec3::new(1.0, 0.0, 0.0),
            rotation: DQuat::IDENTITY,
        };
        let world = parent.then(&child);
        assert!(world
            .translation
            .abs_diff_eq(DVec3::new(1.0, 1.0, 0.0), 1e-12));
        assert!(z_onto(DVec3::X)
            .mul_vec3(DVec3::Z)
            .abs_diff_eq(DVec3::X, 1e-12));
    }
}
