//! The multibody trees of a [`crate::RobotWorld`]: which instances are held fixed, the
//! joints' frames and Rapier descriptions, inserting the trees parents first, placing
//! floating ones, and the joints' initial positions.

use gymfleet_assembly::{Assembly, Joint, JointType};
use rapier3d::prelude::*;

use super::planar::{fused_joint, PlanarRoot};
use crate::error::{PhysicsError, Result};
use crate::world::{Lane, Sets};

/// Inserts every joint that does not close a loop into the multibody trees, parents
/// before children (each insertion appends one link); returns every joint's two frames.
pub(super) fn insert_trees(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    welded_away: &[bool],
    roots: &[PlanarRoot],
    (rehung, anchors): (&[Option<usize>], &[Option<RigidBodyHandle>]),
) -> Result<Vec<(Pose, Pose)>> {
    // Parents before children, so each insertion appends one link to a tree.
    let mut order: Vec<usize> = (0..assembly.joints.len()).collect();
    let depth = depths(assembly);
    order.sort_by_key(|&j| depth[assembly.joints[j].child]);
    let mut frames = vec![(Pose::IDENTITY, Pose::IDENTITY); assembly.joints.len()];
    for &j in &order {
        let joint = &assembly.joints[j];
        // A tree rehung on another static body (`rehang.rs`) hangs from that one.
        // A tree split from the others on its fixed body (`split.rs`) hangs from its anchor.
        let parent = anchors[j].unwrap_or(bodies[rehung[j].unwrap_or(joint.parent)]);
        let child = bodies[joint.child];
        let (f1, f2) = joint_frames(&sets.bodies, parent, child, joint);
        frames[j] = (f1, f2);
        if joint.closes_loop {
            continue; // Added once the trees are complete (`loops.rs`).
        }
        if welded_away[joint.child] {
            continue; // Held fixed or folded (a planar root's helper): no link of its own.
        }
        // A planar root's hinge: the whole root, from the fixed instance above it.
        let root = roots.iter().find(|r| r.joints[2] == j);
        let (parent, top) = match root {
            Some(r) => (anchors[j].unwrap_or(bodies[r.parent]), r.parent),
            None => (parent, joint.parent),
        };
        // A ground plane collides with what is jointed to it too (MuJoCo never filters
        // the world body's geoms): only the plane stops a link from falling through.
        // A rehung or split child is no child of its new parent: the contact filter keeps it from
        // its former one instead.
        let contacts = assembly.instances[top].shape.is_ground()
            || rehung[j].is_some()
            || anchors[j].is_some();
        let data = match root {
            Some(r) => {
                let (parent_pose, body_pose) = (
                    sets.bodies[parent].position(),
                    sets.bodies[child].position(),
                );
                let data = fused_joint(assembly, r, parent_pose, body_pose, contacts);
                for &k in &r.joints {
                    frames[k] = (data.local_frame1, data.local_frame2);
                }
                data
            }
            None => generic_joint(joint, f1, f2, contacts),
        };
        sets.multibody_joints
            .insert(parent, child, data, true)
            .ok_or_else(|| PhysicsError::BadOption {
                field: "assembly.joints",
                reason: format!(
                    "joint {:?} could not be added to the multibody tree",
                    joint.name
                ),
            })?;
    }
    Ok(frames)
}

/// Runs forward kinematics once on every tree: one on a dynamic root (a floating base)
/// sits at Rapier's origin until a step reads the root body's pose.
pub(super) fn place_floating_trees(sets: &mut Sets) {
    // A tree whose root is dynamic (a floating base) starts as Rapier's free root at the
    // origin until a step reads the root body's pose: read it now, so that everything
    // below (initial positions, gains) sees the tree where the document places it.
    let trees: Vec<MultibodyIndex> = sets
        .multibody_joints
        .multibodies()
        .map(|mb| mb.root().rigid_body_handle())
        .filter_map(|root| Some(sets.multibody_joints.rigid_body_link(root)?.multibody))
        .collect();
    for &index in &trees {
        if let Some(mb) = sets.multibody_joints.get_multibody_mut(index) {
            mb.forward_kinematics(&sets.bodies, true);
            mb.update_rigid_bodies(&mut sets.bodies, true);
        }
    }
}

