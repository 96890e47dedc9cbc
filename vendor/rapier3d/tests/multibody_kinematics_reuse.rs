//! gymfleet patch 14 (`PATCHES.md`): a step skips the forward kinematics of a fixed-root
//! multibody that the previous step's solver left current and nothing has touched since.
//! These tests pin that the skip changes no bit, and that every way of touching a
//! multibody between steps (its links, its root body) still brings its kinematics up to date.

use rapier3d::prelude::*;

struct World {
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    pipeline: PhysicsPipeline,
    islands: IslandManager,
    broad_phase: DefaultBroadPhase,
    narrow_phase: NarrowPhase,
    ccd: CCDSolver,
    soft_bodies: SoftBodySet,
    params: IntegrationParameters,
    base: RigidBodyHandle,
    links: Vec<RigidBodyHandle>,
    joint: MultibodyJointHandle,
}

/// A fixed base and three links on revolute joints about Z, X and Z, each link a capsule
/// hanging 0.3 m off its joint so that gravity swings the chain.
fn chain() -> World {
    chain_of(1.0)
}

/// [`chain`] with capsules of `density` (at water's, the joints' default damping no longer
/// holds the links back, and they swing at metres per second).
fn chain_of(density: Real) -> World {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let mut multibody_joints = MultibodyJointSet::new();
    let base = bodies.insert(RigidBodyBuilder::fixed());
    let mut parent = base;
    let mut links = Vec::new();
    let mut joint = None;
    for (i, axis) in [Vector::Z, Vector::X, Vector::Z].into_iter().enumerate() {
        let link = bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(
            0.3 * (i + 1) as Real,
            0.0,
            0.0,
        )));
        colliders.insert_with_parent(
            ColliderBuilder::capsule_x(0.1, 0.02)
                .translation(Vector::new(0.1, 0.0, 0.0))
                .density(density),
            link,
            &mut bodies,
        );
        let anchor = if i == 0 {
            Vector::ZERO
        } else {
            Vector::new(0.3, 0.0, 0.0)
        };
        let rev = RevoluteJointBuilder::new(axis).local_anchor1(anchor);
        joint = multibody_joints.insert(parent, link, rev, true);
        links.push(link);
        parent = link;
    }
    World {
        bodies,
        colliders,
        impulse_joints: ImpulseJointSet::new(),
        multibody_joints,
        pipeline: PhysicsPipeline::new(),
        islands: IslandManager::new(),
        broad_phase: DefaultBroadPhase::new(),
        narrow_phase: NarrowPhase::new(),
        ccd: CCDSolver::new(),
        soft_bodies: SoftBodySet::new(),
        params: IntegrationParameters {
            dt: 1.0 / 240.0,
            ..IntegrationParameters::default()
        },
        base,
        links,
        joint: joint.unwrap(),
    }
}

impl World {
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

    fn multibody(&mut self) -> &mut Multibody {
        self.multibody_joints.get_mut(self.joint).unwrap().0
    }

    /// Every link body's pose and velocity, as bits.
    fn bits(&self) -> Vec<u32> {
        let mut out = Vec::new();
        for h in &self.links {
            let rb = &self.bodies[*h];
            let p = rb.position();
            for v in [p.translation, rb.linvel(), rb.angvel()] {
                out.extend([v.x, v.y, v.z].map(Real::to_bits));
            }
            let q = p.rotation;
            out.extend([q.x, q.y, q.z, q.w].map(Real::to_bits));
        }
        out
    }
}

#[test]
fn skipping_forward_kinematics_changes_no_bit() {
    let (mut reused, mut recomputed) = (chain(), chain());
    for _ in 0..300 {
        reused.step();
        // A mutable access to a link makes the next step run forward kinematics.
        let _ = recomputed.multibody().link_mut(0);
        recomputed.step();
    }
    assert_eq!(reused.bits(), recomputed.bits());
    // The chain did swing.
    let tip = reused.bodies[reused.links[2]].translation();
    assert!(
        (tip - Vector::new(0.9, 0.0, 0.0)).length() > 0.1,
        "tip at {tip:?}"
    );
}

