//! MuJoCo's contact exclusions: geoms of one body never collide, nor do a body's and its
//! parent's (`filterparent`), unless the parent is the world. Here a body is a rigid
//! group (instances welded by fixed joints), and a group's parent is the group a joint
//! connects it to, looking through groups that collide with nothing (the helper instances
//! an MJCF body with several joints becomes). Directly jointed instances are already kept
//! apart by their joint (`contacts_enabled`); this adds the rest as a contact-pair hook.

use std::collections::HashSet;
use std::sync::Arc;

use gymfleet_assembly::{Assembly, JointType};
use rapier3d::prelude::*;

use crate::world::{ContactFilter, ExplicitPair, Sets};

fn key(a: RigidBodyHandle, b: RigidBodyHandle) -> (RigidBodyHandle, RigidBodyHandle) {
    if a.into_raw_parts() <= b.into_raw_parts() {
        (a, b)
    } else {
        (b, a)
    }
}

/// A pair's order in [`ContactFilter::excluded`].
fn order(pair: &(RigidBodyHandle, RigidBodyHandle)) -> ((u32, u32), (u32, u32)) {
    (pair.0.into_raw_parts(), pair.1.into_raw_parts())
}

/// The collision group bit an explicit pair's colliders share, so that Rapier's group test
/// lets them meet; the hook then decides by their own bits, kept in `user_data`.
const PAIR_BIT: u32 = 1 << 31;
/// Marks a collider's `user_data` as holding its own `(group, mask)` bits, low 64 bits.
const OWN_BITS: u128 = 1 << 127;

/// A collider's own collision bits, `(group, mask)`: kept in `user_data` for a collider an
/// explicit pair widened, else its groups.
fn own_bits(collider: &Collider) -> (u32, u32) {
    let data = collider.user_data;
    if data & OWN_BITS != 0 {
        (data as u32, (data >> 32) as u32)
    } else {
        let g = collider.collision_groups();
        (g.memberships.bits(), g.filter.bits())
    }
}

fn collider_key(a: ColliderHandle, b: ColliderHandle) -> (ColliderHandle, ColliderHandle) {
    if a.into_raw_parts() <= b.into_raw_parts() {
        (a, b)
    } else {
        (b, a)
    }
}

impl ContactFilter {
    /// The explicit pair of colliders `a` and `b`, if they are one: its friction.
    fn pair(&self, a: ColliderHandle, b: ColliderHandle) -> Option<Option<Real>> {
        let wanted = collider_key(a, b);
        let raw =
            |(x, y): (ColliderHandle, ColliderHandle)| (x.into_raw_parts(), y.into_raw_parts());
        self.pairs
            .binary_search_by(|(pair, _)| raw(*pair).cmp(&raw(wanted)))
            .ok()
            .map(|k| self.pairs[k].1)
    }

    /// Whether bodies `a` and `b` are kept from colliding.
    pub(crate) fn excludes(&self, a: RigidBodyHandle, b: RigidBodyHandle) -> bool {
        let wanted = order(&key(a, b));
        // A binary search of a few pairs: the hook runs for every pair the broad phase
        // finds, every step, and a hashed lookup cost about 380 instructions.
        self.excluded
            .binary_search_by(|pair| order(pair).cmp(&wanted))
            .is_ok()
    }
}

impl PhysicsHooks for ContactFilter {
    fn filter_contact_pair(&self, context: &PairFilterContext) -> Option<SolverFlags> {
        // Rapier's own rule, which a hook replaces: two bodies that cannot move never meet.
        let moves = |h: Option<RigidBodyHandle>| {
            h.and_then(|h| context.bodies.get(h))
                .is_some_and(|rb| rb.is_dynamic())
        };
        if !moves(context.rigid_body1) && !moves(context.rigid_body2) {
            return None;
        }
        let (c1, c2) = (context.collider1, context.collider2);
        if self.pair(c1, c2).is_some() {
            return Some(SolverFlags::default());
        }
        // A pair's colliders met through the pair's bit: their own bits decide.
        let (g1, m1) = own_bits(&context.colliders[c1]);
        let (g2, m2) = own_bits(&context.colliders[c2]);
        if g1 & m2 == 0 && g2 & m1 == 0 {
            return None;
        }
        match (context.rigid_body1, context.rigid_body2) {
            (Some(a), Some(b)) if self.excludes(a, b) => None,
            _ => Some(SolverFlags::default()),
        }
    }

    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        if let Some(Some(friction)) = self.pair(context.collider1, context.collider2) {
            if let Some(manifold) = context.rigid_mut() {
                *manifold.friction = friction;
            }
        }
    }
}