/// Which instances are fixed bodies: the grounded ones, and those welded to one by a
/// fixed joint of a tree, transitively (a URDF's base on its `world` link, MuJoCo bodies
/// without joints under the world body, such as Reacher's arena). A weld to the ground
/// never moves; as a link of a tree it would still cost kinematics and mass-matrix work
/// every substep. Its pose, collider and readouts are the same either way.
pub(super) fn held_fixed(assembly: &Assembly) -> Vec<bool> {
    let mut held: Vec<bool> = assembly.instances.iter().map(|i| i.grounded).collect();
    loop {
        let mut changed = false;
        for joint in &assembly.joints {
            if joint.kind == JointType::Fixed
                && !joint.closes_loop
                && held[joint.parent]
                && !held[joint.child]
            {
                held[joint.child] = true;
                changed = true;
            }
        }
        if !changed {
            return held;
        }
    }
}

/// The instance whose body each instance is part of. An instance welded (by a fixed joint
/// of a tree) to a moving one is folded into that one's body, transitively: its collider
/// rides on the body of the first instance of its weld chain, and no tree link is spent
/// on a joint that never moves (MuJoCo's multi-geom bodies come as such welds: a
/// Humanoid's head, hands and feet, the Ant's leg roots, Pusher's arm). Every other
/// instance owns its body. Welds to the ground are [`held_fixed`]'s.
pub(super) fn fold_owners(assembly: &Assembly, held: &[bool]) -> Vec<usize> {
    let mut owners: Vec<usize> = (0..assembly.instances.len()).collect();
    loop {
        let mut changed = false;
        for joint in &assembly.joints {
            if joint.kind == JointType::Fixed
                && !joint.closes_loop
                && !held[joint.parent]
                && !held[joint.child]
                && owners[joint.child] != owners[joint.parent]
            {
                owners[joint.child] = owners[joint.parent];
                changed = true;
            }
        }
        if !changed {
            return owners;
        }
    }
}

/// The loop-closing joints' frames taken again at the bodies' poses now: after the
/// joints' initial positions, a constraint holds the pose the world starts in. Nothing on a
/// loop's own path moves there (`initial` is refused on it), so only a constraint to a body
/// outside the tree's path (a mocap body, the world's geometry) changes: its partner may
/// have moved with the joints below it.
pub(super) fn refresh_loop_frames(
    sets: &Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    frames: &mut [(Pose, Pose)],
) {
    for (j, joint) in assembly.joints.iter().enumerate() {
        if joint.closes_loop {
            let (parent, child) = (bodies[joint.parent], bodies[joint.child]);
            let (f1, _) = joint_frames(&sets.bodies, parent, child, joint);
            // The child's frame: where the parent's frame is, seen from the child now.
            let world = *sets.bodies[parent].position() * f1;
            frames[j] = (f1, sets.bodies[child].position().inverse() * world);
        }
    }
}

/// Depth of each instance in the joint forest (roots are 0).
fn depths(assembly: &Assembly) -> Vec<usize> {
    let mut parent = vec![None; assembly.instances.len()];
    for joint in assembly.joints.iter().filter(|j| !j.closes_loop) {
        parent[joint.child] = Some(joint.parent);
    }
    (0..assembly.instances.len())
        .map(|mut i| {
            let mut d = 0;
            while let Some(p) = parent[i] {
                d += 1;
                i = p;
                if d > parent.len() {
                    break; // Validation rules out loops; never spin regardless.
                }
            }
            d
        })
        .collect()
}

