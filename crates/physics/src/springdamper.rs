//! MuJoCo's joint `springdamper` (`mjCModel::AutoSpringDamper`): a joint's stiffness and
//! damping sized so that its DOF, alone, is a spring-mass-damper of the given time constant
//! and damping ratio: `I = 1 / (M⁻¹)ᵢᵢ` at the document's pose (MuJoCo's `dof_invweight0`,
//! armature included), `stiffness = I / (timeconst² · dampratio²)`, `damping = 2·I /
//! timeconst`. They are read off a world built once without them.

use gymfleet_assembly::Assembly;
use rapier3d::prelude::*;

use crate::world::RobotWorld;

impl RobotWorld {
    /// `assembly` with every `springdamper` joint's stiffness and damping sized from this
    /// world (built from `assembly`), its `springdamper` then cleared.
    pub(crate) fn sized_springdampers(&self, assembly: &Assembly) -> Assembly {
        // The bodies' given mass properties, as a step applies them (`actuators.rs` reads
        // the mass matrix the same way).
        let mut sets = self.live.clone();
        let handles: Vec<_> = sets.bodies.iter().map(|(h, _)| h).collect();
        for h in handles {
            if let Some(rb) = sets.bodies.get_mut(h) {
                rb.recompute_mass_properties_from_colliders(&sets.colliders);
            }
        }
        let mut sized = assembly.clone();
        let mut inverses = std::collections::HashMap::new();
        for (j, joint) in sized.joints.iter_mut().enumerate() {
            let Some([timeconst, dampratio]) = joint.springdamper.take() else {
                continue;
            };
            let slot = &self.joints[j];
            let Some(mb) = sets.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(first) = mb.link(slot.link).map(|l| l.assembly_id()) else {
                continue;
            };
            let inv: &DVector = inverses
                .entry(slot.multibody)
                .or_insert_with(|| mb.dof_inverse_inertia(&sets.bodies));
            let inverse = f64::from(inv[slot.link_dof(first, 0)]);
            let inertia = 1.0 / inverse.max(f64::from(f32::MIN_POSITIVE));
            joint.stiffness = inertia / (timeconst * timeconst * dampratio * dampratio);
            joint.damping = 2.0 * inertia / timeconst;
        }
        sized
    }
}
