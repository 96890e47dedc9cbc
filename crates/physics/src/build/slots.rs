//! Each joint's slot in the built world (its link in a multibody tree, its loop
//! constraint, or nothing for a weld taken out of the trees), its DOFs, and what the trees
//! take from the document per DOF: armature, damping, friction, springs, hard limits, and
//! per tree how its velocity terms enter a substep (`simulation.integrator`).

use std::collections::HashMap;

use gymfleet_assembly::{Assembly, DofKind, Integrator, Joint, JointType};
use rapier3d::geometry::PairCompliance;
use rapier3d::prelude::*;

use crate::error::{PhysicsError, Result};
use crate::world::{JointDof, JointSlot, Lane, Sets};

/// The multibody of a slot in no tree.
fn no_multibody() -> MultibodyIndex {
    MultibodyIndex(rapier3d::data::Index::from_raw_parts(u32::MAX, u32::MAX))
}

/// Each joint's slot (its link in a tree, or its loop constraint), its DOFs, and each
/// DOF's apparent inertia (for default gains). Also gives the trees their joint damping,
/// friction, springs, hard limits and self-contacts ([`configure_tree_joint`]). Links are
/// looked up only once the trees are complete: insertion may renumber them.
pub(super) fn joint_slots(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    frames: &[(Pose, Pose)],
    closing: &[Option<ImpulseJointHandle>],
    welded_away: &[bool],
    lanes: &[Option<Lane>],
) -> Result<(Vec<JointSlot>, Vec<JointDof>, Vec<f64>)> {
    let mut joints = Vec::with_capacity(assembly.joints.len());
    let mut dofs = Vec::with_capacity(assembly.total_dof());
    let mut inertia = Vec::with_capacity(assembly.total_dof());
    let mut inverse_inertias = HashMap::new();
    let explicit = assembly.integrator == Integrator::Euler;
    for (j, joint) in assembly.joints.iter().enumerate() {
        let child = bodies[joint.child];
        // A slot in no tree, with no DOF: what a weld held fixed or folded
        // (`held_fixed`, `fold_owners`) keeps.
        let unlinked = JointSlot {
            kind: joint.kind,
            parent: bodies[joint.parent],
            child,
            multibody: no_multibody(),
            link: 0,
            frame1: frames[j].0,
            first_dof: dofs.len(),
            closing: None,
            observed_dofs: 0,
            on_loop: joint.on_loop,
            lane: None,
        };
        if let Some(handle) = closing[j] {
            // A child in no tree (the ground): no multibody.
            let link_id = sets.multibody_joints.rigid_body_link(child).copied();
            joints.push(JointSlot {
                multibody: link_id.map_or_else(no_multibody, |l| l.multibody),
                link: link_id.map_or(0, |l| l.id),
                closing: Some(handle),
                observed_dofs: joint.observed_dof(),
                on_loop: true,
                ..unlinked
            });
            if joint.observed {
                // Passive: its inertia only feeds default gains, which it never uses.
                inertia.extend(std::iter::repeat_n(0.0, joint.kind.dof()));
                dofs.extend(joint_dofs(j, joint));
            }
        } else if welded_away[joint.child] && lanes[j].is_none() {
            joints.push(unlinked);
        } else {
            let link_id = *sets
                .multibody_joints
                .rigid_body_link(child)
                .ok_or_else(|| PhysicsError::BadOption {
                    field: "assembly.joints",
                    reason: format!("joint {:?} has no multibody link", joint.name),
                })?;
            let slot = JointSlot {
                multibody: link_id.multibody,
                link: link_id.id,
                observed_dofs: joint.kind.dof(),
                lane: lanes[j],
                ..unlinked
            };
            inertia.extend(configure_tree_joint(
                sets,
                joint,
                &slot,
                assembly,
                &mut inverse_inertias,
            ));
            joints.push(slot);
            dofs.extend(joint_dofs(j, joint));
        }
    }
    if explicit {
        keep_loops_implicit(sets, assembly, bodies, closing);
    }
    Ok((joints, dofs, inertia))
}