/// The joint frame (origin at the anchor, X along the axis) in each body's local frame.
fn joint_frames(
    bodies: &RigidBodySet,
    parent: RigidBodyHandle,
    child: RigidBodyHandle,
    joint: &Joint,
) -> (Pose, Pose) {
    let [ax, ay, az] = joint.axis.map(|c| c as Real);
    let [px, py, pz] = joint.anchor.map(|c| c as Real);
    let rotation = Rotation::from_rotation_arc(Vector::X, Vector::new(ax, ay, az).normalize());
    let world = Pose::from_parts(Vector::new(px, py, pz), rotation);
    let f1 = bodies[parent].position().inverse() * world;
    let f2 = bodies[child].position().inverse() * world;
    (f1, f2)
}

/// `contacts`: whether the two instances still collide (a ground plane and what hangs on it).
pub(super) fn generic_joint(joint: &Joint, f1: Pose, f2: Pose, contacts: bool) -> GenericJoint {
    let locked = match joint.kind {
        JointType::Revolute => JointAxesMask::LOCKED_REVOLUTE_AXES,
        JointType::Prismatic => JointAxesMask::LOCKED_PRISMATIC_AXES,
        JointType::Cylindrical => {
            JointAxesMask::LIN_Y
                | JointAxesMask::LIN_Z
                | JointAxesMask::ANG_Y
                | JointAxesMask::ANG_Z
        }
        JointType::Ball => JointAxesMask::LOCKED_SPHERICAL_AXES,
        JointType::Fixed => JointAxesMask::LOCKED_FIXED_AXES,
    };
    let mut builder = GenericJointBuilder::new(locked)
        .local_frame1(f1)
        .local_frame2(f2)
        .contacts_enabled(contacts);
    if let Some([min, max]) = joint.limits {
        let axis = match joint.kind {
            JointType::Prismatic => JointAxis::LinX,
            _ => JointAxis::AngX,
        };
        builder = builder.limits(axis, [min as Real, max as Real]);
    }
    builder.build()
}

/// Moves every joint with an `initial` position there (from the document's pose, where
/// the multibodies were built), so that the world's initial state, which every reset
/// restores, starts there; rigid bodies and their colliders follow.
pub(super) fn apply_initial_positions(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    lanes: &[Option<Lane>],
) -> Result<()> {
    let mut touched: Vec<MultibodyIndex> = Vec::new();
    for (joint, lane) in assembly
        .joints
        .iter()
        .zip(lanes)
        .filter(|(j, _)| j.initial != 0.0)
    {
        let link = sets
            .multibody_joints
            .rigid_body_link(bodies[joint.child])
            .copied()
            .ok_or_else(|| PhysicsError::BadOption {
                field: "assembly.joints",
                reason: format!("joint {:?} has no multibody link", joint.name),
            })?;
        let Some(mb) = sets.multibody_joints.get_multibody_mut(link.multibody) else {
            continue;
        };
        let Some(first) = mb.link(link.id).map(|l| l.assembly_id()) else {
            continue;
        };
        let mut disp = vec![0.0; mb.ndofs()];
        disp[first + lane.map_or(0, |l| l.offset)] = joint.initial as Real;
        mb.apply_displacements(&disp);
        if !touched.contains(&link.multibody) {
            touched.push(link.multibody);
        }
    }
    if touched.is_empty() {
        return Ok(());
    }
    for index in touched {
        if let Some(mb) = sets.multibody_joints.get_multibody_mut(index) {
            mb.forward_kinematics(&sets.bodies, true);
            mb.update_rigid_bodies(&mut sets.bodies, true);
        }
    }
    // Colliders follow their bodies now, not at the first step: a scene drawn before it
    // shows the robot where it is.
    for (_, co) in sets.colliders.iter_mut() {
        if let Some(parent) = co.parent() {
            let wrt = co.position_wrt_parent().copied().unwrap_or(Pose::IDENTITY);
            co.set_position(*sets.bodies[parent].position() * wrt);
        }
    }
    Ok(())
}