#[test]
fn displacing_joints_between_steps_moves_the_links() {
    let (mut a, mut b) = (chain(), chain());
    for w in [&mut a, &mut b] {
        for _ in 0..20 {
            w.step();
        }
    }
    let before = a.bodies[a.links[2]].translation();
    let disp = [0.5, 0.0, 0.0];
    a.multibody().apply_displacements(&disp);
    // The explicit way: forward kinematics and the bodies' poses, before stepping.
    b.multibody().apply_displacements(&disp);
    let World {
        multibody_joints,
        bodies,
        joint,
        ..
    } = &mut b;
    let mb = multibody_joints.get_mut(*joint).unwrap().0;
    mb.forward_kinematics(bodies, true);
    mb.update_rigid_bodies(bodies, true);
    a.step();
    b.step();
    assert_eq!(a.bits(), b.bits());
    let after = a.bodies[a.links[2]].translation();
    assert!((after - before).length() > 0.2, "{before:?} -> {after:?}");
}

#[test]
fn moving_the_fixed_root_moves_the_chain() {
    let mut w = chain();
    for _ in 0..20 {
        w.step();
    }
    let before = w.bodies[w.links[2]].translation();
    let shift = Vector::new(0.0, 0.0, 1.0);
    w.bodies
        .get_mut(w.base)
        .unwrap()
        .set_translation(shift, true);
    w.step();
    let after = w.bodies[w.links[2]].translation();
    // One step of 1/240 s moves the tip by millimetres; the root moved it by a metre.
    assert!(
        ((after - before) - shift).length() < 0.05,
        "{before:?} -> {after:?}"
    );
}

/// The chain stepped at 1/30 s, so that its swinging links count as fast bodies, above a
/// fixed `floor` collider (patches 23 and 24).
fn fast_chain_over(floor: ColliderBuilder) -> World {
    let mut w = chain_of(1000.0);
    w.params.dt = 1.0 / 30.0;
    w.params.num_solver_iterations = 4;
    w.colliders.insert(floor);
    w
}

/// Steps `reused` and `recomputed` (forward kinematics forced before each step) alike and
/// asserts the same bits, and that every link body sits where its multibody's kinematics
/// put it (no pose of the CCD's own); returns the lowest height the chain's tip reached.
fn lockstep(mut reused: World, mut recomputed: World, steps: usize) -> Real {
    let mut lowest = Real::MAX;
    for _ in 0..steps {
        reused.step();
        let _ = recomputed.multibody().link_mut(0);
        recomputed.step();
        assert_eq!(reused.bits(), recomputed.bits());
        let World {
            multibody_joints,
            bodies,
            joint,
            ..
        } = &reused;
        let mb = multibody_joints.get(*joint).unwrap().0;
        for link in mb.links() {
            let body = bodies[link.rigid_body_handle()].position();
            assert_eq!(
                body,
                link.local_to_world(),
                "a link's body left its kinematics"
            );
        }
        lowest = lowest.min(reused.bodies[reused.links[2]].translation().y);
    }
    lowest
}

#[test]
fn a_fast_chain_over_a_floor_keeps_the_kinematics_its_solver_left() {
    let floor = || {
        ColliderBuilder::new(SharedShape::halfspace(Vector::Y))
            .translation(Vector::new(0.0, -2.0, 0.0))
    };
    let lowest = lockstep(fast_chain_over(floor()), fast_chain_over(floor()), 60);
    assert!(lowest < -0.5, "the chain swung down to {lowest}");
}

#[test]
fn a_fast_link_is_stopped_by_its_contact_not_by_the_ccd() {
    // A 2 mm plate 0.45 m under the chain: the swinging links reach it at metres per second.
    // The CCD leaves links below the root alone (patch 24): a clamp of their bodies would be
    // undone by the next step's kinematics. The predicted contact holds them above the plate.
    let plate =
        || ColliderBuilder::cuboid(1.0, 0.001, 1.0).translation(Vector::new(0.5, -0.45, 0.0));
    let lowest = lockstep(fast_chain_over(plate()), fast_chain_over(plate()), 60);
    assert!(lowest > -0.5, "the tip passed the plate: {lowest}");
}
