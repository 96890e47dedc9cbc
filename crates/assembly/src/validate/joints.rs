//! Joints: each joint's ends, its place in the tree or a loop (the topology's rules), and
//! its terms through `joint_terms.rs`.

use std::collections::hash_map::Entry;
use std::collections::HashMap;

use crate::document::{InstanceDef, JointDef};
use crate::error::quoted;
use crate::model::{Joint, JointType, MM_PER_M};
use crate::topology::{Edge, Role, Topology};

use super::{limit_to_si, list, Anchor, Roots, Validator};

/// The joints' graph: the instances by name, and the spanning tree and the loops chosen
/// from the joints whose instances resolve (their references are reported joint by joint).
struct JointGraph<'a> {
    index: HashMap<&'a str, usize>,
    topology: Topology,
    /// Each joint on a loop's path, with the joint that closes that loop.
    on_loop: Vec<Option<usize>>,
}

impl<'a> JointGraph<'a> {
    fn new(defs: &[JointDef], instances: &'a [InstanceDef], roots_of: Roots<'_>) -> Self {
        // Look names up in the document's instances, so that one bad instance does not
        // turn every joint that names it into a second, misleading error.
        let mut index: HashMap<&str, usize> = HashMap::new();
        for (i, inst) in instances.iter().enumerate() {
            index.entry(inst.name.as_str()).or_insert(i);
        }
        let edges: Vec<Option<Edge>> = defs
            .iter()
            .map(|def| {
                Some(Edge {
                    parent: *index.get(def.parent.as_str())?,
                    child: *index.get(def.child.as_str())?,
                    actuated: def.actuated.unwrap_or(true),
                    observed: def.observed.unwrap_or(true),
                })
            })
            .collect();
        let roots: Vec<bool> = (0..instances.len())
            .map(|i| i == 0 || roots_of.anchor(i) != Anchor::None)
            .collect();
        let world: Vec<bool> = (0..instances.len()).map(|i| roots_of.held(i)).collect();
        let topology = crate::topology::choose(&edges, &roots, &world);
        let mut on_loop: Vec<Option<usize>> = vec![None; defs.len()];
        for (j, edge) in edges.iter().enumerate() {
            if let (Some(Role::Loop), Some(e)) = (topology.roles[j], edge) {
                on_loop[j].get_or_insert(j);
                for k in topology.path(e.parent, e.child) {
                    on_loop[k].get_or_insert(j);
                }
            }
        }
        JointGraph {
            index,
            topology,
            on_loop,
        }
    }
}

/// What every joint's checks share: the document's joints and instances, what roots the
/// trees, the graph, and the names taken so far.
struct JointsContext<'d> {
    defs: &'d [JointDef],
    instances: &'d [InstanceDef],
    roots_of: Roots<'d>,
    graph: JointGraph<'d>,
    names: HashMap<String, usize>,
}

impl Validator {
    pub(super) fn joints(
        &mut self,
        defs: &[JointDef],
        instances: &[InstanceDef],
        anchors: &[Anchor],
        floating_base: bool,
    ) -> Vec<Joint> {
        let roots_of = Roots {
            anchors,
            floating_base,
        };
        let mut cx = JointsContext {
            defs,
            instances,
            roots_of,
            graph: JointGraph::new(defs, instances, roots_of),
            names: HashMap::new(),
        };
        let mut out = Vec::with_capacity(defs.len());
        for (j, def) in defs.iter().enumerate() {
            out.extend(self.joint(j, def, &mut cx));
        }
        out
    }

