//! URDF (ROS's robot description) → assembly JSON.
//!
//! The mapping: the kinematic tree is walked from its one root link; every `<collision>`
//! becomes an instance (its own part, placed in world mm), a link's first collision is the
//! link's instance and its others are welded to it; a link without collisions is a 1 mg
//! helper instance that collides with nothing. A link's `<inertial>` gives its mass
//! properties (on the link's instance; welded extra shapes weigh 1 mg); a link without one
//! takes its mass from its shapes at 1000 kg/m³ (with a warning); a massless link (URDF's
//! frames, e.g. `base`, `tool0`) is a helper. Joints: revolute, continuous, prismatic and
//! fixed map one to one (anchor and axis in world coordinates; limits rad → deg, m → mm;
//! `effort` → `max_effort`; `damping`); every moving joint is actuated. Meshes become
//! `{"type": "mesh", "file": …}` primitives in metres (scaled into mm), read from the
//! request's assets afterwards ([`crate::inline_mesh_files`]) and simulated as their hull.
//!
//! PyBullet's `<contact>` gives the link's shapes their `lateral_friction` and
//! `restitution`. A `floating` joint from an empty root link (the world) makes its child
//! the floating base. Refused with the element and its line: mimic joints, planar
//! joints, several roots, a link that is two joints' child, zero inertia with a
//! mass, bad numbers. Ignored with a warning: `<visual>`, `<material>`, `<gazebo>`,
//! `<transmission>`, joint `velocity` limits, calibration and safety controllers.
//!
//! This file walks the document and the tree; `urdf/links.rs` converts links (collisions,
//! inertials, contacts, helpers) and `urdf/joints.rs` joints.

use std::collections::HashMap;

use glam::{DQuat, DVec3};
use roxmltree::Node;
use serde_json::{json, Map, Value};

use crate::frame::Frame;
use crate::xml::{elements, Names, Warnings, XmlReader};
use crate::{Converted, ImportError, Result};

mod joints;
mod links;

/// Millimetres per metre.
const MM: f64 = 1000.0;
/// The mass of helper instances (kg), as in the MJCF conversion.
const HELPER_MASS: f64 = 1e-6;
/// A helper instance's radius (mm).
const HELPER_RADIUS: f64 = 1.0;
/// The heaviest link (kg) whose non-physical inertia is taken for a placeholder (and
/// replaced by its shape's for its mass) rather than refused.
const PLACEHOLDER_MASS: f64 = 1e-3;

