//! What each DOF drives (issue F): its apparent inertia and the gravity load it holds, through
//! the tree below it and through the kinematic loops that tree closes. The default PD gains
//! (`actuation.rs`) and the default action bounds (`action_bound.rs`) follow them.
//!
//! - A DOF of a tree joint off any loop: the tree's apparent inertia `1 / diag(M⁻¹)` (MuJoCo's
//!   `dof_invweight0`, from the trees) and the torque that holds its subtree where gravity
//!   pulls hardest, `m·|g⊥|·r⊥` (`m` the subtree's mass, `r⊥` its centre of mass's distance
//!   from the axis line, `g⊥` gravity's part across the axis); a linear DOF's `m·|g·a|`.
//! - A DOF of a tree joint on a loop: the same with the loops closed. `M` is the joint-space
//!   inertia of the trees the loops join (armature included) and `G` the loop joints' locked
//!   rows in joint space; `P = M⁻¹ − M⁻¹Gᵀ(G M⁻¹ Gᵀ)⁺ G M⁻¹` is the inverse inertia the
//!   mechanism shows with the loops closed, and the DOF's inertia is `1 / P_kk`. A unit rate of
//!   the DOF moves the mechanism as `u = P·e_k / P_kk` (the motion of least kinetic energy the
//!   loops allow); the hold is every moving body's weight along its velocity,
//!   `|g|·Σ m_b·|v_b(u)|`, the most gravity can load the DOF in this pose. A crank-rocker's
//!   crank so drives its coupler and rocker, where its subtree alone held the coupler only.

use gymfleet_assembly::{DofKind, JointType};
use rapier3d::na::{DMatrix, DVector};
use rapier3d::prelude::*;

use crate::world::{JointDof, JointSlot, Sets};

/// A DOF's apparent inertia (kg·m² or kg) and the effort (N·m or N) that holds against gravity
/// what it drives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DofLoad {
    pub(crate) inertia: f64,
    pub(crate) hold: f64,
}

/// Every DOF's load, in DOF order, from the trees' apparent inertias `tree_inertia` (what
/// `joint_slots` measured) and `gravity` (m/s²). A loop-closing joint's observed DOFs are
/// passive: their load is zero.
pub(crate) fn dof_loads(
    sets: &Sets,
    joints: &[JointSlot],
    dofs: &[JointDof],
    tree_inertia: &[f64],
    gravity: Vector,
) -> Vec<DofLoad> {
    let mut loads: Vec<DofLoad> = tree_inertia
        .iter()
        .map(|&inertia| DofLoad { inertia, hold: 0.0 })
        .collect();
    for slot in joints.iter().filter(|s| s.closing.is_none()) {
        let n = slot
            .kind
            .dof()
            .min(dofs.len().saturating_sub(slot.first_dof));
        for k in 0..n {
            loads[slot.first_dof + k].hold =
                tree_hold(sets, slot, k, dofs[slot.first_dof + k].kind, gravity);
        }
    }
    if joints.iter().any(|s| s.closing.is_some()) {
        if let Some(closed) = LoopedTrees::new(sets, joints) {
            closed.set_loads(sets, joints, gravity, &mut loads);
        }
    }
    loads
}