    /// Joint `j`: every check of it, in order, and the joint when none failed.
    fn joint(&mut self, j: usize, def: &JointDef, cx: &mut JointsContext<'_>) -> Option<Joint> {
        let path = format!("assembly.joints[{j}]");
        let before = self.issues.len();
        let parent = self.instance_ref(&format!("{path}.parent"), &def.parent, &cx.graph.index);
        let child = self.instance_ref(&format!("{path}.child"), &def.child, &cx.graph.index);
        let name = self.joint_name(&path, j, def, cx);
        let anchor = self.anchor(&path, def);
        let axis = self.axis(&path, def);
        let document_limits = self.limits(&path, def);
        let initial = self.initial(&path, def, document_limits);
        let damping = self.non_negative(&format!("{path}.damping"), def.damping, "damping");
        let armature = self.dof_quantity(
            &path,
            def,
            ("armature", def.armature),
            "an armature >= 0 (kg·m² or kg)",
            "to add armature to",
        );
        let (stiffness, spring_rest) = self.spring(&path, def);
        let friction = self.dof_quantity(
            &path,
            def,
            ("friction", def.friction),
            "a friction >= 0 (N·m or N)",
            "to resist with friction",
        );
        let soft_limit = self.soft_limit(&path, def, document_limits);
        let role = cx.graph.topology.roles[j];
        // A loop-closing joint is passive (a driven one is refused in `topology`).
        let actuated = def.actuated.unwrap_or(true) && role != Some(Role::Loop);
        self.initial_off_loop(
            &path,
            def,
            cx.graph.on_loop[j].map(|k| &cx.defs[k]),
            initial,
        );
        let (gear, reference) = self.gear_and_reference(&path, def, actuated);
        let max_effort = self.max_effort(&path, def, actuated);
        let (parent, child) = (parent?, child?);
        let topology = &cx.graph.topology;
        self.topology(
            &path,
            def,
            (parent, child),
            role,
            topology,
            cx.instances,
            cx.roots_of,
        );
        if self.issues.len() != before {
            return None;
        }
        let si = limit_to_si(def.kind);
        Some(Joint {
            name,
            kind: def.kind,
            parent,
            child,
            anchor,
            axis,
            limits: document_limits.map(|l| l.map(|v| v * si)),
            document_limits,
            damping: damping.unwrap_or(0.0),
            max_effort,
            actuated,
            armature: armature.unwrap_or(0.0),
            initial: initial * si,
            stiffness,
            spring_rest: spring_rest * si,
            springdamper: self.springdamper(&path, def),
            friction: friction.unwrap_or(0.0),
            gear,
            reference,
            closes_loop: role == Some(Role::Loop),
            observed: def.observed.unwrap_or(true),
            on_loop: cx.graph.on_loop[j].is_some(),
            soft_limit,
        })
    }

    /// The joint's name (its child's when it has none), refused when another joint has it.
    fn joint_name(
        &mut self,
        path: &str,
        j: usize,
        def: &JointDef,
        cx: &mut JointsContext<'_>,
    ) -> String {
        let name = def.name.clone().unwrap_or_else(|| def.child.clone());
        match cx.names.entry(name.clone()) {
            // A defaulted name clashes with a joint of the same child: that is a
            // child with two parents, which `topology` reports on `child`.
            Entry::Occupied(first)
                if def.name.is_none()
                    && cx.defs[*first.get()].child == def.child
                    && cx.graph.topology.roles[j].is_none() => {}
            Entry::Occupied(first) => self.push(
                format!("{path}.name"),
                format!(
                    "duplicate joint name {} (also assembly.joints[{}]); give one of them a \"name\"",
                    quoted(&name),
                    first.get()
                ),
            ),
            Entry::Vacant(slot) => {
                slot.insert(j);
            }
        }
        name
    }

    /// The anchor in world m: required but for a fixed joint (the origin then).
    fn anchor(&mut self, path: &str, def: &JointDef) -> [f64; 3] {
        match def.anchor {
            Some(a) => self
                .vec3(&format!("{path}.anchor"), a)
                .map(|c| c / MM_PER_M),
            None if def.kind == JointType::Fixed => [0.0; 3],
            None => {
                self.push(
                    format!("{path}.anchor"),
                    format!(
                        "missing field `anchor`: a {} joint needs an anchor (world mm)",
                        def.kind.as_str()
                    ),
                );
                [0.0; 3]
            }
        }
    }

    /// Refuses an initial position on a joint of a kinematic loop (`closer` closes it).
    fn initial_off_loop(
        &mut self,
        path: &str,
        def: &JointDef,
        closer: Option<&JointDef>,
        initial: f64,
    ) {
        let Some(closer) = closer.filter(|_| initial != 0.0) else {
            return;
        };
        self.push(
            format!("{path}.initial"),
            format!(
                "joint {} is on the kinematic loop that joint {} closes; an initial position would open the loop (loops start at the document's pose): remove \"initial\"",
                quoted(def.name.as_deref().unwrap_or(&def.child)),
                quoted(closer.name.as_deref().unwrap_or(&closer.child))
            ),
        );
    }

    pub(super) fn instance_ref(
        &mut self,
        path: &str,
        name: &str,
        index: &HashMap<&str, usize>,
    ) -> Option<usize> {
        let found = index.get(name).copied();
        if found.is_none() {
            let mut known: Vec<&str> = index.keys().copied().collect();
            known.sort_unstable();
            self.push(
                path,
                format!(
                    "unknown instance {} (known: {})",
                    quoted(name),
                    list(&known)
                ),
            );
        }
        found
    }

