//! What a planar root joint saves HalfCheetah (the measurement that led gymfleet to build one,
//! `crates/physics/src/build/planar.rs`).
//!
//! gymfleet converts MJCF's slide/slide/hinge roots (HalfCheetah, Hopper, Walker2d: `rootx`,
//! `rootz`, `rooty`) into three one-DoF joints through two 1 mg helper bodies; as links, every
//! per-link loop of the multibody would run over two links more. This builds Gymnasium's HalfCheetah
//! (`half_cheetah.xml`: its capsules, density 1000, the plane) on the patched Rapier both ways:
//!
//! - `helpers`: fixed base → prismatic X → helper → prismatic Z → helper → revolute Y → torso;
//! - `planar`: fixed base → one joint with LinX, LinZ and AngY free → torso (the same three DoFs
//!   in the same order; the composite mass matrix takes it, patch 30, as the velocity terms are
//!   explicit, patch 26);
//!
//! then steps each with the same random torques (0.05 s steps of 5 substeps, explicit velocity
//! terms, as gymfleet steps `HalfCheetah-v5`) and prints the torso's final pose and the time per
//! step. `cargo run --release --bin planar_root -- helpers 600`; under callgrind, the difference
//! between 200 and 600 steps gives instructions per step.

use new::prelude::*;
use std::time::Instant;

const GEARS: [Real; 6] = [120.0, 90.0, 60.0, 120.0, 60.0, 30.0];
/// The legs' joint ranges (rad), bthigh to ffoot.
const LIMITS: [(Real, Real); 6] = [
    (-0.52, 1.05),
    (-0.785, 0.785),
    (-0.4, 0.785),
    (-1.0, 0.7),
    (-1.2, 0.87),
    (-0.5, 0.5),
];

/// A capsule of MuJoCo's `size="radius half_length"` at `pos`, turned by `angle` about Y from
/// MuJoCo's Z-aligned capsule.
fn capsule(pos: [Real; 3], angle: Real, radius: Real, half: Real) -> ColliderBuilder {
    ColliderBuilder::capsule_z(half, radius)
        .translation(Vector::new(pos[0], pos[1], pos[2]))
        .rotation(Vector::Y * angle)
        .density(1000.0)
        .friction(0.4)
}

fn link(world: &mut PhysicsWorld, at: Vector, shape: ColliderBuilder) -> RigidBodyHandle {
    world
        .insert(RigidBodyBuilder::dynamic().translation(at), shape)
        .0
}

