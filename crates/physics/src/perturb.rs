//! Starting an episode away from the initial pose: per-DOF position offsets applied to
//! the multibody's generalized coordinates after a reset.

use rapier3d::prelude::*;

use crate::units::{to_si, Units};
use crate::world::RobotWorld;

impl RobotWorld {
    /// [`RobotWorld::reset`], then offsets every DOF's position by `offsets[k]` (deg or
    /// mm, in [`RobotWorld::dofs`] order; a rotation vector in deg for ball joints), the
    /// position it reaches (from the joint's initial one) clamped into the DOF's limits. Velocities stay zero. Offsets of zero leave the
    /// state bit-for-bit as a plain reset does.
    ///
    /// # Panics
    ///
    /// If `offsets.len()` differs from the number of DOFs.
    pub fn reset_with_offsets(&mut self, offsets: &[f64]) {
        self.reset();
        self.offset_dofs(offsets);
    }

    /// Offsets every DOF's position from where it is (see
    /// [`RobotWorld::reset_with_offsets`]); for a reset whose domain randomisation must
    /// be applied at the initial pose first.
    ///
    /// # Panics
    ///
    /// If `offsets.len()` differs from the number of DOFs.
    pub fn offset_dofs(&mut self, offsets: &[f64]) {
        assert_eq!(offsets.len(), self.dofs.len(), "one offset per DOF");
        if offsets.iter().all(|&o| o == 0.0) {
            return;
        }
        let mut touched = Vec::new();
        for slot in &self.joints {
            let n = slot.kind.dof();
            if n == 0 {
                continue;
            }
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(link) = mb.link(slot.link) else {
                continue;
            };
            let mut disp = vec![0.0; mb.ndofs()];
            let first = link.assembly_id();
            for k in 0..n {
                let dof = &self.dofs[slot.first_dof + k];
                let mut offset = offsets[slot.first_dof + k];
                // From the joint's initial position, kept within its limits.
                if let Some([min, max]) = dof.limits {
                    offset = (dof.initial + offset).clamp(min, max) - dof.initial;
                }
                disp[first + k] = to_si(dof.kind, offset) as Real;
            }
            mb.apply_displacements(&disp);
            if !touched.contains(&slot.multibody) {
                touched.push(slot.multibody);
            }
        }
        self.sync_bodies(&touched);
    }

    /// Sets every DOF's velocity (in [`RobotWorld::dofs`] order; deg/s or mm/s, rad/s or
    /// m/s in [`Units::Si`]; a ball joint's angular velocity in its joint frame), e.g. to
    /// start an episode moving. The links' velocities follow at the next substep.
    ///
    /// # Panics
    ///
    /// If `velocities.len()` differs from the number of DOFs.
    pub fn set_dof_velocities(&mut self, units: Units, velocities: &[f64]) {
        assert_eq!(velocities.len(), self.dofs.len(), "one velocity per DOF");
        for slot in &self.joints {
            let n = slot.kind.dof();
            if n == 0 {
                continue;
            }
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(first) = mb.link(slot.link).map(|l| l.assembly_id()) else {
                continue;
            };
            let mut all = mb.generalized_velocity_mut();
            for k in 0..n {
                let dof = &self.dofs[slot.first_dof + k];
                all[first + k] = units.to_si(dof.kind, velocities[slot.first_dof + k]) as Real;
            }
        }
    }

    /// After their generalized coordinates were changed outside a step: recomputes the
    /// links of `multibodies` and moves their rigid bodies (and, at the next step, their
    /// colliders) with them.
    pub(crate) fn sync_bodies(&mut self, multibodies: &[MultibodyIndex]) {
        for &index in multibodies {
            if let Some(mb) = self.live.multibody_joints.get_multibody_mut(index) {
                // The root of a floating tree is placed where its body is.
                mb.forward_kinematics(&self.live.bodies, true);
                mb.update_rigid_bodies(&mut self.live.bodies, true);
            }
        }
    }
}
