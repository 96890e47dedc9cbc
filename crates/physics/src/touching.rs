//! Whether any two colliders overlap in the world's current state (MuJoCo's `ncon > 0`
//! after `mj_forward`), for the Control Suite's starts that are drawn again until nothing
//! touches (dm_control's finger, ball-in-cup and humanoid).

use rapier3d::geometry::PairContacts;

use crate::world::RobotWorld;

impl RobotWorld {
    /// Whether a collision detection of the state now (on a copy: the world is not
    /// changed) finds a contact point with a negative distance between two colliders the
    /// contact rules let touch.
    pub fn penetrating(&self) -> bool {
        let mut sets = self.live.clone();
        let mut params = self.pipeline_params;
        params.dt = 0.0;
        params.max_solver_contacts = usize::MAX;
        let mut pipeline = rapier3d::pipeline::PhysicsPipeline::new();
        pipeline.step(
            self.gravity,
            &params,
            &mut sets.islands,
            &mut sets.broad_phase,
            &mut sets.narrow_phase,
            &mut sets.bodies,
            &mut sets.colliders,
            &mut sets.impulse_joints,
            &mut sets.multibody_joints,
            &mut sets.soft_bodies,
            &mut sets.ccd,
            &self.contact_filter,
            &(),
        );
        let touching = sets.narrow_phase.contact_pairs().any(|pair| {
            let PairContacts::Rigid(rigid) = &pair.contacts else {
                return false;
            };
            rigid
                .manifolds
                .iter()
                .any(|m| m.data.solver_contacts.iter().any(|c| c.dist < 0.0))
        });
        touching
    }
}
