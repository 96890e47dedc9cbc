//! Trees that hang from one fixed body and share nothing. Rapier makes one multibody of a
//! static body and everything that hangs from it, so Gymnasium's Pusher was one multibody
//! of 11 DOFs: its arm (7), its object (2) and its goal (2), all jointed to the table. Its
//! mass matrix, the matrix's factorisation and every contact's Jacobian were computed over
//! all 11 as if they were coupled. Each such tree beyond the first now hangs from an anchor
//! of its own: a fixed body without colliders at the static body's pose, so that it is a
//! multibody of its own and the dynamics are the same (the joint-space inertia of
//! independent trees is block-diagonal).
//!
//! Trees that one constraint joins stay on one body: a coupling's or tendon's joints and
//! sites, and a loop's two sides (`rehang.rs` hangs such trees from one static body). A
//! split tree's root is no longer jointed to the static body, so, as for a rehung tree, the
//! contact filter keeps the two apart unless the body is a ground plane (what the joint did).

use gymfleet_assembly::Assembly;
use rapier3d::prelude::*;

use super::planar::PlanarRoot;
use crate::world::Sets;

/// Where the trees hang that [`split_trees`] separates.
pub(super) struct Anchors {
    /// For each joint, the anchor it hangs from instead of its parent's body.
    pub(super) of_joint: Vec<Option<RigidBodyHandle>>,
    /// The (child, former parent) instance pairs kept from colliding.
    pub(super) exclusions: Vec<(usize, usize)>,
}

/// Gives every tree beyond the first that hangs from a fixed body, and shares no
/// constraint with the others, an anchor of its own (inserted into `sets`). `rehung`:
/// each joint's static instance from `rehang.rs`; `held`: the instances held fixed.
pub(super) fn split_trees(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    held: &[bool],
    roots: &[PlanarRoot],
    rehung: &[Option<usize>],
) -> Anchors {
    let joints = &assembly.joints;
    let parent_of_joint = |j: usize| rehung[j].unwrap_or(joints[j].parent);
    let mut class = joined_trees(assembly, &tree_roots(assembly, held, rehung));
    // The classes on each fixed body, in the order of their first root joint: the first
    // stays, each other gets an anchor.
    let mut of_joint = vec![None; joints.len()];
    let mut exclusions = Vec::new();
    let mut seen: Vec<(RigidBodyHandle, usize, Option<RigidBodyHandle>)> = Vec::new();
    for (j, joint) in joints.iter().enumerate() {
        if joint.closes_loop || held[joint.child] || !held[parent_of_joint(j)] {
            continue;
        }
        let body = bodies[parent_of_joint(j)];
        if !sets.bodies[body].is_fixed() {
            continue; // A mocap body moves: its trees move with it.
        }
        let c = find(&mut class, j);
        let anchor = match seen.iter().find(|(b, k, _)| *b == body && *k == c) {
            Some(&(_, _, anchor)) => anchor,
            None => {
                let first = !seen.iter().any(|(b, _, _)| *b == body);
                let anchor = (!first).then(|| {
                    let pose = *sets.bodies[body].position();
                    sets.bodies
                        .insert(RigidBodyBuilder::fixed().pose(pose).build())
                });
                seen.push((body, c, anchor));
                anchor
            }
        };
        of_joint[j] = anchor;
        if anchor.is_some() && !assembly.instances[joint.parent].shape.is_ground() {
            exclusions.push((joint.child, joint.parent));
        }
    }
    // A planar root's fused hinge hangs from the fixed instance above its chain.
    for r in roots {
        if let Some(anchor) = r.joints.iter().find_map(|&j| of_joint[j]) {
            of_joint[r.joints[2]] = Some(anchor);
            if !assembly.instances[r.parent].shape.is_ground() {
                exclusions.push((r.body, r.parent));
            }
        }
    }
    Anchors {
        of_joint,
        exclusions,
    }
}

