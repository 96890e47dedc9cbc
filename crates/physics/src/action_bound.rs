//! Each actuated DOF's action-space bound: what a sampled or normalised torque action may
//! reach. With the document's `max_effort` it is `max_effort / |gear|`; without one (a
//! clamp the physics does not have), a default derived from the model at its initial pose,
//! so that `action_space.sample()` moves a gram-scale arm as sensibly as a metre-scale one:
//!
//! - twice the effort that holds what the DOF drives against gravity where gravity pulls
//!   hardest (`loads.rs`: its subtree, `2·m·|g⊥|·r⊥` for an angular DOF and `2·m·|g·a|` for a
//!   linear one, and with the loops it closes, what it drives through them);
//! - and at least what gives the DOF's apparent inertia (armature included) an
//!   acceleration of [`FALLBACK_ACCELERATION`] rad/s² or m/s², for axes that gravity does
//!   not load (a vertical turntable, a horizontal slide, zero gravity).
//!
//! The bound is a property of the action space only: it never clamps an effort (that is
//! `max_effort`'s job, and a document without one has none).

use crate::loads::DofLoad;
use crate::world::{JointDof, JointSlot};

/// How many times the gravity-holding effort the default bound allows.
pub const GRAVITY_MULTIPLE: f64 = 2.0;
/// The acceleration (rad/s² or m/s²) the default bound gives the DOF's apparent inertia at
/// least.
pub const FALLBACK_ACCELERATION: f64 = 10.0;

/// Sets every DOF's `action_bound` (in action units: effort over `|gear|`) from what it
/// drives (`loads`, in DOF order; `loads.rs`).
pub(crate) fn set_action_bounds(joints: &[JointSlot], dofs: &mut [JointDof], loads: &[DofLoad]) {
    for slot in joints {
        if slot.closing.is_some() {
            continue; // Loop-closing joints are passive (`loops.rs`).
        }
        let n = slot.kind.dof();
        for (dof, load) in dofs[slot.first_dof..slot.first_dof + n]
            .iter_mut()
            .zip(&loads[slot.first_dof..slot.first_dof + n])
        {
            let gear = dof.gear.abs().max(f64::MIN_POSITIVE);
            if let Some(max_effort) = dof.max_effort {
                dof.action_bound = max_effort / gear;
                continue;
            }
            let effort = (GRAVITY_MULTIPLE * load.hold).max(load.inertia * FALLBACK_ACCELERATION);
            dof.action_bound = effort / gear;
        }
    }
}