/// Whether the trees solve their constraints on the mass matrix without the joints' damping,
/// which then acts on their impulses and the step's forces together, as MuJoCo's Euler step
/// does (`mj_EulerSkip`, vendored patch 50): under `euler` with MuJoCo's soft contacts or
/// limits. The others keep Rapier's order: a rigid document its results, and one whose file
/// said RK4 (integrated implicit here) stays nearer MuJoCo's RK4 with it
/// (`bench/journal/2026-12-08-damping-order.md`).
fn mujoco_damping_order(assembly: &Assembly) -> bool {
    assembly.integrator == Integrator::Euler
        && (assembly.joints.iter().any(|j| j.soft_limit.is_some())
            || assembly
                .instances
                .iter()
                .any(|i| i.material.soft_contact.is_some()))
}

/// A tree that a loop constraint closes keeps the implicit velocity terms even under
/// `simulation.integrator: "euler"`: with the explicit ones a four-bar linkage parts from
/// MuJoCo's `Euler` trajectory by 0.18 rad within 0.5 s, against 0.018 rad with the
/// implicit ones (`test_loops.py`; measured, the cause not pinned down: both lose energy
/// alike, the explicit one leaves MuJoCo's path earlier near the dead points).
fn keep_loops_implicit(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    closing: &[Option<ImpulseJointHandle>],
) {
    for (joint, _) in assembly
        .joints
        .iter()
        .zip(closing)
        .filter(|(_, c)| c.is_some())
    {
        for body in [bodies[joint.parent], bodies[joint.child]] {
            let Some(link) = sets.multibody_joints.rigid_body_link(body).copied() else {
                continue;
            };
            if let Some(mb) = sets.multibody_joints.get_multibody_mut(link.multibody) {
                mb.set_explicit_velocity_terms(false);
            }
        }
    }
}

/// Gives a tree joint's DOFs the document's damping, friction and spring, and returns
/// each DOF's apparent inertia. The first joint of each tree also sets the tree's
/// self-contacts, hard limits, zero default damping, (under `euler`) MuJoCo's `Euler`
/// velocity terms, (`mujoco_damping_order`) MuJoCo's damping order, and computes its DOFs'
/// inverse inertias (kept in `inverse_inertias`, before any damping or spring changes them).
fn configure_tree_joint(
    sets: &mut Sets,
    joint: &Joint,
    slot: &JointSlot,
    assembly: &Assembly,
    inverse_inertias: &mut HashMap<MultibodyIndex, DVector>,
) -> Vec<f64> {
    let explicit = assembly.integrator == Integrator::Euler;
    let mb = sets
        .multibody_joints
        .get_multibody_mut(slot.multibody)
        .expect("a link's multibody exists");
    let inv = inverse_inertias.entry(slot.multibody).or_insert_with(|| {
        mb.set_self_contacts_enabled(true);
        // Limits are hard stops: a DOF past its limit is put back on it after
        // every substep (Rapier's own limit engages only once it is past).
        mb.set_hard_limits(true);
        // `simulation.integrator: "euler"`: the velocity terms as forces of the
        // substep's start (vendored Rapier patch 26), as MuJoCo's Euler integrator.
        mb.set_explicit_velocity_terms(explicit);
        // and its springs explicit, implicit in damping only (vendored patch 45).
        mb.set_explicit_springs(explicit);
        // MuJoCo's constraints see `M` without the damping, which acts on their impulses
        // afterwards (vendored patch 50).
        mb.set_damping_after_constraints(mujoco_damping_order(assembly));
        // Rapier gives angular DOFs a default damping of 0.1: remove it, so
        // that a free pendulum keeps its energy unless the document says not.
        mb.damping_mut().fill(0.0);
        mb.dof_inverse_inertia(&sets.bodies)
    });
    let assembly_id = mb.link(slot.link).expect("link exists").assembly_id();
    // A passive spring (MuJoCo's joint stiffness): Rapier's implicit joint spring on
    // the joint's one free axis (a revolute joint's angle is angular X, a prismatic
    // joint's displacement linear X; its axis in a fused planar root), its rest measured
    // like the joint's coordinate. The default gains exclude springs, so setting it here
    // changes nothing for them.
    let spring_axis = match joint.kind {
        JointType::Revolute | JointType::Prismatic => Some(slot.coord(0)),
        _ => None,
    };
    if let (Some(axis), true) = (spring_axis, joint.stiffness > 0.0) {
        if let Some(link) = mb.link_mut(slot.link) {
            link.joint
                .set_spring(axis, joint.stiffness as Real, joint.spring_rest as Real);
        }
    }
    // MuJoCo's compliant limits (vendored patch 44), sized by the DOF's inverse inertia at
    // the document's pose (MuJoCo's `dof_invweight0`, set by `set_invweights`).
    if let (Some(soft), JointType::Revolute | JointType::Prismatic) = (joint.soft_limit, joint.kind)
    {
        // Its inverse weight is set once the masses are known (`set_invweights`).
        if let Some(link) = mb.link_mut(slot.link) {
            link.joint
                .set_limit_compliance(Some(limit_compliance(soft, 0.0)));
        }
    }
    (0..joint.kind.dof())
        .map(|k| {
            let dof = slot.link_dof(assembly_id, k);
            mb.damping_mut()[dof] = joint.damping as Real;
            mb.frictions_mut()[dof] = joint.friction as Real;
            let inv_i = f64::from(inv[dof]);
            if inv_i > 0.0 {
                1.0 / inv_i
            } else {
                0.0
            }
        })
        .collect()
}

