//! Hard stops. Rapier's multibody limit constraint engages only once a joint has
//! already crossed its limit, so under a large effort a joint could pass it by tens of
//! degrees within one substep (the seed arm's elbow: 42° past its stop at 0.25 N·m).
//! After every substep, a limited DOF found past its limit is put back on it, and its
//! outward velocity is removed by an inelastic impulse through the multibody's mass
//! matrix, which also moves the coupled DOFs as the impact would.

use rapier3d::math::DVector;
use rapier3d::prelude::*;

use gymfleet_assembly::DofKind;

use crate::world::RobotWorld;

impl RobotWorld {
    /// Puts every limited DOF that is past its limit back on it; see the module docs.
    pub(crate) fn enforce_limits(&mut self) {
        let mut fixed: Vec<MultibodyIndex> = Vec::new();
        for slot in &self.joints {
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(link) = mb.link(slot.link) else {
                continue;
            };
            let first = link.assembly_id();
            let coords = link.joint().coords();
            for k in 0..slot.kind.dof() {
                let dof = &self.dofs[slot.first_dof + k];
                let Some([min, max]) = dof.limits else {
                    continue;
                };
                // The joint's own coordinate, as `readout` reads it: slide, then turn.
                let (position, min, max) = match dof.kind {
                    DofKind::Linear => (coords[0], (min / 1000.0) as Real, (max / 1000.0) as Real),
                    DofKind::Angular => (
                        coords[3],
                        min.to_radians() as Real,
                        max.to_radians() as Real,
                    ),
                };
                let excess = if position > max {
                    position - max
                } else if position < min {
                    position - min
                } else {
                    continue;
                };
                let index = first + k;
                let mut disp = vec![0.0; mb.ndofs()];
                disp[index] = -excess;
                mb.apply_displacements(&disp);
                stop_outward_velocity(mb, index, excess.signum());
                if !fixed.contains(&slot.multibody) {
                    fixed.push(slot.multibody);
                }
            }
        }
        for index in fixed {
            if let Some(mb) = self.live.multibody_joints.get_multibody_mut(index) {
                mb.forward_kinematics(&self.live.bodies, false);
                mb.update_rigid_bodies(&mut self.live.bodies, true);
            }
        }
    }
}

/// If DOF `index` moves in direction `outward`, applies the generalized impulse along it
/// that brings its velocity to zero: `Δv = M⁻¹·e·p` with `p = -v / (M⁻¹)ᵢᵢ`.
fn stop_outward_velocity(mb: &mut Multibody, index: usize, outward: Real) {
    let v = mb.generalized_velocity()[index];
    if v * outward <= 0.0 {
        return;
    }
    let mut response = DVector::zeros(mb.ndofs());
    response[index] = 1.0;
    if !mb.inv_augmented_mass().solve_mut(&mut response) || response[index] <= 0.0 {
        // A singular mass matrix: fall back to stopping this DOF alone.
        mb.generalized_velocity_mut()[index] = 0.0;
        return;
    }
    let impulse = -v / response[index];
    let mut velocities = mb.generalized_velocity_mut();
    velocities.axpy(impulse, &response, 1.0);
}
