//! Fixed tendons: a length Σ coef · q over revolute and prismatic joints (SI, positions as
//! observed: `reference` included), as MuJoCo's `<tendon><fixed>`. A tendon with stiffness
//! or damping pulls on its joints: the force f = −k·(length − rest) − b·rate acts on each
//! joint as coef · f (MuJoCo's passive tendon force through the tendon's Jacobian). It
//! depends on the state, so a world with such a tendon recomputes it before every substep.
//! A tendon's range is a hard limit on its length, enforced with the joints' hard stops
//! (vendored patch 20; MuJoCo's limit is soft).

use std::collections::HashMap;

use gymfleet_assembly::Assembly;
use rapier3d::dynamics::{MultibodyIndex, MultibodyLinearLimit};
use rapier3d::math::Real;

use crate::error::{PhysicsError, Result};
use crate::units::to_si;
use crate::world::{JointSlot, RobotWorld, Sets, TendonSlot};

impl TendonSlot {
    pub(crate) fn has_force(&self) -> bool {
        self.stiffness > 0.0 || self.damping > 0.0
    }
}

/// The assembly's tendons over the world's DOFs (`first_dof` of each document joint).
pub(crate) fn tendon_slots(
    assembly: &Assembly,
    first_dof: &[usize],
    references_si: &[f64],
) -> Vec<TendonSlot> {
    assembly
        .tendons
        .iter()
        .map(|t| {
            let dofs: Vec<(usize, f64)> =
                t.joints.iter().map(|&(j, c)| (first_dof[j], c)).collect();
            let at_pose: f64 = dofs.iter().map(|&(d, c)| c * references_si[d]).sum();
            TendonSlot {
                stiffness: t.stiffness,
                damping: t.damping,
                rest: t.spring_length.unwrap_or(at_pose),
                dofs,
            }
        })
        .collect()
}

/// Puts each ranged tendon's limits on its multibody (vendored patch 20: enforced after
/// every substep with the joints' hard stops): bounds on Σ coef · coordinate, the
/// references taken off. A tendon's joints must be in one kinematic tree.
pub(crate) fn set_tendon_limits(
    assembly: &Assembly,
    joints: &[JointSlot],
    references_si: &[f64],
    sets: &mut Sets,
) -> Result<()> {
    let mut by_multibody: HashMap<MultibodyIndex, Vec<MultibodyLinearLimit>> = HashMap::new();
    for t in &assembly.tendons {
        let Some([lo, hi]) = t.range else { continue };
        let first = joints[t.joints[0].0].multibody;
        if t.joints.iter().any(|&(j, _)| joints[j].multibody != first) {
            return Err(PhysicsError::BadOption {
                field: "assembly.tendons",
                reason: format!(
                    "tendon {:?} has a range, and its joints are in different kinematic trees; a ranged tendon's joints must share one",
                    t.name
                ),
            });
        }
        let offset: f64 = t
            .joints
            .iter()
            .map(|&(j, c)| c * references_si[joints[j].first_dof])
            .sum();
        by_multibody
            .entry(first)
            .or_default()
            .push(MultibodyLinearLimit {
                dofs: t
                    .joints
                    .iter()
                    .map(|&(j, c)| (joints[j].link, joints[j].in_link(0), c as Real))
                    .collect(),
                min: (lo - offset) as Real,
                max: (hi - offset) as Real,
            });
    }
    for (multibody, limits) in by_multibody {
        if let Some(mb) = sets.multibody_joints.get_multibody_mut(multibody) {
            mb.set_linear_limits(limits);
        }
    }
    Ok(())
}

impl RobotWorld {
    /// Number of fixed tendons.
    pub fn num_tendons(&self) -> usize {
        self.tendons.len()
    }

    /// Tendon `k`'s length and rate of change, SI (MuJoCo's `ten_length`, `ten_velocity`).
    pub fn tendon_state(&self, k: usize) -> (f64, f64) {
        self.combined_state(&self.tendons[k].dofs)
    }

    /// Σ coef · q and Σ coef · q̇ over `(DOF, coef)` pairs of revolute and prismatic DOFs,
    /// SI: a tendon's or an actuator's length and velocity.
    pub(crate) fn combined_state(&self, pairs: &[(usize, f64)]) -> (f64, f64) {
        let mut length = 0.0;
        let mut rate = 0.0;
        for &(dof, coef) in pairs {
            let (q, v) = self.scalar_dof_si(dof);
            length += coef * q;
            rate += coef * v;
        }
        (length, rate)
    }

    /// Adds `coef × force` to the generalized force of each `(DOF, coef)` pair's DOF (after
    /// `apply_efforts` has written the commanded ones): a tendon's or an actuator's pull.
    pub(crate) fn add_combined_force(&mut self, pairs: &[(usize, f64)], force: f64) {
        for &(dof, coef) in pairs {
            let slot = &self.joints[self.dofs[dof].joint];
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(first) = mb.link(slot.link).map(|link| link.assembly_id()) else {
                continue;
            };
            mb.applied_forces_mut()[slot.link_dof(first, 0)] += (coef * force) as Real;
        }
    }

    /// A revolute or prismatic DOF's position (its reference included) and velocity, SI.
    pub(crate) fn scalar_dof_si(&self, dof: usize) -> (f64, f64) {
        let d = &self.dofs[dof];
        let slot = &self.joints[d.joint];
        let Some(mb) = self.live.multibody_joints.get_multibody(slot.multibody) else {
            return (0.0, 0.0);
        };
        let Some(link) = mb.link(slot.link) else {
            return (0.0, 0.0);
        };
        let q = link.joint().coords()[slot.coord(0)];
        let v = mb.joint_velocity(link)[slot.in_link(0)];
        (f64::from(q) + to_si(d.kind, d.reference), f64::from(v))
    }

    /// Adds every springy tendon's pull to its joints' generalized forces (after
    /// [`RobotWorld::apply_efforts`] has written the commanded ones).
    pub(crate) fn apply_tendon_forces(&mut self) {
        for k in 0..self.tendons.len() {
            if !self.tendons[k].has_force() {
                continue;
            }
            let (length, rate) = self.tendon_state(k);
            let t = &self.tendons[k];
            let force = -t.stiffness * (length - t.rest) - t.damping * rate;
            let dofs = std::mem::take(&mut self.tendons[k].dofs);
            self.add_combined_force(&dofs, force);
            self.tendons[k].dofs = dofs;
        }
    }
}