/// The effort that holds DOF `k` of `slot`'s subtree against `gravity` where it pulls hardest.
fn tree_hold(sets: &Sets, slot: &JointSlot, k: usize, kind: DofKind, gravity: Vector) -> f64 {
    let frame = crate::world::joint_frame(sets, slot);
    let axes = [Vector::X, Vector::Y, Vector::Z].map(|v| frame.rotation * v);
    // A ball joint's DOFs turn about the frame's three axes; the other joints' about (or
    // along) X.
    let axis = if slot.kind == JointType::Ball {
        axes[k]
    } else {
        axes[0]
    };
    let (mass, com) = subtree_mass(sets, slot);
    match kind {
        DofKind::Angular => {
            let lever = com - frame.translation;
            let lever_across = lever - axis * lever.dot(axis);
            let g_across = gravity - axis * gravity.dot(axis);
            mass * f64::from(g_across.length()) * f64::from(lever_across.length())
        }
        DofKind::Linear => mass * f64::from(gravity.dot(axis).abs()),
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

/// The trees that loop joints join, in joint space: each body's velocity per unit rate of
/// each DOF (its columns), the joint-space inertia and the loops' locked rows.
struct LoopedTrees {
    /// Each tree's multibody and the index of its first DOF among all of theirs.
    trees: Vec<(MultibodyIndex, usize)>,
    /// The trees' link bodies, each with its mass and its velocity columns: rows 0–2 the
    /// centre of mass's linear velocity, 3–5 the angular velocity, per unit rate of a DOF.
    bodies: Vec<(RigidBodyHandle, f64, DMatrix<f64>)>,
    /// The joint-space inertia, armature included.
    mass: DMatrix<f64>,
    /// The loop joints' locked rows (relative velocity along each locked axis).
    rows: DMatrix<f64>,
}

impl LoopedTrees {
    fn new(sets: &Sets, joints: &[JointSlot]) -> Option<Self> {
        let mut trees: Vec<(MultibodyIndex, usize)> = Vec::new();
        let mut n = 0;
        let mut add = |handle: RigidBodyHandle, trees: &mut Vec<(MultibodyIndex, usize)>| {
            let link = sets.multibody_joints.rigid_body_link(handle)?;
            if !trees.iter().any(|(m, _)| *m == link.multibody) {
                let ndofs = sets.multibody_joints.get_multibody(link.multibody)?.ndofs();
                trees.push((link.multibody, n));
                n += ndofs;
            }
            Some(())
        };
        for slot in joints.iter().filter(|s| s.closing.is_some()) {
            let _ = add(slot.parent, &mut trees);
            let _ = add(slot.child, &mut trees);
        }
        if n == 0 {
            return None;
        }
        // Each DOF's unit rate, through the trees' kinematics, on copies.
        let mut multibodies = sets.multibody_joints.clone();
        let mut scratch = sets.bodies.clone();
        let mut bodies = Vec::new();
        let mut mass = DMatrix::zeros(n, n);
        for &(index, first) in &trees {
            let mb = multibodies.get_multibody_mut(index)?;
            mb.forward_kinematics(&scratch, false);
            let handles: Vec<RigidBodyHandle> = mb.links().map(|l| l.rigid_body_handle()).collect();
            let start = bodies.len();
            for &h in &handles {
                bodies.push((h, f64::from(scratch[h].mass()), DMatrix::zeros(6, n)));
            }
            for d in 0..mb.ndofs() {
                let mut v = mb.generalized_velocity_mut();
                v.fill(0.0);
                v[d] = 1.0;
                mb.update_rigid_body_velocities(&mut scratch);
                for (b, &h) in handles.iter().enumerate() {
                    let rb = &scratch[h];
                    let (lin, ang) = (rb.linvel(), rb.angvel());
                    let column = &mut bodies[start + b].2;
                    for r in 0..3 {
                        column[(r, first + d)] = f64::from(lin[r]);
                        column[(3 + r, first + d)] = f64::from(ang[r]);
                    }
                }
            }
            for (k, armature) in mb.armature().iter().enumerate() {
                mass[(first + k, first + k)] += f64::from(*armature);
            }
            mb.generalized_velocity_mut().fill(0.0);
        }
        // M = Σ Jᵀ·diag(m, I_world)·J over the links.
        for (h, m, columns) in &bodies {
            let rb = &sets.bodies[*h];
            let rotation = Mat3::from_quat(*rb.rotation());
            let local = rb
                .mass_properties()
                .local_mprops
                .reconstruct_inertia_matrix();
            let world = rotation * local * rotation.transpose();
            let mut metric = DMatrix::zeros(6, 6);
            for r in 0..3 {
                metric[(r, r)] = *m;
                for c in 0..3 {
                    metric[(3 + r, 3 + c)] = f64::from(world.col(c)[r]);
                }
            }
            mass += columns.transpose() * &metric * columns;
        }
        let rows = loop_rows(sets, joints, &bodies, n);
        Some(LoopedTrees {
            trees,
            bodies,
            mass,
            rows,
        })
    }

    /// Writes the loop-aware inertia and hold of every actuated DOF of a tree joint on a loop.
    fn set_loads(&self, sets: &Sets, joints: &[JointSlot], gravity: Vector, loads: &mut [DofLoad]) {
        let Some(m_inv) = self.mass.clone().try_inverse() else {
            return;
        };
        let constrained = if self.rows.nrows() == 0 {
            m_inv
        } else {
            let g_m = &self.rows * &m_inv;
            let coupling = &g_m * self.rows.transpose();
            let tolerance = 1e-12 * coupling.norm().max(f64::MIN_POSITIVE);
            let Ok(pinv) = coupling.pseudo_inverse(tolerance) else {
                return;
            };
            &m_inv - g_m.transpose() * pinv * &g_m
        };
        let g = f64::from(gravity.length());
        for slot in joints.iter().filter(|s| s.closing.is_none() && s.on_loop) {
            let Some(&(_, first)) = self.trees.iter().find(|(m, _)| *m == slot.multibody) else {
                continue;
            };
            let Some(link_first) = sets
                .multibody_joints
                .get_multibody(slot.multibody)
                .and_then(|mb| mb.link(slot.link))
                .map(|l| l.assembly_id())
            else {
                continue;
            };
            for k in 0..slot.kind.dof() {
                let i = first + slot.link_dof(link_first, k);
                let p = constrained[(i, i)];
                if !(p > 0.0 && p.is_finite()) {
                    continue;
                }
                let rate = constrained.column(i) / p;
                let hold: f64 = self
                    .bodies
                    .iter()
                    .map(|(_, m, columns)| {
                        let v = columns.rows(0, 3) * &rate;
                        m * g * v.norm()
                    })
                    .sum();
                loads[slot.first_dof + k] = DofLoad {
                    inertia: 1.0 / p,
                    hold,
                };
            }
        }
    }
}

/// The loop joints' locked rows in joint space: for each locked axis of a loop joint, the
/// relative velocity of its two bodies at the joint along that axis, per unit rate of each DOF.
fn loop_rows(
    sets: &Sets,
    joints: &[JointSlot],
    bodies: &[(RigidBodyHandle, f64, DMatrix<f64>)],
    n: usize,
) -> DMatrix<f64> {
    let zero = DMatrix::zeros(6, n);
    let columns = |h: RigidBodyHandle| {
        bodies
            .iter()
            .find(|(b, _, _)| *b == h)
            .map_or(&zero, |(_, _, c)| c)
    };
    let mut rows: Vec<DVector<f64>> = Vec::new();
    for handle in joints.iter().filter_map(|s| s.closing) {
        let Some(joint) = sets.impulse_joints.get(handle) else {
            continue;
        };
        let (b1, b2) = (joint.body1(), joint.body2());
        let frame1 = *sets.bodies[b1].position() * joint.data.local_frame1;
        let anchor = (*sets.bodies[b2].position() * joint.data.local_frame2).translation;
        // The velocity of body `h`'s point at the anchor, per unit rate of each DOF (3 × n).
        let point_velocity = |h: RigidBodyHandle| {
            let c = columns(h);
            let arm = anchor - sets.bodies[h].center_of_mass();
            let mut out = c.rows(0, 3).clone_owned();
            for d in 0..n {
                let w = Vector::new(c[(3, d)] as Real, c[(4, d)] as Real, c[(5, d)] as Real);
                let extra = w.cross(arm);
                for r in 0..3 {
                    out[(r, d)] += f64::from(extra[r]);
                }
            }
            out
        };
        let linear = point_velocity(b2) - point_velocity(b1);
        let angular = columns(b2).rows(3, 3) - columns(b1).rows(3, 3);
        let locked = joint.data.locked_axes;
        for (k, &axis) in crate::world::EVERY_AXIS.iter().enumerate() {
            if !locked.contains(JointAxesMask::from(axis)) {
                continue;
            }
            let dir = frame1.rotation * [Vector::X, Vector::Y, Vector::Z][k % 3];
            let dir = DVector::from_iterator(3, (0..3).map(|r| f64::from(dir[r])));
            let source = if k < 3 { &linear } else { &angular };
            rows.push(source.transpose() * dir);
        }
    }
    if rows.is_empty() {
        return DMatrix::zeros(0, n);
    }
    DMatrix::from_fn(rows.len(), n, |r, c| rows[r][c])
}
