//! Stepping a world ([`RobotWorld::step`]): one Rapier pipeline step per env step, or one
//! per substep where efforts depend on the state or contacts are MuJoCo's.

use super::{ContactOverload, RobotWorld};

impl RobotWorld {
    /// Whether each substep is a pipeline step of its own (see [`RobotWorld::step`]).
    pub(crate) fn steps_by_substep(&self) -> bool {
        self.soft_contacts || self.has_state_dependent_efforts()
    }

    /// Advances the world by one step of `dt`, holding the current command.
    ///
    /// The step is one Rapier pipeline step (collision detection once, then `substeps`
    /// solver substeps, each integrating the multibody dynamics with the joint efforts,
    /// motors, contacts and hard stops). Each substep is instead a pipeline step of its own
    /// where an effort depends on the state (the explicit ball-joint PD under targets, a
    /// fluid's drag, a springy tendon, a state-dependent actuator: recomputed before every
    /// substep), and where contacts are MuJoCo's compliant ones, which MuJoCo detects at
    /// every timestep: detected once per step, a contact that a step's motion opens (a
    /// capsule landing on one end, then tipping onto the other) is missing from its later
    /// substeps, and a spinning capsule dropped at 1.5 m/s came off the floor at −8.5 rad/s
    /// where MuJoCo's leaves at 1.3 (`test_soft_contacts.py`).
    ///
    /// A step whose contacts ask for more solver work than
    /// [`RobotWorld::set_contact_work_limit`] allows stops before its solver and returns
    /// the [`ContactOverload`]; the world is then where the last step left it (see
    /// `contact_budget.rs` for the one exception, [`ContactOverload::substeps_done`]).
    pub fn step(&mut self) -> Result<(), ContactOverload> {
        self.clear_limit_impulses();
        self.keep_motion();
        if self.steps_by_substep() {
            self.keep_rollback();
            let h = f64::from(self.substep_params.dt);
            for k in 0..self.substeps {
                self.move_mocap_bodies(self.substeps - k);
                self.apply_efforts();
                self.apply_fluid();
                self.pipeline_step(true);
                // The links' body velocities as the substep left them (the solver leaves
                // them one substep old), which the next substep's facet rows read: five
                // substeps step then as five steps of one do
                // (`bench/journal/2026-12-08-pyramid-facets.md`).
                self.refresh_body_velocities();
                if k > 0 && self.pipeline.0.contact_budget_exceeded().is_some() {
                    let done = if self.roll_back() { 0 } else { k };
                    return Err(self.overload(done).expect("the budget was exceeded"));
                }
                if let Some(overload) = self.overload(0) {
                    return Err(overload);
                }
                self.advance_activations(h);
            }
        } else {
            self.move_mocap_bodies(1);
            self.apply_efforts();
            self.pipeline_step(false);
            if let Some(overload) = self.overload(0) {
                return Err(overload);
            }
        }
        self.refresh_body_velocities();
        self.age_hot_ranges();
        Ok(())
    }

    /// The links' body velocities from the final generalized velocities (vendored patch
    /// 19: the solver leaves them one substep old).
    fn refresh_body_velocities(&mut self) {
        let s = &mut self.live;
        let mut last = None;
        for slot in self
            .joints
            .iter()
            .filter(|j| j.closing.is_none())
            .map(|j| j.multibody)
            .chain(self.free_roots.iter().map(|r| r.multibody))
        {
            if last == Some(slot) {
                continue;
            }
            last = Some(slot);
            if let Some(mb) = s.multibody_joints.get_multibody_mut_internal(slot) {
                mb.update_rigid_body_velocities(&mut s.bodies);
            }
        }
    }

    /// Starts the step's accumulation of the hard limits' impulses
    /// ([`RobotWorld::limit_force`]).
    fn clear_limit_impulses(&mut self) {
        let mut last = None;
        for slot in &self.joints {
            if slot.kind.dof() == 0 || slot.closing.is_some() || last == Some(slot.multibody) {
                continue;
            }
            last = Some(slot.multibody);
            if let Some(mb) = self
                .live
                .multibody_joints
                .get_multibody_mut_internal(slot.multibody)
            {
                mb.clear_hard_limit_impulses();
            }
        }
    }

    fn pipeline_step(&mut self, one_substep: bool) {
        let params = if one_substep {
            &self.substep_params
        } else {
            &self.pipeline_params
        };
        let s = &mut self.live;
        self.pipeline.0.step(
            self.gravity,
            params,
            &mut s.islands,
            &mut s.broad_phase,
            &mut s.narrow_phase,
            &mut s.bodies,
            &mut s.colliders,
            &mut s.impulse_joints,
            &mut s.multibody_joints,
            &mut s.soft_bodies,
            &mut s.ccd,
            &self.contact_filter,
            &(),
        );
    }
}
