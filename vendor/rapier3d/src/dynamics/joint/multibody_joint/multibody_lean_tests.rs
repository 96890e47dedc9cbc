//! Tests of gymfleet patch 33 (see `PATCHES.md`): `Jᵀ·f` summed by a backward pass over the
//! links' wrenches, and the solver's forward kinematics between two substeps, which updates
//! only each link's own columns of its body jacobian.

use super::Multibody;
use crate::alloc_prelude::*;
use crate::math::{DVector, Real, Vector};
use crate::prelude::*;
use alloc::format;

const DT: Real = 1.0 / 1200.0;

/// A tree on a fixed base or, with `free_root`, on a free (dynamic) one: a revolute joint
/// about Z (or, with `ball`, a spherical joint), then a prismatic X and a revolute Y on one
/// branch and a revolute about a skew axis on another. Every centre of mass is off its
/// joint; the joints start displaced and moving. Returns the world, the multibody's handle
/// and the displacement that `moved` applies.
pub(super) fn tree(free_root: bool, ball: bool) -> (PhysicsWorld, MultibodyJointHandle, Vec<Real>) {
    let mut world = PhysicsWorld::new();
    let base = if free_root {
        world
            .insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 1.0, -0.1)),
                ColliderBuilder::cuboid(0.1, 0.05, 0.08)
                    .translation(Vector::new(0.03, -0.02, 0.04))
                    .density(900.0),
            )
            .0
    } else {
        world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.2, 1.0, -0.1)))
    };
    let link = |world: &mut PhysicsWorld, at: Vector, half: Vector| {
        world
            .insert(
                RigidBodyBuilder::dynamic().translation(at),
                ColliderBuilder::cuboid(half.x, half.y, half.z)
                    .translation(Vector::new(half.x, 0.02, -0.01))
                    .density(700.0 + 100.0 * at.x),
            )
            .0
    };
    let l1 = link(
        &mut world,
        Vector::new(0.2, 1.0, -0.1),
        Vector::new(0.15, 0.03, 0.02),
    );
    let l2 = link(
        &mut world,
        Vector::new(0.5, 1.0, -0.1),
        Vector::new(0.1, 0.02, 0.04),
    );
    let l3 = link(
        &mut world,
        Vector::new(0.7, 1.0, -0.1),
        Vector::new(0.12, 0.03, 0.03),
    );
    let l4 = link(
        &mut world,
        Vector::new(0.2, 1.1, -0.1),
        Vector::new(0.08, 0.05, 0.02),
    );
    let first: GenericJoint = if ball {
        SphericalJointBuilder::new().into()
    } else {
        RevoluteJointBuilder::new(Vector::Z).into()
    };
    let skew = Vector::new(1.0, 1.0, 0.0).normalize();
    let joints: [(RigidBodyHandle, RigidBodyHandle, GenericJoint, Vector); 4] = [
        (base, l1, first, Vector::ZERO),
        (
            l1,
            l2,
            PrismaticJointBuilder::new(Vector::X).into(),
            Vector::new(0.3, 0.0, 0.0),
        ),
        (
            l2,
            l3,
            RevoluteJointBuilder::new(Vector::Y).into(),
            Vector::new(0.2, 0.0, 0.0),
        ),
        (
            l1,
            l4,
            RevoluteJointBuilder::new(skew).into(),
            Vector::new(0.0, 0.1, 0.0),
        ),
    ];
    let mut handle = None;
    for (parent, child, mut joint, anchor) in joints {
        joint.set_local_anchor1(anchor);
        handle = world.insert_multibody_joint(parent, child, joint);
    }
    let handle = handle.unwrap();
    let mb = world.multibody_joints.get_mut(handle).unwrap().0;
    // The root's type decides its DoFs (a fixed one collapses to a fixed joint).
    mb.forward_kinematics(&world.bodies, false);
    let n = mb.ndofs();
    assert_eq!(n, 4 + 2 * usize::from(ball) + 6 * usize::from(free_root));
    let values = |scale: Real, seed: usize| -> Vec<Real> {
        (0..n)
            .map(|i| scale * (((i * 7 + seed * 3) % 11) as Real / 5.0 - 1.0))
            .collect()
    };
    mb.apply_displacements(&values(0.4, 1));
    mb.forward_kinematics(&world.bodies, false);
    mb.update_rigid_bodies(&mut world.bodies, true);
    mb.velocities.copy_from_slice(&values(2.0, 2));
    (world, handle, values(0.1, 3))
}

