//! The contact work one step may ask of the solver, and what a step over it leaves.
//!
//! A step's solver cost grows with its contact points times its substeps (each point is a
//! normal row and its friction rows in every substep), and a pile of overlapping bodies
//! can find hundreds of thousands of points. [`RobotWorld::set_contact_work_limit`] bounds
//! that product: the pipeline step counts the points its collision detection leaves
//! (vendored Rapier patch 40, `IntegrationParameters::max_solver_contacts`) and, over the
//! budget, stops before the solver, so no body moves. [`RobotWorld::step`] then returns a
//! [`ContactOverload`] and the world is where the last step left it.
//!
//! A world whose substeps are pipeline steps of their own (an explicit ball-joint PD or a
//! fluid, see [`RobotWorld::step`]) detects contacts before every substep. Its first
//! detection stops the step as above. A later one can only stop it after the earlier
//! substeps moved the bodies, so when the contacts the world last had come near the budget
//! (past half of it), the step keeps a copy of the world first and goes back to it; a step
//! whose contacts grew from below half to over the whole within it stays where it stopped,
//! and [`ContactOverload::substeps_done`] says so (the env then needs a reset).

use rapier3d::geometry::ContactLoad;

use crate::world::{ContactOverload, RobotWorld};

impl RobotWorld {
    /// Bounds each step's contact work: at most `max` contact points × substeps (0: no
    /// limit). A step over it stops before its solver (see the module docs).
    pub fn set_contact_work_limit(&mut self, max: usize) {
        self.contact_work_limit = max;
        // points × substeps > max exactly when points > ⌊max / substeps⌋.
        let budget = match max {
            0 => usize::MAX,
            max => max / self.substeps.max(1) as usize,
        };
        self.pipeline_params.max_solver_contacts = budget;
        self.substep_params.max_solver_contacts = budget;
    }

    /// The limit [`RobotWorld::set_contact_work_limit`] set (0: none).
    pub fn contact_work_limit(&self) -> usize {
        self.contact_work_limit
    }

    /// The contact work of the world's first step, estimated without stepping it: the
    /// contact points a collision detection of the initial state finds (on a copy), times
    /// the substeps. For refusing, at creation, a world whose very first step is over
    /// the limit.
    pub fn initial_contact_work(&self) -> (ContactLoad, usize) {
        let mut sets = (*self.initial).clone();
        self.detect_contacts(&mut sets);
        let load = sets.narrow_phase.contact_load();
        (load, load.points.saturating_mul(self.substeps as usize))
    }

    /// A collision detection of `sets` (a copy of the world's): a pipeline step of no
    /// time, without the contact budget, that moves nothing.
    pub(crate) fn detect_contacts(&self, sets: &mut crate::world::Sets) {
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
    }

    /// The overload the last pipeline step stopped for, after `substeps_done` substeps.
    pub(crate) fn overload(&self, substeps_done: u32) -> Option<ContactOverload> {
        let load = self.pipeline.0.contact_budget_exceeded()?;
        Some(ContactOverload {
            pairs: load.pairs,
            points: load.points,
            substeps: self.substeps,
            work: load.points.saturating_mul(self.substeps as usize),
            max: self.contact_work_limit,
            substeps_done,
        })
    }

    /// Before a substepped step: keeps a copy of the world to go back to when the contacts
    /// it last had are past half its budget; clears any older copy otherwise.
    pub(crate) fn keep_rollback(&mut self) {
        let budget = self.substep_params.max_solver_contacts;
        let near =
            budget != usize::MAX && self.live.narrow_phase.contact_load().points > budget / 2;
        if !near {
            self.rollback.0 = None;
            return;
        }
        match &mut self.rollback.0 {
            Some(copy) => {
                copy.0.clone_from(&self.live);
                copy.1.clone_from(&self.activations);
            }
            None => self.rollback.0 = Some(Box::new((self.live.clone(), self.activations.clone()))),
        }
    }

    /// After a substepped step stopped past its first substep: goes back to the copy
    /// [`RobotWorld::keep_rollback`] kept, if it kept one. Whether it did.
    pub(crate) fn roll_back(&mut self) -> bool {
        let Some(copy) = &self.rollback.0 else {
            return false;
        };
        self.live.clone_from(&copy.0);
        self.activations.clone_from(&copy.1);
        // The copy may have moved the sets' storage: the next step takes the ranges again.
        self.hot.ranges.clear();
        true
    }
}
