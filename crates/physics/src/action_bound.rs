//! Each actuated DOF's action-space bound: what a sampled or normalised torque action may
//! reach. With the document's `max_effort` it is `max_effort / |gear|`; without one (a
//! clamp the physics does not have), a default derived from the model at its initial pose,
//! so that `action_space.sample()` moves a gram-scale arm as sensibly as a metre-scale one:
//!
//! - an angular DOF (axis `a` through the joint's anchor `p`): twice the torque that holds
//!   the joint's subtree against gravity where gravity pulls hardest, `2·m·|g⊥|·r⊥` (`m` the
//!   subtree's mass, `r⊥` its centre of mass's distance from the axis line, `g⊥` gravity's
//!   part across the axis);
//! - a linear DOF: twice the force that holds the subtree up along the axis, `2·m·|g·a|`;
//! - and at least what gives the DOF's apparent inertia (armature included) an
//!   acceleration of [`FALLBACK_ACCELERATION`] rad/s² or m/s², for axes that gravity does
//!   not load (a vertical turntable, a horizontal slide, zero gravity).
//!
//! The bound is a property of the action space only: it never clamps an effort (that is
//! `max_effort`'s job, and a document without one has none).

use gymfleet_assembly::{DofKind, JointType};
use rapier3d::prelude::*;

use crate::world::{JointDof, JointSlot, Sets};

/// How many times the gravity-holding effort the default bound allows.
pub const GRAVITY_MULTIPLE: f64 = 2.0;
/// The acceleration (rad/s² or m/s²) the default bound gives the DOF's apparent inertia at
/// least.
pub const FALLBACK_ACCELERATION: f64 = 10.0;

/// Sets every DOF's `action_bound` (in action units: effort over `|gear|`). `inertia` is each
/// DOF's apparent inertia (kg·m² or kg), in DOF order; `gravity` in m/s².
pub(crate) fn set_action_bounds(
    sets: &Sets,
    joints: &[JointSlot],
    dofs: &mut [JointDof],
    inertia: &[f64],
    gravity: Vector,
) {
    let g = gravity;
    for slot in joints {
        if slot.closing.is_some() {
            continue; // Loop-closing joints are passive (`loops.rs`).
        }
        let frame = crate::world::joint_frame(sets, slot);
        let anchor = frame.translation;
        let (mass, com) = subtree_mass(sets, slot);
        let axes = [Vector::X, Vector::Y, Vector::Z].map(|v| frame.rotation * v);
        let n = slot.kind.dof();
        for (k, dof) in dofs[slot.first_dof..slot.first_dof + n]
            .iter_mut()
            .enumerate()
        {
            let gear = dof.gear.abs().max(f64::MIN_POSITIVE);
            if let Some(max_effort) = dof.max_effort {
                dof.action_bound = max_effort / gear;
                continue;
            }
            // A ball joint's DOFs turn about the frame's three axes; the other joints'
            // about (or along) X.
            let axis = if slot.kind == JointType::Ball {
                axes[k]
            } else {
                axes[0]
            };
            let hold = match dof.kind {
                DofKind::Angular => {
                    let lever = com - anchor;
                    let lever_across = lever - axis * lever.dot(axis);
                    let g_across = g - axis * g.dot(axis);
                    mass * f64::from(g_across.length()) * f64::from(lever_across.length())
                }
                DofKind::Linear => mass * f64::from(g.dot(axis).abs()),
            };
            let effort =
                (GRAVITY_MULTIPLE * hold).max(inertia[slot.first_dof + k] * FALLBACK_ACCELERATION);
            dof.action_bound = effort / gear;
        }
    }
}

/// The mass (kg) and centre of mass (m, world) of a joint's child link and every link below
/// it in its multibody.
fn subtree_mass(sets: &Sets, slot: &JointSlot) -> (f64, Vector) {
    let Some(mb) = sets.multibody_joints.get_multibody(slot.multibody) else {
        return (0.0, Vector::ZERO);
    };
    let links: Vec<_> = mb.links().collect();
    let below = |mut i: usize| loop {
        if i == slot.link {
            return true;
        }
        if i == 0 {
            return false;
        }
        i = links[i].parent_id().unwrap_or(0);
    };
    let (mut mass, mut moment) = (0.0_f64, Vector::ZERO);
    for (i, link) in links.iter().enumerate() {
        if below(i) {
            let rb = &sets.bodies[link.rigid_body_handle()];
            mass += f64::from(rb.mass());
            moment += rb.center_of_mass() * rb.mass();
        }
    }
    let com = if mass > 0.0 {
        moment / mass as Real
    } else {
        Vector::ZERO
    };
    (mass, com)
}