/// Each instance's rigid group: instances welded by fixed joints share one, numbered by
/// their first instance.
pub(crate) fn rigid_groups(assembly: &Assembly) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..assembly.instances.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for joint in assembly
        .joints
        .iter()
        .filter(|j| j.kind == JointType::Fixed)
    {
        let (a, b) = (
            root(&mut parent, joint.parent),
            root(&mut parent, joint.child),
        );
        parent[a.max(b)] = a.min(b);
    }
    (0..parent.len()).map(|i| root(&mut parent, i)).collect()
}

/// The exclusions of `assembly` (built on `bodies`), with the hook flag set on the
/// colliders they concern.
pub(crate) fn contact_filter(
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    colliders: &[ColliderHandle],
    rehung: &[(usize, usize)],
    sets: &mut Sets,
) -> ContactFilter {
    let group = rigid_groups(assembly);
    let n = assembly.instances.len();
    let collides = |i: usize| assembly.instances[i].collision != (0, 0);
    let pairs = neighbour_groups(assembly, &group);
    // Each group's colliding instances.
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in (0..n).filter(|&i| collides(i)) {
        members[group[i]].push(i);
    }
    let mut excluded = Vec::new();
    let mut hooked = HashSet::new();
    // The document's exclusions, and a rehung child's from its former parent.
    for &(i, j) in assembly.contacts.exclude.iter().chain(rehung) {
        if bodies[i] != bodies[j] {
            excluded.push(key(bodies[i], bodies[j]));
            hooked.extend([bodies[i], bodies[j]]);
        }
    }
    for &(g, h) in &pairs {
        for &i in &members[g] {
            for &j in members[h].iter().filter(|&&j| j != i) {
                excluded.push(key(bodies[i], bodies[j]));
                hooked.extend([bodies[i], bodies[j]]);
            }
        }
    }
    excluded.sort_by_key(order);
    excluded.dedup();
    for body in hooked {
        for &c in sets.bodies[body].colliders() {
            if let Some(collider) = sets.colliders.get_mut(c) {
                let hooks = collider.active_hooks() | ActiveHooks::FILTER_CONTACT_PAIRS;
                collider.set_active_hooks(hooks);
            }
        }
    }
    let pairs = explicit_pairs(assembly, colliders, sets);
    ContactFilter {
        excluded: Arc::from(excluded),
        pairs,
    }
}

/// The pairs of rigid groups (`group[i]`: instance `i`'s) kept from colliding: each
/// colliding, ungrounded group with itself and with the colliding, ungrounded groups one
/// joint away, through groups that collide with nothing.
fn neighbour_groups(assembly: &Assembly, group: &[usize]) -> HashSet<(usize, usize)> {
    let n = assembly.instances.len();
    let collides = |i: usize| assembly.instances[i].collision != (0, 0);
    let mut grounded_group = vec![false; n];
    let mut colliding_group = vec![false; n];
    for i in 0..n {
        grounded_group[group[i]] |= assembly.instances[i].grounded;
        colliding_group[group[i]] |= collides(i);
    }
    let grounded = |g: usize| grounded_group[g];
    let transparent = |g: usize| !colliding_group[g];
    // Joints between groups (fixed joints are inside them).
    let mut edges: Vec<Vec<usize>> = vec![Vec::new(); n];
    for j in assembly
        .joints
        .iter()
        .filter(|j| j.kind != JointType::Fixed)
    {
        let (a, b) = (group[j.parent], group[j.child]);
        edges[a].push(b);
        edges[b].push(a);
    }
    let mut pairs: HashSet<(usize, usize)> = HashSet::new();
    for g in (0..n).filter(|&g| group[g] == g && !transparent(g) && !grounded(g)) {
        pairs.insert((g, g));
        // The colliding groups one joint away, through groups that collide with nothing.
        let mut seen = vec![false; n];
        seen[g] = true;
        let mut stack = edges[g].clone();
        while let Some(h) = stack.pop() {
            if std::mem::replace(&mut seen[h], true) {
                continue;
            }
            if transparent(h) {
                stack.extend(edges[h].iter().copied());
            } else if !grounded(h) {
                pairs.insert((g.min(h), g.max(h)));
            }
        }
    }
    pairs
}

