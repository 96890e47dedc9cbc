//! Hard stops. Rapier's multibody limit constraint engages only once a joint has
//! already crossed its limit, so under a large effort a joint could pass it by tens of
//! degrees within one substep (the seed arm's elbow: 42° past its stop at 0.25 N·m).
//! After every substep, a limited DOF found past its limit is put back on it, and its
//! outward velocity is removed by an inelastic impulse through the multibody's mass
//! matrix, which also moves the coupled DOFs as the impact would.

use rapier3d::math::DVector;
use rapier3d::prelude::*;

use gymfleet_assembly::DofKind;

use crate::perturb::to_si;
use crate::world::RobotWorld;

impl RobotWorld {
    /// Puts every limited DOF that is past its limit back on it; see the module docs.
    pub(crate) fn enforce_limits(&mut self) {
        let mut fixed: Vec<MultibodyIndex> = Vec::new();
        for slot in &self.joints {
            let dofs = &self.dofs[slot.first_dof..slot.first_dof + slot.kind.dof()];
            if dofs.iter().all(|d| d.limits.is_none()) {
                continue;
            }
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(link) = mb.link(slot.link) else {
                continue;
            };
            let first = link.assembly_id();
            let coords = link.joint().coords();
            for (k, dof) in dofs.iter().enumerate() {
                let Some([min, max]) = dof.limits else {
                    continue;
                };
                // The joint's own coordinate, as `readout` reads it: slide, then turn.
                let position = match dof.kind {
                    DofKind::Linear => coords[0],
                    DofKind::Angular => coords[3],
                };
                let (min, max) = (to_si(dof.kind, min), to_si(dof.kind, max));
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
        self.sync_bodies(&fixed);
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
