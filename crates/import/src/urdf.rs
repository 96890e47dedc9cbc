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
//! This file holds the converter and its readers; `urdf/tree.rs` reads the document into
//! the kinematic tree and walks it, `urdf/links.rs` converts links (collisions,
//! inertials, contacts, helpers) and `urdf/joints.rs` joints.

use std::collections::HashMap;

use glam::{DQuat, DVec3};
use gymfleet_assembly::{AssemblyDef, Document, InstanceDef, JointDef, MaterialDef, PartDef};
use roxmltree::Node;
use std::collections::BTreeMap;

use crate::frame::Frame;
use crate::xml::{elements, Names, Warnings, XmlReader};
use crate::{Converted, ImportError, Result};

mod joints;
mod links;
mod tree;

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
        materials: BTreeMap::new(),
        instances: Vec::new(),
        frames: HashMap::new(),
        joints: Vec::new(),
        names: Names::default(),
    };
    let robot = doc.root_element();
    if robot.tag_name().name() != "robot" {
        return Err(c.unsupported(robot, "the root element must be <robot>".into()));
    }
    let tree = c.tree(robot)?;
    let start = c.start(&tree)?;
    c.walk(&tree, &start)?;
    let document = Document {
        parts: c.parts,
        materials: c.materials,
        assembly: AssemblyDef {
            contacts: None,
            instances: c.instances,
            joints: c.joints,
            sites: Vec::new(),
            tendons: Vec::new(),
            couplings: Vec::new(),
            actuators: Vec::new(),
            keyframes: Vec::new(),
            initial_keyframe: None,
            sensors: Vec::new(),
        },
        simulation: None,
        floating_base: start.floating.then_some(true),
    };
    Ok(Converted::of(&document, c.warnings.into_vec()))
}

fn child<'a, 'i>(node: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    elements(node).find(|n| n.tag_name().name() == tag)
}

struct Converter<'a, 'i> {
    doc: &'a roxmltree::Document<'i>,
    warnings: Warnings,
    parts: Vec<PartDef>,
    materials: BTreeMap<String, MaterialDef>,
    instances: Vec<InstanceDef>,
    /// Each instance's frame in the world (m), as written into its `position`/`rotation`.
    frames: HashMap<String, Frame>,
    joints: Vec<JointDef>,
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
            .position(|i| i.name == instance)
            .unwrap_or_default()
    }
}
