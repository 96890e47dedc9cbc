//! Tests of gymfleet patch 35 (see `PATCHES.md`): the mass matrix alone by its own composite
//! pass, the links' inertias computed once per substep, and the joint springs over the free
//! axes only. Each keeps the bits of the code it replaces.

use super::lean_tests::{CASES, multibody, tree};
use super::{Multibody, free_axes};
use crate::dynamics::{GenericJoint, MultibodyJoint};
use crate::math::{Real, SPATIAL_DIM};
use crate::prelude::*;
use alloc::format;

const DT: Real = 1.0 / 1200.0;

/// Without the velocity terms the composite pass builds `M` by itself; its entries are the
/// bits of the pass that also builds the velocity terms, and it fills both triangles.
#[test]
fn the_mass_matrix_alone_has_the_bits_of_the_pass_with_the_velocity_terms() {
    for free_root in [false, true] {
        let (mut world, handle, _) = tree(free_root, false);
        let mb = world.multibody_joints.get_mut(handle).unwrap().0;
        mb.update_velocities(&mut world.bodies);
        let bodies = &world.bodies;
        // Sizes the matrices and computes the links' inertias.
        mb.update_mass_matrix(DT, bodies);
        assert!(mb.composite_applies(bodies, true));
        let n = mb.ndofs();
        let build = |mb: &mut Multibody, velocity_terms: bool| {
            mb.augmented_mass.fill(0.0);
            mb.acc_augmented_mass.fill(0.0);
            mb.composite_mass_matrices(DT, velocity_terms, bodies);
            mb.augmented_mass.clone()
        };
        let with_terms = build(mb, true);
        let alone = build(mb, false);
        let mut off_diagonal = 0;
        for c in 0..n {
            for a in 0..=c {
                let case = format!("free root {free_root}, M[{a}, {c}]");
                assert_eq!(
                    alone[(a, c)].to_bits(),
                    with_terms[(a, c)].to_bits(),
                    "{case}"
                );
                assert_eq!(alone[(c, a)].to_bits(), alone[(a, c)].to_bits(), "{case}");
                off_diagonal += usize::from(a != c && alone[(a, c)] != 0.0);
            }
        }
        assert!(off_diagonal >= n, "free root {free_root}: {alone}");
    }
}

/// `update_dynamics` computes the links' inertias once for both matrices and the free
/// accelerations: the same bits as `update_mass_matrix` and `update_acceleration` called
/// apart, each computing them itself, with the velocity terms in the matrices and without.
#[test]
fn inertias_computed_once_per_substep_give_the_dynamics_bit_for_bit() {
    for (free_root, ball) in CASES {
        for explicit in [false, true] {
            let (mut world, handle, moved) = tree(free_root, ball);
            let mb = world.multibody_joints.get_mut(handle).unwrap().0;
            mb.set_explicit_velocity_terms(explicit);
            // A substep at another configuration first, so that stale inertias would show.
            mb.update_dynamics(DT, &mut world.bodies, true);
            mb.apply_displacements(&moved);
            mb.forward_kinematics(&world.bodies, false);
            mb.update_rigid_bodies(&mut world.bodies, true);
            let mut apart = mb.clone();
            mb.update_dynamics(DT, &mut world.bodies, true);
            apart.update_velocities(&mut world.bodies);
            apart.update_mass_matrix(DT, &world.bodies);
            apart.factorize_inv_augmented_mass();
            apart.update_acceleration(DT, &world.bodies);
            let mb = multibody(&mut world, handle);
            let case = format!("free root {free_root}, ball {ball}, explicit {explicit}");
            assert_eq!(mb.velocity_terms_skipped, explicit, "{case}");
            assert_eq!(mb.augmented_mass, apart.augmented_mass, "{case}: M");
            assert_eq!(
                mb.acc_augmented_mass, apart.acc_augmented_mass,
                "{case}: M + dt·D"
            );
            assert_eq!(
                mb.accelerations, apart.accelerations,
                "{case}: accelerations"
            );
        }
    }
}

/// `free_axes` yields the free axes in order, numbering their DoFs from the first one, for
/// every mask of locked axes.
#[test]
fn free_axes_number_the_unlocked_axes_in_order() {
    for bits in 0..(1u8 << SPATIAL_DIM) {
        let mut data = GenericJoint::default();
        data.locked_axes = JointAxesMask::from_bits_truncate(bits);
        let joint = MultibodyJoint::new(data, false);
        let mut expected = alloc::vec::Vec::new();
        for axis in 0..SPATIAL_DIM {
            if bits & (1 << axis) == 0 {
                expected.push((axis, 7 + expected.len()));
            }
        }
        let ours: alloc::vec::Vec<_> = free_axes(&joint, 7).collect();
        assert_eq!(ours, expected, "locked {bits:06b}");
    }
}