/// Converts a URDF document into gymfleet's assembly JSON.
pub fn urdf_to_document(xml: &str) -> Result<Converted> {
    let doc = roxmltree::Document::parse(xml).map_err(|e| ImportError::Xml(e.to_string()))?;
    let mut c = Converter {
        doc: &doc,
        warnings: Warnings::default(),
        parts: Vec::new(),
        materials: Map::new(),
        instances: Vec::new(),
        frames: HashMap::new(),
        joints: Vec::new(),
        names: Names::default(),
    };
    let root = doc.root_element();
    if root.tag_name().name() != "robot" {
        return Err(c.unsupported(root, "the root element must be <robot>".into()));
    }
    let mut links: HashMap<&str, Node<'_, '_>> = HashMap::new();
    let mut joints: Vec<Node<'_, '_>> = Vec::new();
    for child in elements(root) {
        match child.tag_name().name() {
            "link" => {
                let name = c.required(child, "name")?;
                if links.insert(name, child).is_some() {
                    return Err(c.bad(
                        child,
                        "name",
                        format!("a second link named {}", crate::quote(name)),
                    ));
                }
            }
            "joint" => joints.push(child),
            "material" | "gazebo" | "transmission" | "ros2_control" => {
                c.warn(child, "ignored (no effect on the dynamics)".into())
            }
            other => return Err(c.unsupported(child, format!("<{other}> is not supported"))),
        }
    }
    // The tree: each link is at most one joint's child, and one link is nobody's.
    let mut parent_of: HashMap<&str, Node<'_, '_>> = HashMap::new();
    let mut children: HashMap<&str, Vec<Node<'_, '_>>> = HashMap::new();
    for &joint in &joints {
        let parent = c.link_ref(joint, "parent", &links)?;
        let child = c.link_ref(joint, "child", &links)?;
        if let Some(first) = parent_of.insert(child, joint) {
            return Err(c.unsupported(
                joint,
                format!(
                    "link {} is already the child of joint {} (line {}): URDF is a tree",
                    crate::quote(child),
                    crate::quote(first.attribute("name").unwrap_or("?")),
                    c.line(first)
                ),
            ));
        }
        children.entry(parent).or_default().push(joint);
    }
    let mut roots: Vec<Node<'_, '_>> = links
        .iter()
        .filter(|(name, _)| !parent_of.contains_key(*name))
        .map(|(_, node)| *node)
        .collect();
    roots.sort_by_key(|n| n.range().start);
    let root_link = match roots.as_slice() {
        [one] => *one,
        [] if links.is_empty() => return Err(c.unsupported(root, "no <link>".into())),
        [] => {
            return Err(c.unsupported(
                root,
                "every link is some joint's child: the joints form a cycle".into(),
            ))
        }
        [first, ..] => {
            let names: Vec<String> = roots
                .iter()
                .take(5)
                .map(|n| crate::quote(n.attribute("name").unwrap_or("?")))
                .collect();
            return Err(c.unsupported(
                *first,
                format!(
                    "{} links are no joint's child ({}): a robot has one root link",
                    roots.len(),
                    names.join(", ")
                ),
            ));
        }
    };
    // A floating joint hangs the robot's base from the world: the base is then the first
    // instance (a floating base) and the world link, an empty frame, is dropped.
    let floating: Vec<Node<'_, '_>> = joints
        .iter()
        .copied()
        .filter(|j| j.attribute("type") == Some("floating"))
        .collect();
    let (start, start_frame, visited) = match floating.as_slice() {
        [] => (root_link, Frame::IDENTITY, 0usize),
        [joint] => {
            let world = root_link.attribute("name").unwrap_or_default();
            if c.link_ref(*joint, "parent", &links)? != world {
                return Err(c.unsupported(
                    *joint,
                    format!(
                        "a floating joint must hang the robot from the root link, the world (here {})",
                        crate::quote(world)
                    ),
                ));
            }
            if elements(root_link).any(|n| matches!(n.tag_name().name(), "collision" | "inertial"))
            {
                return Err(c.unsupported(
                    root_link,
                    format!(
                        "the root link {} holds a floating joint, so it is the world: it may have no <collision> or <inertial>",
                        crate::quote(world)
                    ),
                ));
            }
            if children.get(world).map_or(0, Vec::len) > 1 {
                return Err(c.unsupported(
                    root_link,
                    format!(
                        "the world link {} holds a floating joint and other joints: nothing is fixed to the world beside a floating base",
                        crate::quote(world)
                    ),
                ));
            }
            for attr in ["dynamics", "limit"] {
                if let Some(n) = child(*joint, attr) {
                    c.warn(
                        n,
                        "ignored on a floating joint (the base's six DOFs take none)".into(),
                    );
                }
            }
            let base = c.link_ref(*joint, "child", &links)?;
            (links[base], c.origin(*joint)?, 1)
        }
        [_, second, ..] => {
            return Err(c.unsupported(
                *second,
                "a second floating joint: one floating base is supported".into(),
            ))
        }
    };
    // Depth first from the root: the root link's instance comes first (grounded, or the
    // floating base).
    let mut stack = vec![(start, start_frame, None::<(Node<'_, '_>, String)>)];
    let mut visited = visited;
    while let Some((link, frame, via)) = stack.pop() {
        visited += 1;
        let instance = c.link(link, &frame)?;
        if let Some((joint, parent)) = via {
            c.joint(joint, &frame, &parent, &instance)?;
        }
        let name = link.attribute("name").unwrap_or_default();
        for &joint in children.get(name).into_iter().flatten().rev() {
            let child_name = c.link_ref(joint, "child", &links)?;
            let local = c.origin(joint)?;
            stack.push((
                links[child_name],
                frame.then(&local),
                Some((joint, instance.clone())),
            ));
        }
    }
    if visited != links.len() {
        return Err(c.unsupported(root, "some links are not connected to the root link".into()));
    }
    let mut document = json!({
        "parts": c.parts,
        "assembly": {"instances": c.instances, "joints": c.joints}
    });
    if !c.materials.is_empty() {
        document["materials"] = Value::Object(c.materials);
    }
    if !floating.is_empty() {
        document["floating_base"] = json!(true);
    }
    Ok(Converted {
        document,
        warnings: c.warnings.into_vec(),
    })
}