/// Each joint's armature on its DOFs.
pub(super) fn set_armatures(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    lanes: &[Option<Lane>],
) {
    // Armature first: the default PD gains below follow each DOF's apparent inertia,
    // which includes it.
    for (joint, lane) in assembly
        .joints
        .iter()
        .zip(lanes)
        .filter(|(j, _)| j.armature > 0.0 && !j.closes_loop)
    {
        let link = sets
            .multibody_joints
            .rigid_body_link(bodies[joint.child])
            .copied();
        if let Some(mb) = link.and_then(|l| {
            let mb = sets.multibody_joints.get_multibody_mut(l.multibody)?;
            let first = mb.link(l.id)?.assembly_id() + lane.map_or(0, |l| l.offset);
            Some((mb, first))
        }) {
            let (mb, first) = mb;
            for k in 0..joint.kind.dof() {
                mb.armature_mut()[first + k] = joint.armature as Real;
            }
        }
    }
}

fn joint_dofs(j: usize, joint: &Joint) -> impl Iterator<Item = JointDof> + '_ {
    // As the document wrote them: -120° reads -120, not -119.99999999999999.
    let user_limits = joint.document_limits;
    joint.dof_kinds().iter().map(move |&kind| JointDof {
        joint: j,
        joint_name: joint.name.clone(),
        joint_type: joint.kind,
        kind,
        limits: if kind == DofKind::Linear || joint.kind == JointType::Revolute {
            user_limits
        } else {
            None
        },
        initial: crate::units::from_si(kind, joint.initial),
        max_effort: joint.max_effort,
        gear: joint.gear,
        action_bound: 0.0,
        reference: joint.reference,
        actuated: joint.actuated,
        kp: 0.0,
        kd: 0.0,
        kv: 0.0,
    })
}

/// A joint's compliant limits as Rapier's (vendored patch 44): acting from `margin` on.
fn limit_compliance(soft: gymfleet_assembly::SoftLimit, invweight: Real) -> PairCompliance {
    let margin = soft.margin as Real;
    PairCompliance {
        invweight,
        ..PairCompliance::new(
            soft.solref.map(|v| v as Real),
            soft.solimp.map(|v| v as Real),
            margin,
            margin,
        )
    }
}