/// For each instance, the root joint of the tree it belongs to: the joint that hangs it,
/// or an instance above it, from a held instance (none when held or on a moving root).
fn tree_roots(assembly: &Assembly, held: &[bool], rehung: &[Option<usize>]) -> Vec<Option<usize>> {
    let n = assembly.instances.len();
    let joints = &assembly.joints;
    let mut up = vec![None; n];
    for (j, joint) in joints.iter().enumerate().filter(|(_, j)| !j.closes_loop) {
        up[joint.child] = Some(j);
    }
    let tree_of = |mut i: usize| -> Option<usize> {
        for _ in 0..=n {
            if held[i] {
                return None;
            }
            let j = up[i]?;
            if held[rehung[j].unwrap_or(joints[j].parent)] {
                return Some(j);
            }
            i = joints[j].parent;
        }
        None
    };
    (0..n).map(tree_of).collect()
}

/// The trees (by root joint) that one constraint joins, as a union-find over the joints:
/// a coupling's or tendon's joints and sites, a loop's two sides.
fn joined_trees(assembly: &Assembly, tree_of: &[Option<usize>]) -> Vec<usize> {
    let joints = &assembly.joints;
    let children = |terms: &[(usize, f64)]| terms.iter().map(|&(j, _)| joints[j].child).collect();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    groups.extend(assembly.couplings.iter().map(|c| children(&c.terms)));
    for t in &assembly.tendons {
        let mut members: Vec<usize> = children(&t.joints);
        members.extend(t.sites.iter().map(|&s| assembly.sites[s].instance));
        groups.push(members);
    }
    let loops = joints.iter().filter(|j| j.closes_loop);
    groups.extend(loops.map(|j| vec![j.parent, j.child]));
    let mut class: Vec<usize> = (0..joints.len()).collect();
    for group in groups {
        let trees: Vec<usize> = group.iter().filter_map(|&i| tree_of[i]).collect();
        for pair in trees.windows(2) {
            let (a, b) = (find(&mut class, pair[0]), find(&mut class, pair[1]));
            if a != b {
                class[a.max(b)] = a.min(b);
            }
        }
    }
    class
}

/// The union-find's representative of `j`.
fn find(class: &mut [usize], mut j: usize) -> usize {
    while class[j] != j {
        class[j] = class[class[j]];
        j = class[j];
    }
    j
}

#[cfg(test)]
mod tests {
    use crate::{RobotWorld, WorldOptions};

    /// Three arms hinged side by side on a base (`actuators.rs`' test arms), `couplings`
    /// (JSON) between them.
    fn arms(couplings: &str) -> RobotWorld {
        let assembly = crate::actuators::tests::arms_with(&format!("\"couplings\": {couplings}"));
        RobotWorld::new(&assembly, &WorldOptions::default()).unwrap()
    }

    #[test]
    fn independent_trees_on_one_fixed_body_are_multibodies_of_their_own() {
        let world = arms("[]");
        let trees: Vec<_> = world.joints.iter().map(|j| j.multibody).collect();
        assert_ne!(trees[0], trees[1]);
        assert_ne!(trees[1], trees[2]);
        assert_ne!(trees[0], trees[2]);
        assert_eq!(world.live.multibody_joints.multibodies().count(), 3);
        // The arms hang from anchors at the base's pose, the first from the base itself.
        let base = world.bodies[0];
        assert_eq!(world.joints[0].parent, base);
        for slot in &world.joints[1..] {
            assert_ne!(slot.parent, base);
            assert!(world.live.bodies[slot.parent].is_fixed());
            assert!(world.live.bodies[slot.parent].colliders().is_empty());
            assert_eq!(
                world.live.bodies[slot.parent].position(),
                world.live.bodies[base].position()
            );
        }
        // The split arms still do not collide with the base they are jointed to.
        for arm in [2, 3] {
            assert!(world.contact_filter.excludes(world.bodies[arm], base));
        }
    }

    #[test]
    fn trees_a_constraint_joins_stay_one_multibody() {
        let world = arms(r#"[{"name": "gear", "joint1": "b", "joint2": "c"}]"#);
        let trees: Vec<_> = world.joints.iter().map(|j| j.multibody).collect();
        assert_ne!(trees[0], trees[1]);
        assert_eq!(trees[1], trees[2]);
        assert_eq!(world.live.multibody_joints.multibodies().count(), 2);
    }
}
