//! Kinematic topology: which joints make the spanning tree of the robot's bodies, and which
//! close kinematic loops.
//!
//! The tree is chosen deterministically, Kruskal-style over the joints in this order:
//! actuated joints in document order, then passive ones, then unobserved ones (which are
//! constraints only and never join the tree). A joint joins the tree when its child has no
//! parent yet, is not a root (the first instance, a plane) and is not already joined to its
//! parent; every other joint whose two bodies the tree joins closes a loop. A document
//! without loops (one parent per child, no cycle) keeps every joint in the tree, whatever
//! the order.

/// One joint as the topology sees it: its two instances and how it prefers to be placed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Edge {
    pub(crate) parent: usize,
    pub(crate) child: usize,
    /// Actuated joints join the tree first (so that a loop's driven joint stays a tree DOF).
    pub(crate) actuated: bool,
    /// Unobserved joints are constraints only: never tree edges.
    pub(crate) observed: bool,
}

/// Where a joint goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Role {
    /// An edge of the spanning tree: a link of a multibody.
    Tree,
    /// A constraint closing a loop between two bodies the tree already joins.
    Loop,
}

/// The spanning tree and the loops: one role per edge (`None` for an edge that could take
/// neither, which validation reports, and for unresolved joints), and each instance's tree
/// parent as (parent instance, joint index).
pub(crate) struct Topology {
    pub(crate) roles: Vec<Option<Role>>,
    pub(crate) parent: Vec<Option<(usize, usize)>>,
}

/// Chooses the tree (see the module documentation). `roots[i]`: instance `i` can never be a
/// child (the first instance, planes, fixed instances, mocap bodies). `world[i]`: instance
/// `i` is held by the world (grounded, or a mocap body the world moves): all such instances
/// count as one body, so that a constraint between two of their trees closes a loop.
pub(crate) fn choose(edges: &[Option<Edge>], roots: &[bool], world: &[bool]) -> Topology {
    let n = roots.len();
    let mut forest = UnionFind::new(n);
    let mut held = (0..n).filter(|&i| world.get(i).copied().unwrap_or(false));
    if let Some(first) = held.next() {
        for other in held {
            forest.union(first, other);
        }
    }
    let mut parent: Vec<Option<(usize, usize)>> = vec![None; n];
    let mut roles: Vec<Option<Role>> = vec![None; edges.len()];
    let rank = |e: &Edge| match (e.observed, e.actuated) {
        (false, _) => 2,
        (true, true) => 0,
        (true, false) => 1,
    };
    let mut order: Vec<usize> = (0..edges.len()).filter(|&j| edges[j].is_some()).collect();
    order.sort_by_key(|&j| edges[j].as_ref().map_or(3, rank));
    for &j in &order {
        let Some(e) = edges[j] else { continue };
        if !e.observed || e.parent == e.child || roots[e.child] || parent[e.child].is_some() {
            continue;
        }
        if forest.union(e.parent, e.child) {
            parent[e.child] = Some((e.parent, j));
            roles[j] = Some(Role::Tree);
        }
    }
    for (j, edge) in edges.iter().enumerate() {
        if let (None, Some(e)) = (roles[j], edge) {
            if e.parent != e.child && forest.find(e.parent) == forest.find(e.child) {
                roles[j] = Some(Role::Loop);
            }
        }
    }
    Topology { roles, parent }
}

impl Topology {
    /// The tree joints on the path between `a` and `b` (both in one tree), by index.
    pub(crate) fn path(&self, a: usize, b: usize) -> Vec<usize> {
        let up = |mut i: usize| {
            let mut chain = vec![(i, None)];
            while let Some((p, j)) = self.parent[i] {
                chain.push((p, Some(j)));
                i = p;
                if chain.len() > self.parent.len() {
                    break; // The tree has no cycles; never spin regardless.
                }
            }
            chain
        };
        let (from_a, from_b) = (up(a), up(b));
        // The lowest common ancestor: the first of a's ancestors (itself included) that is
        // also one of b's.
        let Some(meet) = from_a
            .iter()
            .position(|(i, _)| from_b.iter().any(|(k, _)| k == i))
        else {
            return Vec::new();
        };
        let lca = from_a[meet].0;
        let meet_b = from_b.iter().position(|(k, _)| *k == lca).unwrap_or(0);
        from_a[1..=meet]
            .iter()
            .chain(&from_b[1..=meet_b])
            .filter_map(|(_, j)| *j)
            .collect()
    }
}

/// Disjoint sets over instance indices.
struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n).collect(),
        }
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    /// Joins the sets of `a` and `b`; false when they were already one set.
    fn union(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        self.parent[rb] = ra;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge(parent: usize, child: usize, actuated: bool) -> Option<Edge> {
        Some(Edge {
            parent,
            child,
            actuated,
            observed: true,
        })
    }

    #[test]
    fn a_four_bar_keeps_its_driven_crank_in_the_tree() {
        // ground 0, crank 1, coupler 2, rocker 3; the crank's joint is listed last.
        let edges = [
            edge(1, 2, false),
            edge(2, 3, false),
            edge(0, 3, false),
            edge(0, 1, true),
        ];
        let t = choose(
            &edges,
            &[true, false, false, false],
            &[true, false, false, false],
        );
        use Role::*;
        assert_eq!(t.roles, [Some(Tree), Some(Tree), Some(Loop), Some(Tree)]);
        // The loop's path: rocker 3 -> coupler 2 -> crank 1 -> ground 0.
        let mut path = t.path(0, 3);
        path.sort_unstable();
        assert_eq!(path, [0, 1, 3]);
    }

    #[test]
    fn a_tree_keeps_every_joint_whatever_the_order() {
        let edges = [edge(2, 3, false), edge(0, 1, true), edge(1, 2, true)];
        let t = choose(
            &edges,
            &[true, false, false, false],
            &[true, false, false, false],
        );
        assert!(t.roles.iter().all(|r| *r == Some(Role::Tree)));
    }

    /// A constraint between a tree hanging from the ground and a body the world holds
    /// elsewhere (a plane, a fixed instance, a mocap body) closes a loop.
    #[test]
    fn a_constraint_to_another_body_the_world_holds_closes_a_loop() {
        // ground 0, arm 1, mocap 2 (welded to the arm, unobserved), free body 3.
        let unobserved = |parent, child| {
            edge(parent, child, false).map(|e| Edge {
                observed: false,
                ..e
            })
        };
        let (weld, to_free) = (unobserved(2, 1), unobserved(2, 3));
        let edges = [edge(0, 1, true), weld, to_free];
        let t = choose(
            &edges,
            &[true, false, true, false],
            &[true, false, true, false],
        );
        assert_eq!(t.roles, [Some(Role::Tree), Some(Role::Loop), None]);
    }

    #[test]
    fn a_second_parent_from_another_tree_takes_no_role() {
        // 3 is a free body jointed to 2, whose parent is 1: neither tree nor loop.
        let edges = [edge(0, 1, true), edge(1, 2, true), edge(3, 2, true)];
        let t = choose(
            &edges,
            &[true, false, false, false],
            &[true, false, false, false],
        );
        assert_eq!(t.roles[2], None);
    }
}
