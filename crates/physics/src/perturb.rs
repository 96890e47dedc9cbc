//! Starting an episode away from the initial pose: per-DOF position offsets applied to
//! the multibody's generalized coordinates after a reset.

use rapier3d::prelude::*;

use crate::units::{to_si, Units};
use crate::world::RobotWorld;

impl RobotWorld {
    /// [`RobotWorld::reset`], then offsets every DOF's position by `offsets[k]` (deg or
    /// mm, in [`RobotWorld::dofs`] order; a rotation vector in deg for ball joints), the
    /// position it reaches (from the joint's initial one) clamped into the DOF's limits. Velocities stay zero. Offsets of zero leave the
    /// state bit-for-bit as a plain reset does. Joints on a kinematic loop keep the
    /// document's pose (their offsets are ignored), so that the loop starts closed.
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
            if n == 0 || slot.on_loop {
                // A joint on a kinematic loop keeps the document's pose and rest: moved
                // alone, it would open the loop (`loops.rs`).
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
                disp[slot.link_dof(first, k)] = to_si(dof.kind, offset) as Real;
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
    /// start an episode moving. The links' velocities follow at the next substep. Joints on
    /// a kinematic loop keep theirs (a loop moves as one).
    ///
    /// # Panics
    ///
    /// If `velocities.len()` differs from the number of DOFs.
    pub fn set_dof_velocities(&mut self, units: Units, velocities: &[f64]) {
        assert_eq!(velocities.len(), self.dofs.len(), "one velocity per DOF");
        for slot in &self.joints {
            let n = slot.kind.dof();
            if n == 0 || slot.on_loop {
                // A joint on a kinematic loop keeps the document's pose and rest: moved
                // alone, it would open the loop (`loops.rs`).
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
                all[slot.link_dof(first, k)] =
                    units.to_si(dof.kind, velocities[slot.first_dof + k]) as Real;
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

/// Floats in a floating base's perturbation ([`RobotWorld::perturb_base`]).
pub const BASE_NOISE_LEN: usize = 13;

impl RobotWorld {
    /// Moves a floating base away from where it is, as MuJoCo's free joint noise does:
    /// `noise[0..3]` offsets the position of its frame (m, world), `noise[3..7]` is added to
    /// its orientation quaternion `[w, x, y, z]` (then normalized), `noise[7..10]` is its
    /// frame origin's linear velocity (m/s, world) and `noise[10..13]` its angular velocity
    /// in its own frame (rad/s; MuJoCo's free-joint `qvel`). The tree's joints keep their
    /// coordinates and follow. With `keyed` (the keyframe the base was placed by,
    /// [`RobotWorld::place_base`]), its velocity is added to the noise's. Nothing happens
    /// without a floating base.
    pub fn perturb_base(
        &mut self,
        noise: &[f64; BASE_NOISE_LEN],
        keyed: Option<&gymfleet_assembly::BaseKey>,
    ) {
        if !self.floating_base {
            return;
        }
        let handle = self.bodies[0];
        let pose = *self.live.bodies[handle].position();
        let q = pose.rotation;
        let (w, x, y, z) = (
            f64::from(q.w) + noise[3],
            f64::from(q.x) + noise[4],
            f64::from(q.y) + noise[5],
            f64::from(q.z) + noise[6],
        );
        let norm = (w * w + x * x + y * y + z * z).sqrt();
        let rotation = if norm > 0.0 && norm.is_finite() {
            Rotation::from_xyzw(
                (x / norm) as Real,
                (y / norm) as Real,
                (z / norm) as Real,
                (w / norm) as Real,
            )
        } else {
            q
        };
        let t = pose.translation;
        let translation = Vector::new(
            t.x + noise[0] as Real,
            t.y + noise[1] as Real,
            t.z + noise[2] as Real,
        );
        self.live.bodies[handle].set_position(Pose::from_parts(translation, rotation), true);
        let mut linear = Vector::new(noise[7] as Real, noise[8] as Real, noise[9] as Real);
        let mut angular =
            rotation * Vector::new(noise[10] as Real, noise[11] as Real, noise[12] as Real);
        if let Some(key) = keyed {
            let real = |v: [f64; 3]| Vector::new(v[0] as Real, v[1] as Real, v[2] as Real);
            let spin = real(key.angular_velocity);
            // The key gives its instance origin's velocity; the base's is its body origin's.
            let instance = Pose::from_parts(translation, rotation) * self.placements[0];
            linear += real(key.linear_velocity) + spin.cross(translation - instance.translation);
            angular += spin;
        }
        self.set_base_velocity(linear, angular);
    }

    /// Turns a floating base to the orientation `q` (`[w, x, y, z]`, normalized here) about
    /// its frame's origin, at rest; the tree's joints keep their coordinates and follow
    /// (dm_control's random start of a free joint's orientation). Nothing happens without a
    /// floating base.
    pub fn turn_base(&mut self, q: [f64; 4]) {
        if !self.floating_base {
            return;
        }
        let now = self.live.bodies[self.bodies[0]].position().rotation;
        let mut noise = [0.0; BASE_NOISE_LEN];
        for (n, (target, current)) in noise[3..7]
            .iter_mut()
            .zip(q.iter().zip([now.w, now.x, now.y, now.z]))
        {
            *n = target - f64::from(current);
        }
        self.perturb_base(&noise, None);
    }

    /// Sets a floating base's velocity once its pose is set: `origin` is its body frame
    /// origin's linear velocity and `angular` its angular velocity (world). In a tree, the
    /// root's generalized velocities (the frame origin's); a base nothing is jointed to is a
    /// plain rigid body, whose velocity is its centre of mass's.
    pub(crate) fn set_base_velocity(&mut self, origin: Vector, angular: Vector) {
        let root = self
            .free_roots
            .first()
            .filter(|r| r.instance == 0)
            .map(|r| r.multibody);
        match root {
            Some(index) => {
                if let Some(mb) = self.live.multibody_joints.get_multibody_mut(index) {
                    let mut v = mb.generalized_velocity_mut();
                    for k in 0..3 {
                        v[k] = origin[k];
                        v[3 + k] = angular[k];
                    }
                }
                self.sync_bodies(&[index]);
            }
            None => {
                let rb = &mut self.live.bodies[self.bodies[0]];
                let arm = rb.center_of_mass() - rb.position().translation;
                rb.set_linvel(origin + angular.cross(arm), true);
                rb.set_angvel(angular, true);
            }
        }
    }
}