fn cheetah(planar: bool) -> (PhysicsWorld, MultibodyJointHandle) {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    world.integration_parameters.dt = 0.05;
    world.integration_parameters.num_solver_iterations = 5;
    world.integration_parameters.flush_denormals = true;
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::new(SharedShape::halfspace(Vector::Z)).friction(0.4),
    );
    let root = Vector::new(0.0, 0.0, 0.7);
    let base = world.insert_body(RigidBodyBuilder::fixed().translation(root));
    let torso = world
        .insert(
            RigidBodyBuilder::dynamic().translation(root),
            ColliderBuilder::capsule_x(0.5, 0.046)
                .density(1000.0)
                .friction(0.4),
        )
        .0;
    let head = capsule([0.6, 0.0, 0.1], 0.87, 0.046, 0.15);
    world.insert_collider(head, Some(torso));
    let mut joints: Vec<(RigidBodyHandle, RigidBodyHandle, GenericJoint, Vector)> = Vec::new();
    if planar {
        let locked = JointAxesMask::LIN_Y | JointAxesMask::ANG_X | JointAxesMask::ANG_Z;
        joints.push((
            base,
            torso,
            GenericJointBuilder::new(locked).into(),
            Vector::ZERO,
        ));
    } else {
        let helper = |world: &mut PhysicsWorld| {
            let mass = MassProperties::new(Vector::ZERO, 1.0e-6, Vector::splat(1.0e-9));
            world.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(root)
                    .additional_mass_properties(mass),
            )
        };
        let (h1, h2) = (helper(&mut world), helper(&mut world));
        joints.push((
            base,
            h1,
            PrismaticJointBuilder::new(Vector::X).into(),
            Vector::ZERO,
        ));
        joints.push((
            h1,
            h2,
            PrismaticJointBuilder::new(Vector::Z).into(),
            Vector::ZERO,
        ));
        joints.push((
            h2,
            torso,
            RevoluteJointBuilder::new(Vector::Y).into(),
            Vector::ZERO,
        ));
    }
    // (parent, body position relative to the parent's, its capsule): back leg, then front leg.
    let legs: [(usize, [Real; 3], ([Real; 3], Real, Real)); 6] = [
        (0, [-0.5, 0.0, 0.0], ([0.1, 0.0, -0.13], -3.8, 0.145)),
        (1, [0.16, 0.0, -0.25], ([-0.14, 0.0, -0.07], -2.03, 0.15)),
        (2, [-0.28, 0.0, -0.14], ([0.03, 0.0, -0.097], -0.27, 0.094)),
        (0, [0.5, 0.0, 0.0], ([-0.07, 0.0, -0.12], 0.52, 0.133)),
        (4, [-0.14, 0.0, -0.24], ([0.065, 0.0, -0.09], -0.6, 0.106)),
        (5, [0.13, 0.0, -0.18], ([0.045, 0.0, -0.07], -0.6, 0.07)),
    ];
    let mut bodies = vec![torso];
    let mut positions = vec![root];
    for (parent, offset, (pos, angle, half)) in legs {
        let at = positions[parent] + Vector::new(offset[0], offset[1], offset[2]);
        let body = link(&mut world, at, capsule(pos, angle, 0.046, half));
        let anchor = Vector::new(offset[0], offset[1], offset[2]);
        let (lo, hi) = LIMITS[bodies.len() - 1];
        let hinge = RevoluteJointBuilder::new(Vector::Y).limits([lo, hi]);
        joints.push((bodies[parent], body, hinge.into(), anchor));
        bodies.push(body);
        positions.push(at);
    }
    let mut handle = None;
    for (parent, child, mut joint, anchor) in joints {
        // Like MuJoCo (and gymfleet's contact filter), a link does not touch its parent.
        joint.set_local_anchor1(anchor).set_contacts_enabled(false);
        handle = world.insert_multibody_joint(parent, child, joint);
    }
    let handle = handle.unwrap();
    let mb = world.multibody_joints.get_mut(handle).unwrap().0;
    // As gymfleet builds a document's multibody (`crates/physics/src/build/slots.rs`): links
    // touch each other but not their parents, limits are hard stops, explicit velocity terms
    // for an Euler file, no default damping.
    mb.set_self_contacts_enabled(true);
    mb.set_hard_limits(true);
    mb.set_explicit_velocity_terms(true);
    mb.damping_mut().fill(0.0);
    // The legs' armature, damping and springs from `half_cheetah.xml` (the root has none).
    let legs = [
        (6.0, 240.0),
        (4.5, 180.0),
        (3.0, 120.0),
        (4.5, 180.0),
        (3.0, 120.0),
        (1.5, 60.0),
    ];
    let first_leg = mb.num_links() - 6;
    for (k, (damping, stiffness)) in legs.into_iter().enumerate() {
        mb.armature_mut()[3 + k] = 0.1;
        mb.damping_mut()[3 + k] = damping;
        let link = mb.link_mut(first_leg + k).unwrap();
        link.joint.set_spring(3, stiffness, 0.0);
    }
    (world, handle)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let planar = match args.get(1).map(String::as_str) {
        Some("planar") => true,
        Some("helpers") => false,
        _ => panic!("usage: planar_root helpers|planar [STEPS [SEED]]"),
    };
    let steps: usize = args
        .get(2)
        .map_or(600, |s| s.parse().expect("a step count"));
    let (mut world, handle) = cheetah(planar);
    // The same torques on both sides: an LCG's uniform draws in [-1, 1] times the gears.
    let seed: u64 = args.get(3).map_or(0, |s| s.parse().expect("a seed"));
    let mut state: u64 = 0x2545_f491_4f6c_dd1d ^ seed;
    let started = Instant::now();
    for _ in 0..steps {
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        let forces = mb.applied_forces_mut();
        for (k, gear) in GEARS.iter().enumerate() {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let u = (state >> 11) as Real / (1u64 << 53) as Real;
            forces[3 + k] = gear * (2.0 * u - 1.0);
        }
        world.step();
    }
    let elapsed = started.elapsed().as_secs_f64();
    let mb = world.multibody_joints.get(handle).unwrap().0;
    // The torso is the link before the six legs.
    let torso = mb.link(mb.num_links() - 7).unwrap();
    let pose = world.bodies[torso.rigid_body_handle()].position();
    println!(
        "{}: {} links, {} DoFs; after {steps} steps torso at ({:.4}, {:.4}) m, pitch {:.4}; {:.2} µs per step",
        if planar { "planar" } else { "helpers" },
        mb.num_links(),
        mb.ndofs(),
        pose.translation.x,
        pose.translation.z,
        pose.rotation.to_scaled_axis().y,
        elapsed / steps as f64 * 1e6,
    );
}