pub(super) fn multibody(world: &mut PhysicsWorld, handle: MultibodyJointHandle) -> &mut Multibody {
    world.multibody_joints.get_mut(handle).unwrap().0
}

pub(super) const CASES: [(bool, bool); 4] =
    [(false, false), (true, false), (false, true), (true, true)];

/// The backward pass's generalized forces are `Σᵢ Jᵢᵀ·fᵢ` over the links' full body
/// jacobians, to `f32` rounding, for the forces it projects and for the applied ones.
#[test]
fn projecting_the_subtree_wrenches_sums_the_transposed_body_jacobians() {
    for (free_root, ball) in CASES {
        let (mut world, handle, _) = tree(free_root, ball);
        let mb = multibody(&mut world, handle);
        let (n, nlinks) = (mb.ndofs(), mb.links.len());
        let wrench = |i: usize, seed: Real| {
            let x = i as Real + seed;
            [
                Vector::new(x.sin(), (2.0 * x).cos(), 0.5 - x * 0.1),
                Vector::new(0.3 * x.cos(), -0.2 * x, (3.0 * x).sin()),
            ]
        };
        mb.workspace.wrenches = (0..nlinks).map(|i| wrench(i, 0.3)).collect();
        mb.workspace.applied_wrenches = (0..nlinks).map(|i| wrench(i, 1.7)).collect();
        let mut expected = (DVector::zeros(n), DVector::zeros(n));
        for i in 0..nlinks {
            let jacobian = mb.body_jacobian(i);
            for (out, [force, torque]) in [
                (&mut expected.0, mb.workspace.wrenches[i]),
                (&mut expected.1, mb.workspace.applied_wrenches[i]),
            ] {
                let f = DVector::from_row_slice(&[
                    force.x, force.y, force.z, torque.x, torque.y, torque.z,
                ]);
                *out += jacobian.tr_mul(&f);
            }
        }
        let mut applied = DVector::zeros(n);
        mb.project_link_wrenches(true, &mut applied);
        for (ours, reference, what) in [
            (&mb.accelerations, &expected.0, "forces"),
            (&applied, &expected.1, "applied forces"),
        ] {
            let error = (ours - reference).amax() / reference.amax();
            assert!(
                error < 1.0e-5,
                "free root {free_root}, ball {ball}, {what}: {error:e}\n{ours}\n{reference}"
            );
        }
    }
}

/// The solver's update between two substeps (poses and own columns only) gives the dynamics
/// the full forward kinematics gives, bit for bit: the mass matrices and the free
/// accelerations. With a ball joint and the velocity terms on, the link-by-link construction
/// reads the ancestors' columns, so the update completes the jacobians itself.
#[test]
fn the_update_between_substeps_gives_the_dynamics_of_the_full_one() {
    for (free_root, ball) in CASES {
        let (mut world, handle, moved) = tree(free_root, ball);
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        mb.update_dynamics(DT, &mut world.bodies, true);
        // A substep later: new coordinates, the body jacobians of the old ones.
        mb.apply_displacements(&moved);
        let mut lean = mb.clone();

        mb.forward_kinematics(&world.bodies, false);
        mb.update_rigid_bodies(&mut world.bodies, true);
        mb.update_dynamics(DT, &mut world.bodies, true);
        let full = mb.clone();

        lean.forward_kinematics_between_substeps(&world.bodies);
        assert!(lean.body_jacobians_partial);
        lean.update_rigid_bodies(&mut world.bodies, true);
        lean.update_dynamics(DT, &mut world.bodies, true);
        let case = format!("free root {free_root}, ball {ball}");
        assert!(!lean.velocity_terms_skipped, "{case}");
        assert_eq!(lean.body_jacobians_partial, !ball, "{case}");
        assert_eq!(lean.augmented_mass, full.augmented_mass, "{case}: M");
        assert_eq!(
            lean.acc_augmented_mass, full.acc_augmented_mass,
            "{case}: M + dt·D"
        );
        assert_eq!(
            lean.accelerations, full.accelerations,
            "{case}: accelerations"
        );

        // The full update after it leaves every column as the full one did.
        lean.forward_kinematics(&world.bodies, false);
        assert!(!lean.body_jacobians_partial);
        for i in 0..lean.links.len() {
            assert_eq!(
                lean.body_jacobian(i),
                full.body_jacobian(i),
                "{case}: link {i}"
            );
        }
    }
}
