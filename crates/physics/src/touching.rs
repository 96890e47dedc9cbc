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
        self.detect_contacts(&mut sets);
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