/// The document's explicit pairs on their colliders: each collider of one widened to meet
/// the others through [`PAIR_BIT`] (its own bits kept in `user_data` for the hook) and
/// hooked, to filter and to set the pair's friction.
fn explicit_pairs(
    assembly: &Assembly,
    colliders: &[ColliderHandle],
    sets: &mut Sets,
) -> Arc<[ExplicitPair]> {
    let mut pairs: Vec<ExplicitPair> = assembly
        .contacts
        .pairs
        .iter()
        .map(|p| {
            (
                collider_key(colliders[p.a], colliders[p.b]),
                p.friction.map(|f| f as Real),
            )
        })
        .collect();
    let raw = |(x, y): (ColliderHandle, ColliderHandle)| (x.into_raw_parts(), y.into_raw_parts());
    pairs.sort_by_key(|(pair, _)| raw(*pair));
    // The last rule for a pair wins, as MuJoCo keeps the last <pair> of two geoms.
    pairs.reverse();
    pairs.dedup_by_key(|(pair, _)| raw(*pair));
    pairs.reverse();
    for &((a, b), _) in &pairs {
        for c in [a, b] {
            let Some(collider) = sets.colliders.get_mut(c) else {
                continue;
            };
            if collider.user_data & OWN_BITS == 0 {
                let g = collider.collision_groups();
                let (group, mask) = (g.memberships.bits(), g.filter.bits());
                collider.user_data = OWN_BITS | u128::from(group) | (u128::from(mask) << 32);
                collider.set_collision_groups(InteractionGroups::new(
                    Group::from_bits_retain(group | PAIR_BIT),
                    Group::from_bits_retain(mask | PAIR_BIT),
                    InteractionTestMode::Or,
                ));
            }
            let hooks = collider.active_hooks()
                | ActiveHooks::FILTER_CONTACT_PAIRS
                | ActiveHooks::MODIFY_SOLVER_CONTACTS;
            collider.set_active_hooks(hooks);
        }
    }
    Arc::from(pairs)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn handle(index: u32, generation: u32) -> RigidBodyHandle {
        RigidBodyHandle::from_raw_parts(index, generation)
    }

    #[test]
    fn a_pair_is_excluded_in_either_order_and_no_other_is() {
        let pairs = [(3, 0), (1, 0), (7, 2), (2, 0), (1, 1)];
        let mut excluded: Vec<_> = pairs
            .windows(2)
            .map(|w| key(handle(w[0].0, w[0].1), handle(w[1].0, w[1].1)))
            .collect();
        excluded.sort_by_key(order);
        let filter = ContactFilter {
            excluded: Arc::from(excluded),
            pairs: Arc::from([]),
        };
        for w in pairs.windows(2) {
            let (a, b) = (handle(w[0].0, w[0].1), handle(w[1].0, w[1].1));
            assert!(
                filter.excludes(a, b) && filter.excludes(b, a),
                "{a:?} {b:?}"
            );
        }
        // Same indices, another generation; and a pair of two listed bodies never listed.
        assert!(!filter.excludes(handle(3, 1), handle(1, 0)));
        assert!(!filter.excludes(handle(3, 0), handle(2, 0)));
        assert!(!filter.excludes(handle(1, 0), handle(1, 1)));
    }
}
