//! Domain randomisation: an episode's scale factors ([`Draws`]) applied to the world
//! after a reset — each instance's mass (through its density) and friction, each joint's
//! damping and PD gains. Default gains are recomputed from the drawn masses (at the
//! initial pose, as when the world was built), so they stay critically damped; explicit
//! gains are scaled as given. Drawing the factors is the env's job (its seeded stream).

use rapier3d::prelude::*;

use crate::actuation::pd_gains_from_load;
use crate::world::RobotWorld;

/// One episode's scale factors; 1.0 leaves a value as the document has it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Draws {
    /// Per instance, in document order: multiplies its mass (density).
    pub mass: Vec<f64>,
    /// Per instance: multiplies its friction coefficient.
    pub friction: Vec<f64>,
    /// Per joint, in document order: multiplies its damping.
    pub damping: Vec<f64>,
    /// Per joint: multiplies its PD gains (`kp` and `kd`).
    pub gain: Vec<f64>,
}

impl Draws {
    /// Factors of 1 for a world of `instances` instances and `joints` joints.
    pub fn identity(instances: usize, joints: usize) -> Self {
        Draws {
            mass: vec![1.0; instances],
            friction: vec![1.0; instances],
            damping: vec![1.0; joints],
            gain: vec![1.0; joints],
        }
    }
}

impl RobotWorld {
    /// Applies an episode's factors. Call right after [`RobotWorld::reset`] (before any
    /// start offsets), so that default gains are recomputed at the initial pose.
    ///
    /// # Panics
    ///
    /// If the draws' lengths do not match the world's instances and joints.
    pub fn apply_draws(&mut self, draws: &Draws) {
        assert_eq!(
            draws.mass.len(),
            self.bodies.len(),
            "one mass factor per instance"
        );
        assert_eq!(
            draws.damping.len(),
            self.joints.len(),
            "one damping factor per joint"
        );
        self.draw_masses_and_friction(draws);
        let inertia = self.draw_damping(draws);
        self.draw_gains(draws, &inertia);
        self.configure_motors();
    }

    /// Each collider's mass (its exact mass properties or its density) and friction, and
    /// the given masses, scaled by their instance's factors.
    fn draw_masses_and_friction(&mut self, draws: &Draws) {
        for (i, &handle) in self.colliders.iter().enumerate() {
            if let Some(collider) = self.live.colliders.get_mut(handle) {
                match self.base.exact[i] {
                    Some(exact) => {
                        let mut scaled = exact;
                        scaled.set_mass(exact.mass() * draws.mass[i] as Real, true);
                        collider.set_mass_properties(scaled);
                    }
                    None => collider.set_density(self.base.density[i] * draws.mass[i] as Real),
                }
                collider.set_friction(self.base.friction[i] * draws.friction[i] as Real);
            }
            self.given_now[i] = self.base.given[i].map(|given| {
                let mut scaled = given;
                scaled.set_mass(given.mass() * draws.mass[i] as Real, true);
                scaled
            });
        }
        crate::colliders::set_given_masses(
            &mut self.live,
            &self.bodies,
            &self.owners,
            &self.placements,
            &self.given_now,
            true,
        );
        self.update_own_props();
    }

    /// Each DOF's damping scaled by its joint's factor; returns each DOF's effective
    /// inertia under the new masses (0 where the gains are overridden: it is not needed).
    fn draw_damping(&mut self, draws: &Draws) -> Vec<f64> {
        let mut inertia = vec![0.0; self.dofs.len()];
        let mut inverse_inertias: Vec<(MultibodyIndex, DVector)> = Vec::new();
        for (j, slot) in self.joints.iter().enumerate() {
            if slot.closing.is_some() {
                continue; // A loop-closing joint (`loops.rs`).
            }
            let n = slot.kind.dof();
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(first) = mb.link(slot.link).map(|l| l.assembly_id()) else {
                continue;
            };
            for k in 0..n {
                let dof = slot.first_dof + k;
                mb.damping_mut()[slot.link_dof(first, k)] =
                    self.base.damping[dof] * draws.damping[j] as Real;
            }
            if !self.gains.overridden && n > 0 {
                // One factorisation per multibody, shared by all of its joints.
                let inv = match inverse_inertias
                    .iter()
                    .position(|(m, _)| *m == slot.multibody)
                {
                    Some(i) => &inverse_inertias[i].1,
                    None => {
                        let inv = mb.dof_inverse_inertia(&self.live.bodies);
                        inverse_inertias.push((slot.multibody, inv));
                        &inverse_inertias[inverse_inertias.len() - 1].1
                    }
                };
                for k in 0..n {
                    let inv_i = f64::from(inv[slot.link_dof(first, k)]);
                    inertia[slot.first_dof + k] = if inv_i > 0.0 { 1.0 / inv_i } else { 0.0 };
                }
            }
        }
        inertia
    }

    /// Each DOF's PD gains (from its load under `inertia`, or the overriding ones) scaled
    /// by its joint's factor.
    fn draw_gains(&mut self, draws: &Draws, inertia: &[f64]) {
        let loads = if self.gains.overridden {
            Vec::new()
        } else {
            crate::loads::dof_loads(&self.live, &self.joints, &self.dofs, inertia, self.gravity)
        };
        for (j, slot) in self.joints.iter().enumerate() {
            if slot.closing.is_some() {
                continue; // Passive: no gains.
            }
            for k in 0..slot.kind.dof() {
                let d = slot.first_dof + k;
                let (kp, kd, kv) = if self.gains.overridden {
                    (self.base.kp[d], self.base.kd[d], self.base.kv[d])
                } else {
                    pd_gains_from_load(loads[d], self.dofs[d].kind)
                };
                self.dofs[d].kp = kp * draws.gain[j];
                self.dofs[d].kd = kd * draws.gain[j];
                self.dofs[d].kv = kv * draws.gain[j];
            }
        }
    }
}
