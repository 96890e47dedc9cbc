//! gymfleet patch 40 (`PATCHES.md`): `IntegrationParameters::max_solver_contacts`. A step
//! whose collision detection leaves more solver contact points than the budget stops before
//! the solver, as a zero-length step does: no body moves, and
//! `PhysicsPipeline::contact_budget_exceeded` reports the load. Within the budget (or with
//! none) a step is what it was; `NarrowPhase::contact_load` counts what the solver gets.

use rapier3d::geometry::ContactLoad;
use rapier3d::prelude::*;

struct World {
    pipeline: PhysicsPipeline,
    islands: IslandManager,
    broad_phase: DefaultBroadPhase,
    narrow_phase: NarrowPhase,
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    ccd: CCDSolver,
    params: IntegrationParameters,
}

impl World {
    /// A ground box and `n` unit boxes resting on it, side by side.
    fn boxes_on_ground(n: usize) -> (World, Vec<RigidBodyHandle>) {
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        let ground = bodies.insert(RigidBodyBuilder::fixed());
        colliders.insert_with_parent(ColliderBuilder::cuboid(50.0, 0.5, 50.0), ground, &mut bodies);
        let handles = (0..n)
            .map(|i| {
                let body = bodies.insert(
                    RigidBodyBuilder::dynamic().translation(Vector::new(3.0 * i as f32, 0.999, 0.0)),
                );
                colliders.insert_with_parent(ColliderBuilder::cuboid(0.5, 0.5, 0.5), body, &mut bodies);
                body
            })
            .collect();
        let world = World {
            pipeline: PhysicsPipeline::new(),
            islands: IslandManager::new(),
            broad_phase: DefaultBroadPhase::new(),
            narrow_phase: NarrowPhase::new(),
            bodies,
            colliders,
            impulse_joints: ImpulseJointSet::new(),
            multibody_joints: MultibodyJointSet::new(),
            soft_bodies: SoftBodySet::new(),
            ccd: CCDSolver::new(),
            params: IntegrationParameters::default(),
        };
        (world, handles)
    }

    fn step(&mut self) {
        self.pipeline.step(
            Vector::new(0.0, -9.81, 0.0),
            &self.params,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd,
            &(),
            &(),
        );
    }

    fn state(&self, h: RigidBodyHandle) -> (Vector, Vector) {
        (self.bodies[h].translation(), self.bodies[h].linvel())
    }
}

#[test]
fn a_step_over_its_contact_budget_moves_nothing_and_says_why() {
    let (mut world, boxes) = World::boxes_on_ground(3);
    world.step();
    assert_eq!(world.pipeline.contact_budget_exceeded(), None, "no budget by default");
    let load = world.narrow_phase.contact_load();
    assert_eq!((load.pairs, load.manifolds, load.points), (3, 3, 12), "{load:?}");

    // A budget of 11 points: the next step stops before its solver.
    world.params.max_solver_contacts = 11;
    let before: Vec<_> = boxes.iter().map(|&h| world.state(h)).collect();
    world.step();
    assert_eq!(
        world.pipeline.contact_budget_exceeded(),
        Some(ContactLoad { pairs: 3, manifolds: 3, points: 12 })
    );
    let after: Vec<_> = boxes.iter().map(|&h| world.state(h)).collect();
    assert_eq!(before, after, "no body moved");

    // At 12 the step runs as an unbudgeted twin's does.
    world.params.max_solver_contacts = 12;
    let (mut twin, _) = World::boxes_on_ground(3);
    twin.step();
    world.step();
    twin.step();
    assert_eq!(world.pipeline.contact_budget_exceeded(), None);
    for &h in &boxes {
        assert_eq!(world.state(h), twin.state(h), "the stopped step left nothing behind");
    }
}
