//! The document's links and joints as a kinematic tree: read and checked (one root, each
//! link at most one joint's child, at most one floating joint), then walked depth first
//! from the root, converting each link and the joint that reaches it.

use std::collections::HashMap;

use roxmltree::Node;

use super::{child, Converter};
use crate::frame::Frame;
use crate::xml::{elements, XmlReader};
use crate::Result;

/// The robot's links and joints, as a tree.
pub(super) struct Tree<'a, 'i> {
    /// Every link, by name.
    links: HashMap<&'a str, Node<'a, 'i>>,
    /// Every joint, in document order.
    joints: Vec<Node<'a, 'i>>,
    /// Each link's child joints, in document order.
    children: HashMap<&'a str, Vec<Node<'a, 'i>>>,
    /// The one link that is no joint's child.
    root: Node<'a, 'i>,
    /// The `<robot>` element.
    robot: Node<'a, 'i>,
}

/// Where the walk starts: the root link, or the floating base below the world link.
pub(super) struct Start<'a, 'i> {
    link: Node<'a, 'i>,
    frame: Frame,
    /// Whether a floating joint hangs the robot from the world (a floating base).
    pub(super) floating: bool,
}

impl<'a, 'i> Converter<'a, 'i> {
    /// Reads `<robot>`'s links and joints (warning about what has no effect on the
    /// dynamics) and checks that they form one tree.
    pub(super) fn tree(&mut self, robot: Node<'a, 'i>) -> Result<Tree<'a, 'i>> {
        let mut links: HashMap<&str, Node<'_, '_>> = HashMap::new();
        let mut joints: Vec<Node<'_, '_>> = Vec::new();
        for child in elements(robot) {
            match child.tag_name().name() {
                "link" => {
                    let name = self.required(child, "name")?;
                    if links.insert(name, child).is_some() {
                        return Err(self.bad(
                            child,
                            "name",
                            format!("a second link named {}", crate::quote(name)),
                        ));
                    }
                }
                "joint" => joints.push(child),
                "material" | "gazebo" | "transmission" | "ros2_control" => {
                    self.warn(child, "ignored (no effect on the dynamics)".into())
                }
                other => return Err(self.unsupported(child, format!("<{other}> is not supported"))),
            }
        }
        // Each link is at most one joint's child, and one link is nobody's.
        let mut parent_of: HashMap<&str, Node<'_, '_>> = HashMap::new();
        let mut children: HashMap<&str, Vec<Node<'_, '_>>> = HashMap::new();
        for &joint in &joints {
            let parent = self.link_ref(joint, "parent", &links)?;
            let child = self.link_ref(joint, "child", &links)?;
            if let Some(first) = parent_of.insert(child, joint) {
                return Err(self.unsupported(
                    joint,
                    format!(
                        "link {} is already the child of joint {} (line {}): URDF is a tree",
                        crate::quote(child),
                        crate::quote(first.attribute("name").unwrap_or("?")),
                        self.line(first)
                    ),
                ));
            }
            children.entry(parent).or_default().push(joint);
        }
        let root = self.root_link(robot, &links, &parent_of)?;
        Ok(Tree {
            links,
            joints,
            children,
            root,
            robot,
        })
    }

    /// The one link no joint has for its child.
    fn root_link(
        &self,
        robot: Node<'a, 'i>,
        links: &HashMap<&'a str, Node<'a, 'i>>,
        parent_of: &HashMap<&'a str, Node<'a, 'i>>,
    ) -> Result<Node<'a, 'i>> {
        let mut roots: Vec<Node<'_, '_>> = links
            .iter()
            .filter(|(name, _)| !parent_of.contains_key(*name))
            .map(|(_, node)| *node)
            .collect();
        roots.sort_by_key(|n| n.range().start);
        match roots.as_slice() {
            [one] => Ok(*one),
            [] if links.is_empty() => Err(self.unsupported(robot, "no <link>".into())),
            [] => Err(self.unsupported(
                robot,
                "every link is some joint's child: the joints form a cycle".into(),
            )),
            [first, ..] => {
                let names: Vec<String> = roots
                    .iter()
                    .take(5)
                    .map(|n| crate::quote(n.attribute("name").unwrap_or("?")))
                    .collect();
                Err(self.unsupported(
                    *first,
                    format!(
                        "{} links are no joint's child ({}): a robot has one root link",
                        roots.len(),
                        names.join(", ")
                    ),
                ))
            }
        }
    }

