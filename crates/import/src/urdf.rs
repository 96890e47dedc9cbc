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

use std::collections::HashMap;

use glam::{DMat3, DQuat, DVec3};
use roxmltree::Node;
use serde_json::{json, Map, Value};

use crate::frame::{euler_xyz_degrees, inertial_json, Frame};
use crate::xml::{elements, Names, Warnings, XmlReader};
use crate::{Converted, ImportError, Result};

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

    /// A link's instances; returns the link's own (its first collision's, or a helper).
    fn link(&mut self, link: Node<'a, 'i>, frame: &Frame) -> Result<String> {
        let link_name = link.attribute("name").unwrap_or("link").to_string();
        let inertial = child(link, "inertial");
        let mass = match inertial {
            Some(i) => {
                let mass_node = child(i, "mass")
                    .ok_or_else(|| self.unsupported(i, "no <mass value=…>".into()))?;
                let m = self
                    .number(mass_node, "value")?
                    .ok_or_else(|| self.bad(mass_node, "value", "missing".into()))?;
                if m < 0.0 {
                    return Err(self.bad(
                        mass_node,
                        "value",
                        format!("expected a mass ≥ 0 kg, got {m}"),
                    ));
                }
                Some(m)
            }
            None => None,
        };
        for node in elements(link) {
            match node.tag_name().name() {
                "visual" => self.warn(
                    node,
                    "ignored (only <collision> shapes are simulated)".into(),
                ),
                "self_filter" => self.warn(
                    node,
                    "ignored (a ROS sensor-filtering setting, no effect on the dynamics)".into(),
                ),
                "inertial" | "collision" | "contact" => {}
                other => {
                    return Err(
                        self.unsupported(node, format!("<{other}> in <link> is not supported"))
                    )
                }
            }
        }
        let massless = mass == Some(0.0);
        if massless {
            self.warn(link, "a link of mass 0 (a frame) weighs 1 mg".into());
        }
        let mut main: Option<String> = None;
        let first_instance = self.instances.len();
        for collision in elements(link).filter(|n| n.tag_name().name() == "collision") {
            // With given mass properties (or none at all) the shapes weigh 1 mg each and
            // the link's instance carries the mass.
            let weight = (mass.is_some()).then_some(HELPER_MASS);
            let name = self.collision(collision, frame, &link_name, weight, main.is_none())?;
            match &main {
                None => main = Some(name),
                Some(m) => self.weld(m, &name),
            }
        }
        // The link's shapes are instances `first_instance..shapes_end`.
        let shapes_end = self.instances.len();
        let main = match main {
            Some(m) => m,
            None => {
                if mass.is_none() {
                    self.warn(
                        link,
                        "a link without <collision> or <inertial> weighs 1 mg".into(),
                    );
                }
                self.helper(&link_name, frame)
            }
        };
        if let Some(contact) = child(link, "contact") {
            self.contact(contact, &link_name, first_instance..shapes_end)?;
        }
        match (inertial, mass) {
            (Some(i), Some(m)) if m > 0.0 => self.inertial(i, m, frame, &main)?,
            (None, _) if shapes_end > first_instance => self.warn(
                link,
                "no <inertial>: the mass comes from the shapes at 1000 kg/m³".into(),
            ),
            _ => {}
        }
        Ok(main)
    }

    /// PyBullet's `<contact>` extension: `lateral_friction` and `restitution` become the
    /// material of the link's shapes (the instances `shapes`); its solver tuning
    /// (stiffness, damping, rolling and spinning friction) is ignored with a warning.
    fn contact(
        &mut self,
        node: Node<'a, 'i>,
        link_name: &str,
        shapes: std::ops::Range<usize>,
    ) -> Result<()> {
        let mut material = Map::new();
        for item in elements(node) {
            let key = match item.tag_name().name() {
                "lateral_friction" => "friction",
                "restitution" => "restitution",
                other => {
                    self.warn(
                        item,
                        format!("<{other}> ignored (gymfleet's contact model)"),
                    );
                    continue;
                }
            };
            let value = self
                .number(item, "value")?
                .ok_or_else(|| self.bad(item, "value", "missing".into()))?;
            material.insert(key.into(), json!(value));
        }
        if material.is_empty() {
            return Ok(());
        }
        let name = format!("{link_name}_contact");
        for instance in &mut self.instances[shapes] {
            instance["material"] = json!(name);
        }
        self.materials.insert(name, Value::Object(material));
        Ok(())
    }

    /// A link's `<inertial>` on its instance: mass, centre of mass and inertia.
    fn inertial(
        &mut self,
        node: Node<'a, 'i>,
        mass: f64,
        link: &Frame,
        instance: &str,
    ) -> Result<()> {
        let at = link.then(&self.origin(node)?);
        let inertia = child(node, "inertia")
            .ok_or_else(|| self.unsupported(node, "no <inertia ixx=… …>".into()))?;
        let mut entry = |name: &str| -> Result<f64> {
            self.number(inertia, name)?
                .ok_or_else(|| self.bad(inertia, name, "missing".into()))
        };
        let [xx, yy, zz, xy, xz, yz] = ["ixx", "iyy", "izz", "ixy", "ixz", "iyz"].map(&mut entry);
        let (xx, yy, zz, xy, xz, yz) = (xx?, yy?, zz?, xy?, xz?, yz?);
        if xx == 0.0 && yy == 0.0 && zz == 0.0 {
            return Err(self.unsupported(
                inertia,
                format!(
                    "a link of {mass} kg with zero inertia: every principal moment must be > 0"
                ),
            ));
        }
        if let Some(problem) =
            gymfleet_assembly::inertia_problem(&[[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        {
            // Placeholder inertias on near-massless frame links (1e-6 everywhere, off
            // diagonals included: Unitree's B1, IIT's HyQ) are not the link's physics: it
            // keeps its mass, with its shape's inertia for that mass.
            if mass <= PLACEHOLDER_MASS {
                self.warn(
                    inertia,
                    format!(
                        "the inertia of a link of {mass} kg is {problem}; a link this light keeps its mass with its shape's inertia"
                    ),
                );
                let index = self.index_of(instance);
                self.instances[index]["inertial"] = json!({"mass": mass});
                return Ok(());
            }
            return Err(self.unsupported(
                inertia,
                format!("the inertia of a link of {mass} kg is {problem}"),
            ));
        }
        let tensor = DMat3::from_cols_array(&[xx, xy, xz, xy, yy, yz, xz, yz, zz]);
        let index = self.index_of(instance);
        self.instances[index]["inertial"] =
            inertial_json(mass, &at, tensor, &self.frames[instance], MM);
        Ok(())
    }

    fn index_of(&self, instance: &str) -> usize {
        self.instances
            .iter()
            .position(|i| i["name"] == instance)
            .unwrap_or_default()
    }

    /// A helper instance: a small sphere of `HELPER_MASS` that collides with nothing.
    fn helper(&mut self, wanted: &str, at: &Frame) -> String {
        let name = self.unique(wanted);
        self.parts.push(json!({
            "name": name,
            "primitive": {"type": "sphere", "radius": HELPER_RADIUS}
        }));
        let p = at.translation * MM;
        let r = euler_xyz_degrees(at.rotation);
        self.instances.push(json!({
            "part": name, "name": name,
            "position": {"x": p.x, "y": p.y, "z": p.z},
            "rotation": {"x": r[0], "y": r[1], "z": r[2]},
            "collision": {"group": 0, "mask": 0},
            "inertial": {"mass": HELPER_MASS}
        }));
        self.frames.insert(name.clone(), *at);
        name
    }

    fn weld(&mut self, parent: &str, child: &str) {
        let name = self.unique(&format!("{child}_weld"));
        self.joints
            .push(json!({"type": "fixed", "name": name, "parent": parent, "child": child}));
    }

    /// One `<collision>` as an instance, placed in the world.
    fn collision(
        &mut self,
        node: Node<'a, 'i>,
        link: &Frame,
        link_name: &str,
        weight: Option<f64>,
        first: bool,
    ) -> Result<String> {
        let at = link.then(&self.origin(node)?);
        let geometry = child(node, "geometry")
            .ok_or_else(|| self.unsupported(node, "no <geometry>".into()))?;
        let shape = elements(geometry)
            .next()
            .ok_or_else(|| self.unsupported(geometry, "empty <geometry>".into()))?;
        let positive = |c: &Self, name: &str| -> Result<f64> {
            match c.number(shape, name)? {
                Some(v) if v > 0.0 => Ok(v),
                Some(v) => Err(c.bad(shape, name, format!("expected a positive length, got {v}"))),
                None => Err(c.bad(shape, name, "missing".into())),
            }
        };
        // Our primitives start at a corner (box) or their base (cylinder, capsule).
        let (primitive, corner) = match shape.tag_name().name() {
            "box" => {
                let s = self
                    .numbers::<3>(shape, "size")?
                    .ok_or_else(|| self.bad(shape, "size", "missing".into()))?;
                if let Some(v) = s.iter().find(|v| **v <= 0.0) {
                    return Err(self.bad(
                        shape,
                        "size",
                        format!("expected positive lengths, got {v}"),
                    ));
                }
                (
                    json!({"type": "cube", "size": {"x": s[0] * MM, "y": s[1] * MM, "z": s[2] * MM}}),
                    DVec3::from_array(s) / 2.0,
                )
            }
            "cylinder" => {
                let (r, l) = (positive(self, "radius")?, positive(self, "length")?);
                (
                    json!({"type": "cylinder", "radius": r * MM, "height": l * MM}),
                    DVec3::new(0.0, 0.0, l / 2.0),
                )
            }
            "capsule" => {
                let (r, l) = (positive(self, "radius")?, positive(self, "length")?);
                (
                    json!({"type": "capsule", "radius": r * MM, "height": (l + 2.0 * r) * MM}),
                    DVec3::new(0.0, 0.0, l / 2.0 + r),
                )
            }
            "sphere" => (
                json!({"type": "sphere", "radius": positive(self, "radius")? * MM}),
                DVec3::ZERO,
            ),
            "mesh" => {
                let file = self.required(shape, "filename")?;
                let s = self.numbers::<3>(shape, "scale")?.unwrap_or([1.0; 3]);
                if let Some(v) = s.iter().find(|v| **v == 0.0) {
                    return Err(self.bad(
                        shape,
                        "scale",
                        format!("expected non-zero factors, got {v}"),
                    ));
                }
                (
                    json!({"type": "mesh", "file": file, "convex": "hull",
                           "scale": {"x": s[0] * MM, "y": s[1] * MM, "z": s[2] * MM}}),
                    DVec3::ZERO,
                )
            }
            other => {
                return Err(self.unsupported(shape, format!("<{other}> geometry is not supported")))
            }
        };
        let origin_m = at.point(-corner);
        let origin = origin_m * MM;
        let rotation = euler_xyz_degrees(at.rotation);
        let wanted = match (first, node.attribute("name")) {
            (true, _) => link_name.to_string(),
            (false, Some(n)) => n.to_string(),
            (false, None) => format!("{link_name}_collision"),
        };
        let name = self.unique(&wanted);
        let mut instance = Map::new();
        instance.insert("part".into(), json!(name));
        instance.insert("name".into(), json!(name));
        instance.insert(
            "position".into(),
            json!({"x": origin.x, "y": origin.y, "z": origin.z}),
        );
        instance.insert(
            "rotation".into(),
            json!({"x": rotation[0], "y": rotation[1], "z": rotation[2]}),
        );
        if let Some(m) = weight {
            instance.insert("inertial".into(), json!({"mass": m}));
        }
        self.parts
            .push(json!({"name": name, "primitive": primitive}));
        self.instances.push(Value::Object(instance));
        self.frames.insert(
            name.clone(),
            Frame {
                translation: origin_m,
                rotation: at.rotation,
            },
        );
        Ok(name)
    }

    /// A `<joint>` from the parent link's instance to the child's; `frame` is the joint's
    /// (the child link's) frame in the world.
    fn joint(
        &mut self,
        node: Node<'a, 'i>,
        frame: &Frame,
        parent: &str,
        child_instance: &str,
    ) -> Result<()> {
        let name = self.required(node, "name")?.to_string();
        let kind = self.required(node, "type")?;
        if let Some(m) = child(node, "mimic") {
            return Err(self.unsupported(
                m,
                format!(
                    "joint {} mimics another: mimic joints are not supported (make it a separate, actuated joint, or fixed)",
                    crate::quote(&name)
                ),
            ));
        }
        let (json_kind, linear) = match kind {
            "revolute" | "continuous" => ("revolute", false),
            "prismatic" => ("prismatic", true),
            "fixed" => ("fixed", false),
            "floating" => {
                return Err(self.unsupported(
                    node,
                    "a floating joint must hang the robot's base from the world link".into(),
                ))
            }
            other => {
                return Err(self.bad(
                    node,
                    "type",
                    format!("{} joints are not supported", crate::quote(other)),
                ))
            }
        };
        let mut j = Map::new();
        j.insert("type".into(), json!(json_kind));
        j.insert("name".into(), json!(self.unique(&name)));
        j.insert("parent".into(), json!(parent));
        j.insert("child".into(), json!(child_instance));
        let anchor = frame.translation * MM;
        j.insert(
            "anchor".into(),
            json!({"x": anchor.x, "y": anchor.y, "z": anchor.z}),
        );
        if json_kind == "fixed" {
            self.joints.push(Value::Object(j));
            return Ok(());
        }
        let axis_node = child(node, "axis");
        let axis = match axis_node {
            Some(a) => DVec3::from_array(self.numbers::<3>(a, "xyz")?.unwrap_or([1.0, 0.0, 0.0])),
            None => DVec3::X,
        };
        if axis.length() < 1e-12 {
            return Err(self.bad(
                axis_node.unwrap_or(node),
                "xyz",
                "the axis is the zero vector".into(),
            ));
        }
        let axis = frame.direction(axis.normalize());
        j.insert(
            "axis".into(),
            json!({"x": axis.x, "y": axis.y, "z": axis.z}),
        );
        let limit = child(node, "limit");
        match (kind, limit) {
            ("continuous", _) => {}
            (_, None) => {
                return Err(self.unsupported(
                    node,
                    format!("a {kind} joint needs <limit lower upper effort velocity> (use continuous for a joint without limits)"),
                ))
            }
            (_, Some(l)) => {
                let lower = self.number(l, "lower")?.unwrap_or(0.0);
                let upper = self.number(l, "upper")?.unwrap_or(0.0);
                if lower > upper {
                    return Err(self.bad(l, "lower", format!("lower {lower} is above upper {upper}")));
                }
                let unit = |v: f64| if linear { v * MM } else { v.to_degrees() };
                j.insert("min".into(), json!(unit(lower)));
                j.insert("max".into(), json!(unit(upper)));
                // The zero pose breaks these limits (Panda's joint 4, Kinova's joint 2):
                // start at the nearest limit, where MuJoCo's limit would push it.
                if lower > 0.0 || upper < 0.0 {
                    let start = 0.0f64.clamp(lower, upper);
                    j.insert("initial".into(), json!(unit(start)));
                    self.warn(
                        l,
                        format!(
                            "joint {} starts at {} {}, its limit nearest to the zero pose that its limits exclude",
                            crate::quote(&name),
                            (unit(start) * 1e6).round() / 1e6,
                            if linear { "mm" } else { "deg" }
                        ),
                    );
                }
            }
        }
        if let Some(l) = limit {
            match self.number(l, "effort")? {
                Some(e) if e > 0.0 => {
                    j.insert("max_effort".into(), json!(e));
                }
                Some(e) if e < 0.0 => {
                    return Err(self.bad(l, "effort", format!("expected an effort ≥ 0, got {e}")))
                }
                _ => self.warn(
                    l,
                    "effort 0 or none: the joint's effort is not clamped".into(),
                ),
            }
            if l.attribute("velocity").is_some() {
                self.warn(
                    l,
                    "velocity ignored (gymfleet limits effort, not speed)".into(),
                );
            }
        }
        if let Some(d) = child(node, "dynamics") {
            if let Some(damping) = self.number(d, "damping")? {
                if damping < 0.0 {
                    return Err(self.bad(
                        d,
                        "damping",
                        format!("expected damping ≥ 0, got {damping}"),
                    ));
                }
                if damping > 0.0 {
                    j.insert("damping".into(), json!(damping));
                }
            }
            if let Some(f) = self.number(d, "friction")?.filter(|f| *f != 0.0) {
                if f < 0.0 {
                    return Err(self.bad(d, "friction", format!("expected friction ≥ 0, got {f}")));
                }
                if json_kind != "fixed" {
                    j.insert("friction".into(), json!(f));
                }
            }
        }
        for other in ["calibration", "safety_controller"] {
            if let Some(n) = child(node, other) {
                self.warn(n, "ignored (no effect on the dynamics)".into());
            }
        }
        self.joints.push(Value::Object(j));
        Ok(())
    }
}
