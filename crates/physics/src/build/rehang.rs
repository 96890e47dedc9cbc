//! Trees that one constraint joins but that hang from different static bodies. A coupling
//! or a ranged tendon is enforced inside one multibody (vendored patches 20 and 42), and
//! Rapier makes a multibody of each static body and what hangs from it: the kitchen's
//! light switch hangs from one static body of the hood and the light it couples to from
//! another. Nothing moves a static body, so such trees hang from one of them instead (the
//! same world frame, a different parent handle): their joints' frames are taken on that
//! body, and their children keep not colliding with the body they were jointed to.

use gymfleet_assembly::{Assembly, JointType};

/// For each joint, the static instance it hangs from instead of its parent, if its tree
/// must share a multibody with another static body's (`held`: the instances held fixed).
pub(super) fn rehang_parents(assembly: &Assembly, held: &[bool]) -> Vec<Option<usize>> {
    let n = assembly.instances.len();
    // Each instance's tree anchor: the held instance its chain of tree joints hangs from
    // (itself when held; none for a tree with a moving root).
    let mut parent_of = vec![None; n];
    for j in assembly.joints.iter().filter(|j| !j.closes_loop) {
        parent_of[j.child] = Some(j.parent);
    }
    let anchor = |mut i: usize| -> Option<usize> {
        for _ in 0..=n {
            if held[i] {
                return Some(i);
            }
            i = parent_of[i]?;
        }
        None
    };
    // The instances each constraint's joints and sites move with.
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let children = |terms: &[(usize, f64)]| -> Vec<usize> {
        terms
            .iter()
            .map(|&(j, _)| assembly.joints[j].child)
            .collect()
    };
    for c in &assembly.couplings {
        groups.push(children(&c.terms));
    }
    for t in assembly.tendons.iter().filter(|t| t.range.is_some()) {
        groups.push(if t.is_spatial() {
            t.sites
                .iter()
                .map(|&s| assembly.sites[s].instance)
                .collect()
        } else {
            children(&t.joints)
        });
    }
    // Union the static anchors of each constraint whose every anchor is static.
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    for group in groups {
        let anchors: Option<Vec<usize>> = group
            .iter()
            .filter(|&&i| !held[i])
            .map(|&i| anchor(i))
            .collect();
        let Some(anchors) = anchors else { continue };
        for pair in anchors.windows(2) {
            let (a, b) = (find(&mut root, pair[0]), find(&mut root, pair[1]));
            if a != b {
                root[a.max(b)] = a.min(b);
            }
        }
    }
    assembly
        .joints
        .iter()
        .map(|j| {
            if j.closes_loop || j.kind == JointType::Fixed || !held[j.parent] {
                return None;
            }
            let to = find(&mut root, j.parent);
            (to != j.parent).then_some(to)
        })
        .collect()
}

/// The (child, former parent) instance pairs of rehung joints whose two instances must
/// still not collide: the joint kept them apart, unless the parent is a ground plane.
pub(super) fn rehung_exclusions(
    assembly: &Assembly,
    rehung: &[Option<usize>],
) -> Vec<(usize, usize)> {
    assembly
        .joints
        .iter()
        .zip(rehung)
        .filter(|(j, to)| to.is_some() && !assembly.instances[j.parent].shape.is_ground())
        .map(|(j, _)| (j.child, j.parent))
        .collect()
}