    /// Where the walk starts. A floating joint hangs the robot's base from the world:
    /// the base is then the first instance (a floating base) and the world link, an
    /// empty frame, is dropped.
    pub(super) fn start(&mut self, tree: &Tree<'a, 'i>) -> Result<Start<'a, 'i>> {
        let floating: Vec<Node<'_, '_>> = tree
            .joints
            .iter()
            .copied()
            .filter(|j| j.attribute("type") == Some("floating"))
            .collect();
        let joint = match floating.as_slice() {
            [] => {
                return Ok(Start {
                    link: tree.root,
                    frame: Frame::IDENTITY,
                    floating: false,
                })
            }
            [joint] => *joint,
            [_, second, ..] => {
                return Err(self.unsupported(
                    *second,
                    "a second floating joint: one floating base is supported".into(),
                ))
            }
        };
        let world = tree.root.attribute("name").unwrap_or_default();
        if self.link_ref(joint, "parent", &tree.links)? != world {
            return Err(self.unsupported(
                joint,
                format!(
                    "a floating joint must hang the robot from the root link, the world (here {})",
                    crate::quote(world)
                ),
            ));
        }
        if elements(tree.root).any(|n| matches!(n.tag_name().name(), "collision" | "inertial")) {
            return Err(self.unsupported(
                tree.root,
                format!(
                    "the root link {} holds a floating joint, so it is the world: it may have no <collision> or <inertial>",
                    crate::quote(world)
                ),
            ));
        }
        if tree.children.get(world).map_or(0, Vec::len) > 1 {
            return Err(self.unsupported(
                tree.root,
                format!(
                    "the world link {} holds a floating joint and other joints: nothing is fixed to the world beside a floating base",
                    crate::quote(world)
                ),
            ));
        }
        for attr in ["dynamics", "limit"] {
            if let Some(n) = child(joint, attr) {
                self.warn(
                    n,
                    "ignored on a floating joint (the base's six DOFs take none)".into(),
                );
            }
        }
        let base = self.link_ref(joint, "child", &tree.links)?;
        Ok(Start {
            link: tree.links[base],
            frame: self.origin(joint)?,
            floating: true,
        })
    }

    /// Converts every link and joint, depth first from `start`: the root link's instance
    /// comes first (grounded, or the floating base).
    pub(super) fn walk(&mut self, tree: &Tree<'a, 'i>, start: &Start<'a, 'i>) -> Result<()> {
        let mut stack = vec![(start.link, start.frame, None::<(Node<'_, '_>, String)>)];
        // The world link above a floating base is dropped, but it was reached.
        let mut visited = usize::from(start.floating);
        while let Some((link, frame, via)) = stack.pop() {
            visited += 1;
            let instance = self.link(link, &frame)?;
            if let Some((joint, parent)) = via {
                self.joint(joint, &frame, &parent, &instance)?;
            }
            let name = link.attribute("name").unwrap_or_default();
            for &joint in tree.children.get(name).into_iter().flatten().rev() {
                let child_name = self.link_ref(joint, "child", &tree.links)?;
                let local = self.origin(joint)?;
                stack.push((
                    tree.links[child_name],
                    frame.then(&local),
                    Some((joint, instance.clone())),
                ));
            }
        }
        if visited != tree.links.len() {
            return Err(self.unsupported(
                tree.robot,
                "some links are not connected to the root link".into(),
            ));
        }
        Ok(())
    }
}