    /// Reports a joint the tree and the loops could not place, and the rules of loops:
    /// a loop-closing joint is not explicitly driven, an unobserved joint closes a loop.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn topology(
        &mut self,
        path: &str,
        def: &JointDef,
        (parent, child): (usize, usize),
        role: Option<Role>,
        topology: &Topology,
        instances: &[InstanceDef],
        roots: Roots<'_>,
    ) {
        let first = held_child(def, child, roots)
            .or_else(|| holds_nothing(def, (parent, child), roots))
            .or_else(|| hangs_from_mocap(def, parent, roots));
        let found = match (first, role) {
            (Some(found), _) => Some(found),
            (None, Some(Role::Tree)) => None,
            (None, Some(Role::Loop)) => actuated_loop(def),
            (None, None) => joins_itself(def, (parent, child))
                .or_else(|| unobserved_tree_joint(def))
                .or_else(|| root_as_child(def, child, roots))
                .or_else(|| second_parent(def, child, topology, instances)),
        };
        if let Some((field, message)) = found {
            self.push(format!("{path}.{field}"), message);
        }
    }
}

/// A problem a joint's place in the trees has: the field it is about and the message.
type Found = Option<(&'static str, String)>;

/// A child the world holds where it is (a ground, a fixed or a mocap instance).
fn held_child(def: &JointDef, child: usize, roots: Roots<'_>) -> Found {
    let what = match roots.anchor(child) {
        Anchor::None => return None,
        Anchor::Plane => "a plane or heightfield, a ground fixed to the world,",
        Anchor::Fixed => "fixed to the world (\"fixed\": true)",
        Anchor::Mocap => "a mocap body, which only its pose targets move,",
    };
    Some((
        "child",
        format!(
            "instance {} is {what} and cannot be a joint child; swap parent and child",
            quoted(&def.child)
        ),
    ))
}

/// A joint between two instances the world holds.
fn holds_nothing(def: &JointDef, (parent, child): (usize, usize), roots: Roots<'_>) -> Found {
    (roots.held(parent) && roots.held(child) && parent != child).then(|| {
        (
            "child",
            format!(
                "joint {} -> {} joins two instances the world holds where they are (grounded, fixed or mocap): it would hold nothing; remove it",
                quoted(&def.parent),
                quoted(&def.child)
            ),
        )
    })
}

/// A moving joint from a mocap body that is not an unobserved constraint.
fn hangs_from_mocap(def: &JointDef, parent: usize, roots: Roots<'_>) -> Found {
    (roots.anchor(parent) == Anchor::Mocap
        && def.kind != JointType::Fixed
        && def.observed != Some(false))
    .then(|| {
        (
            "observed",
            format!(
                "instance {} is a mocap body, which nothing moving hangs from: a joint from it is a constraint that pulls {} along (\"observed\": false), or a fixed joint that makes {} part of it",
                quoted(&def.parent),
                quoted(&def.child),
                quoted(&def.child)
            ),
        )
    })
}

/// An actuated joint that closes a loop (loop-closing joints are passive).
fn actuated_loop(def: &JointDef) -> Found {
    (def.actuated == Some(true)).then(|| {
        (
            "actuated",
            format!(
                "joint {} -> {} closes a kinematic loop, and a loop-closing joint is passive; remove \"actuated\": true, or mark another joint of the loop \"actuated\": false so that this one joins the tree (the tree takes actuated joints first)",
                quoted(&def.parent),
                quoted(&def.child)
            ),
        )
    })
}

/// A joint from an instance to itself.
fn joins_itself(def: &JointDef, (parent, child): (usize, usize)) -> Found {
    (parent == child).then(|| {
        (
            "child",
            format!(
                "joint connects instance {} to itself; parent and child must differ",
                quoted(&def.child)
            ),
        )
    })
}

/// An unobserved joint that does not close a loop.
fn unobserved_tree_joint(def: &JointDef) -> Found {
    (def.observed == Some(false)).then(|| {
        (
            "observed",
            format!(
                "only a joint that closes a kinematic loop may be unobserved, and {} and {} are not otherwise joined; remove \"observed\": false",
                quoted(&def.parent),
                quoted(&def.child)
            ),
        )
    })
}

/// The first instance (grounded, or the floating base) as a child.
fn root_as_child(def: &JointDef, child: usize, roots: Roots<'_>) -> Found {
    (child == 0).then(|| {
        let what = if roots.floating_base {
            "the floating base (the first instance), the root of the tree,"
        } else {
            "grounded (the first instance)"
        };
        (
            "child",
            format!(
                "instance {} is {what} and cannot be a joint child; swap parent and child",
                quoted(&def.child)
            ),
        )
    })
}

/// A second parent for a child, from a joint that does not close a loop.
fn second_parent(
    def: &JointDef,
    child: usize,
    topology: &Topology,
    instances: &[InstanceDef],
) -> Found {
    let (existing, _) = topology.parent[child]?;
    Some((
        "child",
        format!(
            "instance {} already has parent {}; a second parent is only for a joint that closes a kinematic loop, and {} is not otherwise joined to {}",
            quoted(&def.child),
            quoted(&instances[existing].name),
            quoted(&def.parent),
            quoted(&def.child)
        ),
    ))
}
