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
use crate::world::{JointSlot, PathPoint, RobotWorld, Sets, TendonSlot};

impl TendonSlot {
    pub(crate) fn has_force(&self) -> bool {
        self.stiffness > 0.0 || self.damping > 0.0
    }
}

/// The assembly's tendons over the world's DOFs (`first_dof` of each document joint) and
/// bodies (each spatial tendon's path, `paths`); a rest length left out is the length at
/// the document's pose, where `sets` holds the bodies.
pub(crate) fn tendon_slots(
    assembly: &Assembly,
    first_dof: &[usize],
    references_si: &[f64],
    paths: Vec<Vec<PathPoint>>,
    sets: &Sets,
) -> Vec<TendonSlot> {
    assembly
        .tendons
        .iter()
        .zip(paths)
        .map(|(t, path)| {
            let dofs: Vec<(usize, f64)> =
                t.joints.iter().map(|&(j, c)| (first_dof[j], c)).collect();
            let at_pose: f64 = if t.is_spatial() {
                crate::spatial::path_length(&path, sets)
            } else {
                dofs.iter().map(|&(d, c)| c * references_si[d]).sum()
            };
            TendonSlot {
                stiffness: t.stiffness,
                damping: t.damping,
                rest: t.spring_length.unwrap_or(at_pose),
                dofs,
                path,
            }
        })
        .collect()
}

/// Puts each ranged fixed tendon's limits and each coupling on its multibody (vendored
/// patches 20 and 42: enforced after every substep with the joints' hard stops): bounds on
/// Σ coef · coordinate, the references taken off (a coupling's bounds are one value: an
/// equality). A tendon's or a coupling's joints must be in one kinematic tree.
pub(crate) fn set_tendon_limits(
    assembly: &Assembly,
    joints: &[JointSlot],
    references_si: &[f64],
    sets: &mut Sets,
) -> Result<()> {
    let mut by_multibody: HashMap<MultibodyIndex, Vec<MultibodyLinearLimit>> = HashMap::new();
    // Bounds on Σ coef · coordinate.
    let mut add = |field: &'static str,
                   what: &str,
                   name: &str,
                   terms: &[(usize, f64)],
                   lo: f64,
                   hi: f64| {
        let first = joints[terms[0].0].multibody;
        if terms.iter().any(|&(j, _)| joints[j].multibody != first) {
            return Err(PhysicsError::BadOption {
                field,
                reason: format!(
                    "{what} {name:?} joins joints of different kinematic trees; its joints must share one"
                ),
            });
        }
        by_multibody
            .entry(first)
            .or_default()
            .push(MultibodyLinearLimit {
                dofs: terms
                    .iter()
                    .map(|&(j, c)| (joints[j].link, joints[j].in_link(0), c as Real))
                    .collect(),
                min: lo as Real,
                max: hi as Real,
            });
        Ok(())
    };
    for t in assembly.tendons.iter().filter(|t| !t.is_spatial()) {
        if let Some([lo, hi]) = t.range {
            // The length less the references: the coordinates' part.
            let at_zero: f64 = t
                .joints
                .iter()
                .map(|&(j, c)| c * references_si[joints[j].first_dof])
                .sum();
            add(
                "assembly.tendons",
                "ranged tendon",
                &t.name,
                &t.joints,
                lo - at_zero,
                hi - at_zero,
            )?;
        }
    }
    // A coupling's terms are displacements from the pose (where the coordinates are 0).
    for c in &assembly.couplings {
        let (name, terms) = (&c.name, &c.terms);
        add(
            "assembly.couplings",
            "coupling",
            name,
            terms,
            c.offset,
            c.offset,
        )?;
    }
    for (multibody, limits) in by_multibody {
        if let Some(mb) = sets.multibody_joints.get_multibody_mut(multibody) {
            mb.set_linear_limits(limits);
        }
    }
    Ok(())
}

impl RobotWorld {
    /// Number of tendons.
    pub fn num_tendons(&self) -> usize {
        self.tendons.len()
    }

    /// Tendon `k`'s length and rate of change, SI (MuJoCo's `ten_length`, `ten_velocity`).
    pub fn tendon_state(&self, k: usize) -> (f64, f64) {
        let t = &self.tendons[k];
        if t.path.is_empty() {
            self.combined_state(&t.dofs)
        } else {
            self.path_state(&t.path)
        }
    }

    /// Adds `force` along tendon `k` (N or N·m; positive lengthens) to its joints'
    /// generalized forces.
    pub(crate) fn add_tendon_force(&mut self, k: usize, force: f64) {
        if self.tendons[k].path.is_empty() {
            let dofs = std::mem::take(&mut self.tendons[k].dofs);
            self.add_combined_force(&dofs, force);
            self.tendons[k].dofs = dofs;
        } else {
            let path = std::mem::take(&mut self.tendons[k].path);
            self.add_path_force(&path, force);
            self.tendons[k].path = path;
        }
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
            self.add_tendon_force(k, force);
        }
    }
}