fn child<'a, 'i>(node: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    elements(node).find(|n| n.tag_name().name() == tag)
}

struct Converter<'a, 'i> {
    doc: &'a roxmltree::Document<'i>,
    warnings: Warnings,
    parts: Vec<Value>,
    materials: Map<String, Value>,
    instances: Vec<Value>,
    /// Each instance's frame in the world (m), as written into its `position`/`rotation`.
    frames: HashMap<String, Frame>,
    joints: Vec<Value>,
    names: Names,
}

impl<'i> XmlReader<'i> for Converter<'_, 'i> {
    fn document(&self) -> &roxmltree::Document<'i> {
        self.doc
    }

    fn warnings(&mut self) -> &mut Warnings {
        &mut self.warnings
    }
}

impl<'a, 'i> Converter<'a, 'i> {
    fn required(&self, node: Node<'a, 'i>, name: &str) -> Result<&'a str> {
        node.attribute(name)
            .ok_or_else(|| self.bad(node, name, "missing".into()))
    }

    /// `N` numbers separated by spaces, or `None` when the attribute is absent.
    fn numbers<const N: usize>(&self, node: Node<'_, '_>, name: &str) -> Result<Option<[f64; N]>> {
        let Some(text) = node.attribute(name) else {
            return Ok(None);
        };
        let values: Vec<f64> = text
            .split_whitespace()
            .map(|t| t.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect::<Option<_>>()
            .ok_or_else(|| {
                self.bad(
                    node,
                    name,
                    format!("expected finite numbers, got {}", crate::quote(text)),
                )
            })?;
        <[f64; N]>::try_from(values.as_slice())
            .map(Some)
            .map_err(|_| {
                self.bad(
                    node,
                    name,
                    format!("expected {N} numbers, got {}", values.len()),
                )
            })
    }

    fn number(&self, node: Node<'_, '_>, name: &str) -> Result<Option<f64>> {
        Ok(self.numbers::<1>(node, name)?.map(|[v]| v))
    }

    /// The link a joint's `<parent>` or `<child>` names.
    fn link_ref(
        &self,
        joint: Node<'a, 'i>,
        tag: &str,
        links: &HashMap<&str, Node<'a, 'i>>,
    ) -> Result<&'a str> {
        let node = child(joint, tag)
            .ok_or_else(|| self.unsupported(joint, format!("no <{tag} link=…>")))?;
        let name = self.required(node, "link")?;
        if !links.contains_key(name) {
            return Err(self.bad(
                node,
                "link",
                format!("no link is named {}", crate::quote(name)),
            ));
        }
        Ok(name)
    }

    /// An element's `<origin xyz rpy>` (fixed-axis roll, pitch, yaw: R = Rz·Ry·Rx).
    fn origin(&self, node: Node<'_, '_>) -> Result<Frame> {
        let Some(origin) = child(node, "origin") else {
            return Ok(Frame::IDENTITY);
        };
        let xyz = self.numbers::<3>(origin, "xyz")?.unwrap_or([0.0; 3]);
        let [r, p, y] = self.numbers::<3>(origin, "rpy")?.unwrap_or([0.0; 3]);
        Ok(Frame {
            translation: DVec3::from_array(xyz),
            rotation: DQuat::from_rotation_z(y)
                * DQuat::from_rotation_y(p)
                * DQuat::from_rotation_x(r),
        })
    }

    fn unique(&mut self, wanted: &str) -> String {
        self.names.unique(wanted)
    }

    fn index_of(&self, instance: &str) -> usize {
        self.instances
            .iter()
            .position(|i| i["name"] == instance)
            .unwrap_or_default()
    }
}
