//! MJCF (MuJoCo's XML) → assembly JSON. See the crate documentation for the subset.
//!
//! The mapping: every geom becomes an instance (its own part, placed in world mm with the
//! document's Euler angles); a body's first geom is the body's instance and its other geoms
//! are welded to it with fixed joints. A body's joints connect its parent's instance to its
//! instance, through helper instances (1 mg spheres that collide with nothing) when it has
//! several; a body without joints is welded to its parent. The world's geoms are the
//! grounded instance and parts welded to it. Masses come from the geoms (volume × density,
//! as MuJoCo's `inertiafromgeom`), or from `<inertial>` on the body's instance.

use std::collections::{HashMap, HashSet};

use glam::{DMat3, DQuat, DVec3};
use roxmltree::Node;
use serde_json::{json, Map, Value};

use crate::frame::{euler_xyz_degrees, inertial_json, z_onto, Frame};
use crate::xml::{elements, Names, Warnings, XmlReader};
use crate::{Converted, ImportError, Result};

/// Millimetres per metre.
const MM: f64 = 1000.0;
/// The mass of the helper instances the conversion adds (kg): between two joints of one
/// body, or for a body without geoms; small beside any real link, large enough for the
/// solver.
const HELPER_MASS: f64 = 1e-6;
/// A helper instance's radius (mm).
const HELPER_RADIUS: f64 = 1.0;
/// MuJoCo's default geom density, kg/m³.
const DEFAULT_DENSITY: f64 = 1000.0;

/// Converts an MJCF document into gymfleet's assembly JSON.
pub fn mjcf_to_document(xml: &str) -> Result<Converted> {
    let doc = roxmltree::Document::parse(xml).map_err(|e| ImportError::Xml(e.to_string()))?;
    let root = doc.root_element();
    let mut c = Converter::new(&doc);
    if root.tag_name().name() != "mujoco" {
        return Err(c.unsupported(root, "the root element must be <mujoco>".into()));
    }
    // Settings first: they change how the rest reads.
    for child in elements(root) {
        match child.tag_name().name() {
            "compiler" => c.compiler(child)?,
            "default" => c.defaults(child, None)?,
            _ => {}
        }
    }
    for child in elements(root) {
        match child.tag_name().name() {
            "compiler" | "default" | "worldbody" => {}
            "option" => c.option(child)?,
            "actuator" => c.actuators(child)?,
            "size" | "visual" | "statistic" | "keyframe" | "sensor" | "custom" => {
                c.warn(child, "ignored (no effect on the dynamics)".into());
            }
            "asset" => c.assets(child)?,
            "tendon" | "contact" | "equality" if elements(child).next().is_none() => {
                c.warn(child, "empty, ignored".into());
            }
            other => return Err(c.unsupported(child, format!("<{other}> is not supported yet"))),
        }
    }
    let world = elements(root)
        .find(|n| n.tag_name().name() == "worldbody")
        .ok_or_else(|| c.unsupported(root, "no <worldbody>".into()))?;
    c.worldbody(world)?;
    c.finish()
}

/// How a body's mass is found (`compiler inertiafromgeom`).
#[derive(Debug, Clone, Copy, PartialEq)]
enum InertiaFromGeom {
    /// From `<inertial>` where a body has one, else from its geoms (MuJoCo's default).
    Auto,
    /// Always from the geoms.
    True,
    /// Always from `<inertial>`.
    False,
}

/// One default class: its parent and its attributes per element kind.
#[derive(Debug, Default)]
struct Class<'a> {
    parent: Option<String>,
    attributes: HashMap<&'a str, HashMap<&'a str, &'a str>>,
}

/// A motor's effect on its joint.
#[derive(Debug, Clone, Copy)]
struct Motor {
    /// Effort bound, N·m or N, if the motor bounds it.
    max_effort: Option<f64>,
    /// The motor's gear: actions are MuJoCo's ctrl, the effort gear × ctrl.
    gear: f64,
    /// The motor's position among the actuators.
    order: usize,
    /// Its line.
    line: u32,
}

struct Converter<'a, 'i> {
    doc: &'a roxmltree::Document<'i>,
    radian: bool,
    inertia_from_geom: InertiaFromGeom,
    classes: HashMap<String, Class<'a>>,
    warnings: Warnings,
    motors: HashMap<String, Motor>,
    parts: Vec<Value>,
    materials: Map<String, Value>,
    /// The document's `simulation` (gravity, dt) from `<option>`.
    simulation: Map<String, Value>,
    instances: Vec<Value>,
    /// Each instance's frame in the world (m), as written into its `position`/`rotation`.
    frames: HashMap<String, Frame>,
    joints: Vec<Value>,
    names: Names,
    joint_names: Names,
    /// Named points: every named body's origin and every `<site>` in a body.
    sites: Vec<Value>,
    site_names: Names,
    /// Joint names with a DOF, in document (tree) order.
    moving_joints: Vec<String>,
    /// The instance of the first body with a free joint: the floating base.
    floating: Option<String>,
    /// `compiler settotalmass`: every body's mass and inertia scaled to this total (kg).
    total_mass: Option<f64>,
    /// Instances that are not bodies' own mass: the world's geoms and helpers.
    massless: HashSet<String>,
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
    fn new(doc: &'a roxmltree::Document<'i>) -> Self {
        Converter {
            doc,
            radian: false,
            inertia_from_geom: InertiaFromGeom::Auto,
            classes: HashMap::new(),
            warnings: Warnings::default(),
            motors: HashMap::new(),
            parts: Vec::new(),
            materials: Map::new(),
            simulation: Map::new(),
            instances: Vec::new(),
            frames: HashMap::new(),
            joints: Vec::new(),
            names: Names::default(),
            joint_names: Names::default(),
            sites: Vec::new(),
            site_names: Names::default(),
            moving_joints: Vec::new(),
            floating: None,
            total_mass: None,
            massless: HashSet::new(),
        }
    }

    /// Whether `joint` (a `<freejoint>` or `<joint>` of a body of class `class`) is free.
    fn is_free(&self, joint: Node<'a, 'i>, class: Option<&str>) -> bool {
        joint.tag_name().name() == "freejoint" || self.attr(joint, class, "type") == Some("free")
    }

    // --- attributes, with default classes ---------------------------------------------

    /// `node`'s attribute `name`, or its class chain's (`class` attribute, else the
    /// enclosing `childclass`, else the top-level default).
    fn attr(&self, node: Node<'a, 'i>, class: Option<&str>, name: &str) -> Option<&'a str> {
        if let Some(v) = node.attribute(name) {
            return Some(v);
        }
        let tag = node.tag_name().name();
        let mut current = node
            .attribute("class")
            .map(str::to_string)
            .or_else(|| class.map(str::to_string))
            .or_else(|| Some("main".to_string()));
        while let Some(name_of_class) = current {
            let class = self.classes.get(&name_of_class)?;
            if let Some(v) = class.attributes.get(tag).and_then(|a| a.get(name)) {
                return Some(v);
            }
            current = class.parent.clone();
        }
        None
    }

    fn numbers(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
    ) -> Result<Option<Vec<f64>>> {
        let Some(text) = self.attr(node, class, name) else {
            return Ok(None);
        };
        text.split_whitespace()
            .map(|t| {
                t.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        self.bad(node, name, format!("expected finite numbers, got {text:?}"))
                    })
            })
            .collect::<Result<Vec<_>>>()
            .map(Some)
    }

    /// Exactly `n` numbers, if the attribute is there.
    fn exactly<const N: usize>(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
    ) -> Result<Option<[f64; N]>> {
        match self.numbers(node, class, name)? {
            None => Ok(None),
            Some(v) => v.clone().try_into().map(Some).map_err(|_| {
                self.bad(node, name, format!("expected {N} numbers, got {}", v.len()))
            }),
        }
    }

    fn number(&self, node: Node<'a, 'i>, class: Option<&str>, name: &str) -> Result<Option<f64>> {
        Ok(self.exactly::<1>(node, class, name)?.map(|[v]| v))
    }

    fn flag(&self, node: Node<'a, 'i>, class: Option<&str>, name: &str) -> Result<Option<bool>> {
        match self.attr(node, class, name) {
            None | Some("auto") => Ok(None),
            Some("true") => Ok(Some(true)),
            Some("false") => Ok(Some(false)),
            Some(other) => Err(self.bad(
                node,
                name,
                format!("expected true, false or auto, got {other:?}"),
            )),
        }
    }

    fn int(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
        default: u32,
    ) -> Result<u32> {
        match self.attr(node, class, name) {
            None => Ok(default),
            Some(t) => t.trim().parse::<u32>().map_err(|_| {
                self.bad(
                    node,
                    name,
                    format!("expected a non-negative integer, got {t:?}"),
                )
            }),
        }
    }

    fn angle(&self, value: f64) -> f64 {
        if self.radian {
            value
        } else {
            value.to_radians()
        }
    }

    // --- settings ------------------------------------------------------------------------

    fn compiler(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for a in node.attributes() {
            match (a.name(), a.value()) {
                ("angle", "radian") => self.radian = true,
                ("angle", "degree") => self.radian = false,
                ("inertiafromgeom", "true") => self.inertia_from_geom = InertiaFromGeom::True,
                ("inertiafromgeom", "false") => self.inertia_from_geom = InertiaFromGeom::False,
                ("inertiafromgeom", "auto") => self.inertia_from_geom = InertiaFromGeom::Auto,
                ("settotalmass", value) => {
                    let total: f64 = value.trim().parse().map_err(|_| {
                        self.bad(
                            node,
                            "settotalmass",
                            format!("expected a number, got {value:?}"),
                        )
                    })?;
                    if !total.is_finite() {
                        return Err(self.bad(
                            node,
                            "settotalmass",
                            format!("expected a finite mass, got {value:?}"),
                        ));
                    }
                    // MuJoCo: a positive value rescales every body; others do nothing.
                    self.total_mass = (total > 0.0).then_some(total);
                }
                ("eulerseq", "xyz") | ("coordinate", "local") | ("autolimits", "true") => {}
                ("meshdir" | "texturedir" | "assetdir" | "discardvisual" | "strippath", _) => {}
                (name @ ("angle" | "inertiafromgeom"), value) => {
                    return Err(self.bad(node, name, format!("unexpected value {value:?}")))
                }
                (name, value) => {
                    return Err(
                        self.unsupported(node, format!("{name}=\"{value}\" is not supported yet"))
                    )
                }
            }
        }
        Ok(())
    }

    fn defaults(&mut self, node: Node<'a, 'i>, parent: Option<&str>) -> Result<()> {
        let name = match (node.attribute("class"), parent) {
            (Some(n), _) => n.to_string(),
            (None, None) => "main".to_string(),
            (None, Some(_)) => {
                return Err(self.bad(
                    node,
                    "class",
                    "a nested <default> needs a class name".into(),
                ))
            }
        };
        let mut class = Class {
            parent: parent.map(str::to_string),
            attributes: HashMap::new(),
        };
        for child in elements(node) {
            let tag = child.tag_name().name();
            if tag == "default" {
                continue;
            }
            let map = class.attributes.entry(tag).or_default();
            for a in child.attributes() {
                map.insert(a.name(), a.value());
            }
        }
        self.classes.insert(name.clone(), class);
        for child in elements(node).filter(|c| c.tag_name().name() == "default") {
            self.defaults(child, Some(&name))?;
        }
        Ok(())
    }

    /// `<option>`: gravity and timestep become the document's `simulation` (one env step
    /// of the default `dt` is one MuJoCo step); the rest is the engine's own.
    fn option(&mut self, node: Node<'a, 'i>) -> Result<()> {
        if let Some(g) = self.exactly::<3>(node, None, "gravity")? {
            self.simulation
                .insert("gravity".into(), json!({"x": g[0], "y": g[1], "z": g[2]}));
        }
        if let Some(t) = self.number(node, None, "timestep")? {
            if !(t > 0.0 && t <= 1.0) {
                return Err(self.bad(node, "timestep", format!("expected (0, 1] s, got {t}")));
            }
            self.simulation.insert("dt".into(), json!(t));
        }
        for a in node.attributes() {
            if !matches!(a.name(), "timestep" | "gravity") {
                self.warn(node, format!("{}=\"{}\" ignored", a.name(), a.value()));
            }
        }
        if elements(node).next().is_some() {
            self.warn(node, "its flags are ignored".into());
        }
        Ok(())
    }

    fn assets(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for child in elements(node) {
            match child.tag_name().name() {
                "texture" | "material" => self.warn(child, "ignored (appearance only)".into()),
                "mesh" | "hfield" | "skin" => {
                    return Err(self.unsupported(child, "meshes are not converted yet".into()))
                }
                other => {
                    return Err(self.unsupported(child, format!("<{other}> is not supported yet")))
                }
            }
        }
        Ok(())
    }

    fn actuators(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for (order, motor) in elements(node).enumerate() {
            if motor.tag_name().name() != "motor" {
                return Err(self.unsupported(
                    motor,
                    "only <motor> actuators are supported (a torque or force at a joint)".into(),
                ));
            }
            let Some(joint) = self.attr(motor, None, "joint") else {
                return Err(self.unsupported(
                    motor,
                    "a motor must drive a joint (tendon, site and body transmissions are not supported)".into(),
                ));
            };
            let gear = self
                .numbers(motor, None, "gear")?
                .and_then(|g| g.first().copied())
                .unwrap_or(1.0);
            let bound = |range: Option<[f64; 2]>, limited: Option<bool>| match (range, limited) {
                (Some([lo, hi]), Some(true) | None) if lo < hi => Some(lo.abs().max(hi.abs())),
                _ => None,
            };
            let ctrl = bound(
                self.exactly::<2>(motor, None, "ctrlrange")?,
                self.flag(motor, None, "ctrllimited")?,
            )
            .map(|c| c * gear.abs());
            let force = bound(
                self.exactly::<2>(motor, None, "forcerange")?,
                self.flag(motor, None, "forcelimited")?,
            );
            let max_effort = match (ctrl, force) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            }
            .filter(|e| *e > 0.0);
            let line = self.line(motor);
            if self
                .motors
                .insert(
                    joint.to_string(),
                    Motor {
                        max_effort,
                        gear,
                        order,
                        line,
                    },
                )
                .is_some()
            {
                return Err(self.unsupported(motor, format!("joint {joint:?} has a second motor")));
            }
        }
        Ok(())
    }

    // --- the tree ----------------------------------------------------------------------------

    fn unique(&mut self, wanted: &str) -> String {
        self.names.unique(wanted)
    }

    fn worldbody(&mut self, world: Node<'a, 'i>) -> Result<()> {
        // A top-level body with a free joint makes the model's first instance that body's, a
        // floating base (MuJoCo allows free joints in top-level bodies only); the world's
        // geoms are then grounds only if they are planes.
        let floating = elements(world)
            .filter(|n| n.tag_name().name() == "body")
            .any(|body| {
                let class = body.attribute("childclass");
                elements(body).any(|j| {
                    matches!(j.tag_name().name(), "joint" | "freejoint") && self.is_free(j, class)
                })
            });
        let mut world_instance: Option<String> = None;
        // The world's geoms first: the first of them is the grounded instance. A colliding
        // plane (a ground) must be it, so planes go first; one at most.
        let mut geoms: Vec<Node<'a, 'i>> = elements(world)
            .filter(|n| n.tag_name().name() == "geom")
            .collect();
        geoms.sort_by_key(|g| self.attr(*g, None, "type") != Some("plane"));
        for geom in geoms {
            if let Some(name) = self.geom(geom, &Frame::IDENTITY, None, "world", None)? {
                self.massless.insert(name.clone());
                match &world_instance {
                    None if floating && self.attr(geom, None, "type") != Some("plane") => {
                        return Err(self.unsupported(
                            geom,
                            "in a model with a free joint, the world's geoms other than a plane need a ground plane to be fixed to"
                                .into(),
                        ))
                    }
                    None => world_instance = Some(name),
                    Some(ground) => self.weld(ground.clone(), name),
                }
            }
        }
        let ground = match world_instance {
            Some(g) => Some(g),
            None if floating => None,
            None => Some(self.helper("world", &Frame::IDENTITY)),
        };
        for child in elements(world) {
            match child.tag_name().name() {
                "geom" => {}
                "body" => self.body(child, &Frame::IDENTITY, ground.as_deref(), None)?,
                "light" | "camera" | "site" => {
                    self.warn(child, "ignored (no effect on the dynamics)".into())
                }
                other => {
                    return Err(self.unsupported(
                        child,
                        format!("<{other}> in <worldbody> is not supported yet"),
                    ))
                }
            }
        }
        Ok(())
    }

    /// A top-level body's free joint: the body moves freely (the first such body is the
    /// floating base). Its damping and armature act on no DOF gymfleet has: warned about.
    fn free_joint(&mut self, joint: Node<'a, 'i>, class: Option<&str>, main: &str) -> Result<()> {
        for (attr, what) in [
            ("damping", "damping"),
            ("armature", "armature"),
            ("stiffness", "stiffness"),
        ] {
            if self.number(joint, class, attr)?.is_some_and(|v| v != 0.0) {
                self.warn(
                    joint,
                    format!("{what} on a free joint ignored (the base's six DOFs take none)"),
                );
            }
        }
        match &self.floating {
            None => self.floating = Some(main.to_string()),
            Some(base) => {
                let base = base.clone();
                self.warn(
                    joint,
                    format!(
                        "a second free body moves freely, but only the first ({base:?}) is observed as the floating base; name {main:?} in end_effector_ids to observe its pose"
                    ),
                );
            }
        }
        Ok(())
    }

    /// A frame from `pos` and one of `quat`, `euler`, `axisangle` (MuJoCo's defaults).
    fn local_frame(&self, node: Node<'a, 'i>, class: Option<&str>) -> Result<Frame> {
        let p = self.exactly::<3>(node, class, "pos")?.unwrap_or([0.0; 3]);
        let given: Vec<&str> = ["quat", "euler", "axisangle", "xyaxes", "zaxis"]
            .into_iter()
            .filter(|a| node.attribute(*a).is_some())
            .collect();
        if given.len() > 1 {
            return Err(self.bad(
                node,
                given[1],
                format!("an orientation is given twice ({})", given.join(", ")),
            ));
        }
        let rotation = match given.first().copied() {
            None => DQuat::IDENTITY,
            Some("quat") => {
                let [w, x, y, z] = self
                    .exactly::<4>(node, class, "quat")?
                    .unwrap_or([1.0, 0.0, 0.0, 0.0]);
                let q = DQuat::from_xyzw(x, y, z, w);
                if q.length() < 1e-9 {
                    return Err(self.bad(
                        node,
                        "quat",
                        "the zero quaternion is no rotation".into(),
                    ));
                }
                q.normalize()
            }
            Some("euler") => {
                // MuJoCo's default eulerseq "xyz": intrinsic x, then y, then z.
                let [a, b, c] = self.exactly::<3>(node, class, "euler")?.unwrap_or([0.0; 3]);
                DQuat::from_rotation_x(self.angle(a))
                    * DQuat::from_rotation_y(self.angle(b))
                    * DQuat::from_rotation_z(self.angle(c))
            }
            Some("axisangle") => {
                let [x, y, z, angle] = self
                    .exactly::<4>(node, class, "axisangle")?
                    .unwrap_or([0.0, 0.0, 1.0, 0.0]);
                let axis = DVec3::new(x, y, z);
                if axis.length() < 1e-12 {
                    return Err(self.bad(node, "axisangle", "the axis is the zero vector".into()));
                }
                DQuat::from_axis_angle(axis.normalize(), self.angle(angle))
            }
            Some("zaxis") => {
                let [x, y, z] = self
                    .exactly::<3>(node, class, "zaxis")?
                    .unwrap_or([0.0, 0.0, 1.0]);
                let axis = DVec3::new(x, y, z);
                if axis.length() < 1e-12 {
                    return Err(self.bad(node, "zaxis", "the axis is the zero vector".into()));
                }
                z_onto(axis.normalize())
            }
            Some(other) => {
                return Err(
                    self.unsupported(node, format!("{other} orientations are not supported yet"))
                )
            }
        };
        Ok(Frame {
            translation: DVec3::from_array(p),
            rotation,
        })
    }

    /// A helper instance: a small sphere of `HELPER_MASS` that collides with nothing.
    fn helper(&mut self, wanted: &str, at: &Frame) -> String {
        self.helper_before(wanted, at, None)
    }

    /// [`Converter::helper`], listed before instance `before` (so that a body's own
    /// instance stays the last of its own, as users look for it).
    fn helper_before(&mut self, wanted: &str, at: &Frame, before: Option<&str>) -> String {
        let name = self.unique(wanted);
        self.massless.insert(name.clone());
        self.parts.push(json!({
            "name": name,
            "primitive": {"type": "sphere", "radius": HELPER_RADIUS}
        }));
        let p = at.translation * MM;
        let instance = json!({
            "part": name, "name": name,
            "position": {"x": p.x, "y": p.y, "z": p.z},
            "collision": {"group": 0, "mask": 0},
            "inertial": {"mass": HELPER_MASS}
        });
        self.frames.insert(
            name.clone(),
            Frame {
                translation: at.translation,
                rotation: DQuat::IDENTITY,
            },
        );
        match before.and_then(|b| self.instances.iter().position(|i| i["name"] == b)) {
            Some(index) => self.instances.insert(index, instance),
            None => self.instances.push(instance),
        }
        name
    }

    /// A named point at `at` (world, m) on instance `instance`, in its frame.
    fn site(&mut self, wanted: &str, instance: &str, at: DVec3) {
        let Some(frame) = self.frames.get(instance) else {
            return;
        };
        let local = frame.rotation.inverse() * (at - frame.translation) * MM;
        let name = self.site_names.unique(wanted);
        self.sites.push(json!({
            "name": name,
            "instance": instance,
            "point": {"x": local.x, "y": local.y, "z": local.z}
        }));
    }

    fn joint_name(&mut self, wanted: &str) -> String {
        self.joint_names.unique(wanted)
    }

    fn weld(&mut self, parent: String, child: String) {
        let name = self.joint_name(&format!("{child}_weld"));
        self.joints
            .push(json!({"type": "fixed", "name": name, "parent": parent, "child": child}));
    }

    /// One body, its geoms, joints and children. `parent` is the instance it hangs from;
    /// `None` for a top-level body of a model with a free joint and no ground plane.
    fn body(
        &mut self,
        node: Node<'a, 'i>,
        parent_frame: &Frame,
        parent: Option<&str>,
        class: Option<&str>,
    ) -> Result<()> {
        let body_name = node.attribute("name").unwrap_or("body").to_string();
        let class_owned = node
            .attribute("childclass")
            .map(str::to_string)
            .or(class.map(str::to_string));
        let class = class_owned.as_deref();
        for (attr, ok) in [("mocap", "false"), ("gravcomp", "0")] {
            if let Some(v) = node.attribute(attr) {
                if v != ok {
                    return Err(
                        self.unsupported(node, format!("{attr}=\"{v}\" is not supported yet"))
                    );
                }
            }
        }
        let frame = parent_frame.then(&self.local_frame(node, None)?);
        let inertial = elements(node).find(|n| n.tag_name().name() == "inertial");
        let use_inertial = match (self.inertia_from_geom, inertial) {
            (InertiaFromGeom::True, Some(i)) => {
                self.warn(
                    i,
                    "ignored: compiler inertiafromgeom=\"true\" takes masses from the geoms".into(),
                );
                false
            }
            (InertiaFromGeom::False, None) => {
                return Err(self.unsupported(
                    node,
                    "inertiafromgeom=\"false\" and no <inertial>: the body has no mass".into(),
                ))
            }
            (_, i) => i.is_some(),
        };

        // Geoms: the first is the body's instance, the others are welded to it.
        let mut main: Option<String> = None;
        for geom in elements(node).filter(|n| n.tag_name().name() == "geom") {
            let given = if use_inertial {
                Some(HELPER_MASS)
            } else {
                None
            };
            let Some(name) = self.geom(geom, &frame, class, &body_name, given)? else {
                continue;
            };
            match &main {
                None => main = Some(name),
                Some(m) => self.weld(m.clone(), name),
            }
        }
        let main = match main {
            Some(m) => m,
            None => {
                if !use_inertial {
                    self.warn(
                        node,
                        "a body without geoms or <inertial> gets a 1 mg helper mass".into(),
                    );
                }
                self.helper(&body_name, &frame)
            }
        };
        if let Some(i) = inertial.filter(|_| use_inertial) {
            self.inertial(i, &frame, &main)?;
        }
        // The body's origin, by the body's name (what MuJoCo's body xpos reports).
        if let Some(name) = node.attribute("name") {
            self.site(name, &main, frame.translation);
        }

        // Joints: parent → (helpers) → the body's instance.
        let joints: Vec<Node<'a, 'i>> = elements(node)
            .filter(|n| matches!(n.tag_name().name(), "joint" | "freejoint"))
            .collect();
        let top_level = node
            .parent_element()
            .is_some_and(|p| p.tag_name().name() == "worldbody");
        let free = joints.iter().copied().find(|j| self.is_free(*j, class));
        if let Some(free) = free {
            if !top_level {
                return Err(self.unsupported(
                    free,
                    "a free joint belongs to a top-level body (a child of <worldbody>)".into(),
                ));
            }
            if joints.len() > 1 {
                return Err(
                    self.unsupported(free, "a free joint must be its body's only joint".into())
                );
            }
            self.free_joint(free, class, &main)?;
        }
        let parent = match (parent, free) {
            (_, Some(_)) => "",
            (Some(p), None) => p,
            (None, None) => {
                return Err(self.unsupported(
                    node,
                    "in a model with a free joint, a body fixed or jointed to the world needs a ground plane in <worldbody>"
                        .into(),
                ))
            }
        };
        if joints.is_empty() {
            self.weld(parent.to_string(), main.clone());
        }
        let joints = if free.is_some() { Vec::new() } else { joints };
        let mut from = parent.to_string();
        for (k, joint) in joints.iter().enumerate() {
            let to = if k + 1 == joints.len() {
                main.clone()
            } else {
                self.helper_before(&format!("{body_name}_dof{}", k + 1), &frame, Some(&main))
            };
            self.joint(*joint, &frame, class, &body_name, &from, &to)?;
            from = to;
        }

        for child in elements(node) {
            match child.tag_name().name() {
                "geom" | "joint" | "freejoint" | "inertial" => {}
                "body" => self.body(child, &frame, Some(&main), class)?,
                "site" => {
                    // A site is kept as a named point of the body's instance.
                    let at = frame.then(&self.local_frame(child, class)?).translation;
                    let name = child
                        .attribute("name")
                        .map_or_else(|| format!("{body_name}_site"), str::to_string);
                    self.site(&name, &main, at);
                }
                "camera" | "light" => {
                    self.warn(child, "ignored (no effect on the dynamics)".into())
                }
                other => {
                    return Err(self
                        .unsupported(child, format!("<{other}> in <body> is not supported yet")))
                }
            }
        }
        Ok(())
    }

    fn joint(
        &mut self,
        node: Node<'a, 'i>,
        body: &Frame,
        class: Option<&str>,
        body_name: &str,
        parent: &str,
        child: &str,
    ) -> Result<()> {
        let kind = if node.tag_name().name() == "freejoint" {
            "free"
        } else {
            self.attr(node, class, "type").unwrap_or("hinge")
        };
        let our = match kind {
            "hinge" => "revolute",
            "slide" => "prismatic",
            "ball" => "ball",
            "free" => {
                return Err(self.unsupported(
                    node,
                    "a free joint must be its body's only joint, in a top-level body".into(),
                ))
            }
            other => return Err(self.bad(node, "type", format!("unknown joint type {other:?}"))),
        };
        if self
            .numbers(node, class, "springdamper")?
            .is_some_and(|v| v.iter().any(|x| *x != 0.0))
        {
            return Err(self.unsupported(
                node,
                "springdamper (a spring-damper by time constant) is not supported yet".into(),
            ));
        }
        let friction = self
            .number(node, class, "frictionloss")?
            .filter(|f| *f != 0.0);
        if let Some(f) = friction.filter(|f| *f < 0.0) {
            return Err(self.bad(
                node,
                "frictionloss",
                format!("expected a friction >= 0, got {f}"),
            ));
        }
        let stiffness = self.number(node, class, "stiffness")?.filter(|k| *k != 0.0);
        if stiffness.is_some() && our == "ball" {
            return Err(self.unsupported(
                node,
                "stiffness on a ball joint (a rotational spring) is not supported yet".into(),
            ));
        }
        // MuJoCo's joint value is `ref` at the model's pose; gymfleet measures limits from
        // that pose, so a range (given in MuJoCo's values) shifts by −ref, and reports
        // positions with the `reference` added back.
        let reference = self.number(node, class, "ref")?.unwrap_or(0.0);
        let pos = DVec3::from_array(self.exactly::<3>(node, class, "pos")?.unwrap_or([0.0; 3]));
        let axis = DVec3::from_array(
            self.exactly::<3>(node, class, "axis")?
                .unwrap_or([0.0, 0.0, 1.0]),
        );
        if our != "ball" && axis.length() < 1e-12 {
            return Err(self.bad(node, "axis", "the axis is the zero vector".into()));
        }
        let anchor = body.point(pos) * MM;
        let name = node
            .attribute("name")
            .map_or_else(|| format!("{body_name}_joint"), str::to_string);
        let name = self.joint_name(&name);
        let mut j = Map::new();
        j.insert("type".into(), json!(our));
        j.insert("name".into(), json!(name));
        j.insert("parent".into(), json!(parent));
        j.insert("child".into(), json!(child));
        j.insert(
            "anchor".into(),
            json!({"x": anchor.x, "y": anchor.y, "z": anchor.z}),
        );
        if our != "ball" {
            let a = body.direction(axis.normalize());
            j.insert("axis".into(), json!({"x": a.x, "y": a.y, "z": a.z}));
        }
        let range = self.exactly::<2>(node, class, "range")?;
        let limited = self.flag(node, class, "limited")?;
        if let (Some([lo, hi]), Some(true) | None) = (range, limited) {
            if our == "ball" {
                return Err(self.unsupported(
                    node,
                    "a ball joint's range (a cone) is not supported yet".into(),
                ));
            }
            if lo < hi {
                let (lo, hi) = (lo - reference, hi - reference);
                let (lo, hi) = if our == "revolute" {
                    (self.angle(lo).to_degrees(), self.angle(hi).to_degrees())
                } else {
                    (lo * MM, hi * MM)
                };
                j.insert("min".into(), json!(lo));
                j.insert("max".into(), json!(hi));
                // The model's pose (qpos = ref) breaks the range: start at the nearest
                // limit, where MuJoCo's limit constraint would push it.
                if lo > 0.0 || hi < 0.0 {
                    let start = 0.0f64.clamp(lo, hi);
                    j.insert("initial".into(), json!(start));
                    self.warn(
                        node,
                        format!(
                            "joint {name:?} starts at {} {}, the end of its range nearest to the model's pose, which the range excludes",
                            (start * 1e6).round() / 1e6,
                            if our == "revolute" { "deg" } else { "mm" }
                        ),
                    );
                }
            } else if limited == Some(true) {
                return Err(self.bad(
                    node,
                    "range",
                    format!("a limited joint needs min < max, got {lo} {hi}"),
                ));
            }
        } else if limited == Some(true) {
            return Err(self.bad(node, "range", "limited=\"true\" without a range".into()));
        }
        if let Some(d) = self.number(node, class, "damping")?.filter(|d| *d != 0.0) {
            j.insert("damping".into(), json!(d));
        }
        if let Some(a) = self.number(node, class, "armature")?.filter(|a| *a != 0.0) {
            j.insert("armature".into(), json!(a));
        }
        if let Some(f) = friction {
            j.insert("friction".into(), json!(f));
        }
        if let Some(k) = stiffness {
            if k < 0.0 {
                return Err(self.bad(
                    node,
                    "stiffness",
                    format!("expected a stiffness >= 0, got {k}"),
                ));
            }
            j.insert("stiffness".into(), json!(k));
            // MuJoCo's spring pulls qpos to `springref`; positions here are qpos − ref.
            let rest = self.number(node, class, "springref")?.unwrap_or(0.0) - reference;
            if rest != 0.0 {
                let rest = if our == "revolute" {
                    self.angle(rest).to_degrees()
                } else {
                    rest * MM
                };
                j.insert("spring_rest".into(), json!(rest));
            }
        }
        if reference != 0.0 {
            // Observed positions are MuJoCo's qpos: the document's pose reports `ref`.
            let reference = if our == "revolute" {
                self.angle(reference).to_degrees()
            } else {
                reference * MM
            };
            j.insert("reference".into(), json!(reference));
        }
        match self.motors.get(&name).copied() {
            Some(motor) => {
                if let Some(e) = motor.max_effort {
                    j.insert("max_effort".into(), json!(e));
                }
                if motor.gear != 1.0 {
                    if our == "revolute" || our == "prismatic" {
                        // Actions are MuJoCo's ctrl: the effort is gear × ctrl.
                        j.insert("gear".into(), json!(motor.gear));
                    } else {
                        self.warn(
                            node,
                            format!(
                                "gear {} is folded into max_effort: a {our} joint's actions are torques (N·m)",
                                motor.gear
                            ),
                        );
                    }
                }
            }
            None => {
                j.insert("actuated".into(), json!(false));
            }
        }
        self.moving_joints.push(name);
        self.joints.push(Value::Object(j));
        Ok(())
    }

    /// `<inertial>`: given mass properties on the body's instance, in its frame.
    fn inertial(&mut self, node: Node<'a, 'i>, body: &Frame, instance: &str) -> Result<()> {
        let mass = self
            .number(node, None, "mass")?
            .ok_or_else(|| self.bad(node, "mass", "missing".into()))?;
        let local = self.local_frame(node, None)?;
        let world = body.then(&local);
        let principal = match (
            self.exactly::<3>(node, None, "diaginertia")?,
            self.exactly::<6>(node, None, "fullinertia")?,
        ) {
            (Some(d), None) => DMat3::from_diagonal(DVec3::from_array(d)),
            (None, Some([xx, yy, zz, xy, xz, yz])) => {
                DMat3::from_cols_array(&[xx, xy, xz, xy, yy, yz, xz, yz, zz])
            }
            _ => {
                return Err(self.bad(
                    node,
                    "diaginertia",
                    "expected one of diaginertia or fullinertia".into(),
                ))
            }
        };
        // Into the instance's frame: position and axes.
        let index = self
            .instances
            .iter()
            .position(|i| i["name"] == instance)
            .expect("the body's instance exists");
        self.instances[index]["inertial"] =
            inertial_json(mass, &world, principal, &self.frames[instance], MM);
        Ok(())
    }

    /// One geom as an instance; `None` for a plane that collides with nothing (dropped).
    /// `given_mass`: the body's mass comes from `<inertial>`; the geom then weighs this.
    fn geom(
        &mut self,
        node: Node<'a, 'i>,
        body: &Frame,
        class: Option<&str>,
        body_name: &str,
        given_mass: Option<f64>,
    ) -> Result<Option<String>> {
        let kind = self.attr(node, class, "type").unwrap_or("sphere");
        let contype = self.int(node, class, "contype", 1)?;
        let conaffinity = self.int(node, class, "conaffinity", 1)?;
        let size = self.numbers(node, class, "size")?.unwrap_or_default();
        let fromto = self.exactly::<6>(node, class, "fromto")?;
        let size_at = |k: usize, what: &str| -> Result<f64> {
            size.get(k).copied().filter(|v| *v > 0.0).ok_or_else(|| {
                self.bad(
                    node,
                    "size",
                    format!("a {kind} needs a positive {what} (size[{k}])"),
                )
            })
        };
        // The geom's frame in the body; `fromto` gives the centre and the z axis.
        let (local, half_length) = match fromto {
            Some(f) if matches!(kind, "capsule" | "cylinder") => {
                let (a, b) = (DVec3::new(f[0], f[1], f[2]), DVec3::new(f[3], f[4], f[5]));
                let axis = b - a;
                if axis.length() < 1e-12 {
                    return Err(self.bad(node, "fromto", "the two ends are the same point".into()));
                }
                (
                    Frame {
                        translation: (a + b) / 2.0,
                        rotation: z_onto(axis.normalize()),
                    },
                    Some(axis.length() / 2.0),
                )
            }
            Some(_) => {
                return Err(
                    self.unsupported(node, format!("fromto on a {kind} is not supported yet"))
                )
            }
            None => (self.local_frame(node, class)?, None),
        };
        let world = body.then(&local);
        let (primitive, corner) = match kind {
            "plane" => {
                if contype == 0 && conaffinity == 0 {
                    self.warn(node, "a plane that collides with nothing: dropped".into());
                    return Ok(None);
                }
                if body_name != "world" || !self.instances.is_empty() {
                    return Err(self.unsupported(
                        node,
                        "a colliding plane (a ground) must be the world's, and only one".into(),
                    ));
                }
                (json!({"type": "plane"}), DVec3::ZERO)
            }
            "sphere" => {
                let r = size_at(0, "radius")?;
                (json!({"type": "sphere", "radius": r * MM}), DVec3::ZERO)
            }
            "capsule" | "cylinder" => {
                let r = size_at(0, "radius")?;
                let half = match half_length {
                    Some(h) => h,
                    None => size_at(1, "half-length")?,
                };
                if kind == "capsule" {
                    (
                        json!({"type": "capsule", "radius": r * MM, "height": 2.0 * (half + r) * MM}),
                        DVec3::new(0.0, 0.0, half + r),
                    )
                } else {
                    (
                        json!({"type": "cylinder", "radius": r * MM, "height": 2.0 * half * MM}),
                        DVec3::new(0.0, 0.0, half),
                    )
                }
            }
            "box" => {
                let h = DVec3::new(
                    size_at(0, "x half-size")?,
                    size_at(1, "y half-size")?,
                    size_at(2, "z half-size")?,
                );
                (
                    json!({"type": "cube", "size": {"x": 2.0 * h.x * MM, "y": 2.0 * h.y * MM, "z": 2.0 * h.z * MM}}),
                    h,
                )
            }
            "mesh" | "hfield" | "sdf" => {
                return Err(self.unsupported(node, format!("{kind} geoms are not converted yet")))
            }
            other => {
                return Err(self.unsupported(node, format!("{other} geoms are not supported yet")))
            }
        };
        // Our primitives start at a corner (box) or their base (cylinder, capsule).
        let origin_m = world.point(-corner);
        let origin = origin_m * MM;
        let rotation = euler_xyz_degrees(world.rotation);
        let name = match node.attribute("name") {
            Some(n) => self.unique(n),
            None => self.unique(&format!("{body_name}_geom")),
        };
        for attr in [
            "condim", "solref", "solimp", "margin", "gap", "priority", "solmix",
        ] {
            if self.attr(node, class, attr).is_some() {
                self.warn(node, format!("{attr} ignored (gymfleet's contact model)"));
            }
        }
        let friction = self
            .numbers(node, class, "friction")?
            .and_then(|f| f.first().copied());
        let mut material = Map::new();
        if let Some(f) = friction {
            material.insert("friction".into(), json!(f));
        }
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
        if (contype, conaffinity) != (1, 1) {
            instance.insert(
                "collision".into(),
                json!({"group": contype, "mask": conaffinity}),
            );
        }
        match (
            given_mass,
            self.number(node, class, "mass")?,
            self.number(node, class, "density")?,
        ) {
            (Some(m), _, _) => {
                instance.insert("inertial".into(), json!({"mass": m}));
            }
            (None, Some(m), _) => {
                if m <= 0.0 {
                    return Err(self.bad(
                        node,
                        "mass",
                        format!("expected a positive mass, got {m}"),
                    ));
                }
                instance.insert("inertial".into(), json!({"mass": m}));
            }
            (None, None, Some(d)) if d != DEFAULT_DENSITY => {
                material.insert("density".into(), json!(d));
            }
            _ => {}
        }
        if !material.is_empty() {
            instance.insert("material".into(), json!(name));
        }
        self.frames.insert(
            name.clone(),
            Frame {
                translation: origin_m,
                rotation: world.rotation,
            },
        );
        self.parts
            .push(json!({"name": name, "primitive": primitive}));
        if !material.is_empty() {
            self.materials.insert(name.clone(), Value::Object(material));
        }
        self.instances.push(Value::Object(instance));
        Ok(Some(name))
    }

    fn finish(mut self) -> Result<Converted> {
        let materials = std::mem::take(&mut self.materials);
        // Motors name joints that exist.
        let known: HashSet<&String> = self.moving_joints.iter().collect();
        let mut unknown: Vec<(&String, &Motor)> = self
            .motors
            .iter()
            .filter(|(j, _)| !known.contains(j))
            .collect();
        unknown.sort_by_key(|(_, m)| m.order);
        if let Some((j, m)) = unknown.first() {
            return Err(ImportError::BadAttribute {
                element: "motor".into(),
                attribute: "joint".into(),
                line: m.line,
                reason: format!("no hinge, slide or ball joint is named {j:?}"),
            });
        }
        // Actions follow the joints' order; say so when the actuators are in another.
        let mut by_actuator: Vec<(&String, usize)> = self
            .moving_joints
            .iter()
            .filter_map(|j| self.motors.get(j).map(|m| (j, m.order)))
            .collect();
        let tree_order: Vec<&String> = by_actuator.iter().map(|(j, _)| *j).collect();
        by_actuator.sort_by_key(|(_, o)| *o);
        if by_actuator.iter().map(|(j, _)| *j).collect::<Vec<_>>() != tree_order {
            self.warnings.push(format!(
                "actions follow the joints' order ({}), not the actuators' order",
                tree_order
                    .iter()
                    .map(|j| j.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        // The floating base is the first instance.
        if let Some(base) = &self.floating {
            if let Some(at) = self.instances.iter().position(|i| i["name"] == *base) {
                let instance = self.instances.remove(at);
                self.instances.insert(0, instance);
            }
        }
        let mut document = json!({
            "parts": self.parts,
            "assembly": {"instances": self.instances, "joints": self.joints}
        });
        if !self.sites.is_empty() {
            document["assembly"]["sites"] = Value::Array(std::mem::take(&mut self.sites));
        }
        if self.floating.is_some() {
            document["floating_base"] = json!(true);
        }

        if !materials.is_empty() {
            document["materials"] = Value::Object(materials);
        }
        if !self.simulation.is_empty() {
            document["simulation"] = Value::Object(std::mem::take(&mut self.simulation));
        }
        if let Some(total) = self.total_mass {
            scale_total_mass(&mut document, total, &self.massless);
        }
        Ok(Converted {
            document,
            warnings: self.warnings.into_vec(),
        })
    }
}

/// MuJoCo's `compiler settotalmass`: scales every body's mass and inertia (the world's geoms
/// and the conversion's helpers excepted) so that they add up to `total` kg. A geom's mass
/// from its volume scales through its material's density, a given one (`inertial`) with
/// its tensor. A document that does not validate is left as it is: its own parse reports
/// why.
fn scale_total_mass(document: &mut Value, total: f64, massless: &HashSet<String>) {
    let Ok(assembly) = gymfleet_assembly::from_value(document.clone()) else {
        return;
    };
    let bodies: Vec<(usize, f64)> = assembly
        .instances
        .iter()
        .enumerate()
        .filter(|(_, i)| !massless.contains(&i.name))
        .map(|(k, i)| {
            let mass = i
                .inertial
                .map_or(i.shape.volume() * i.material.density, |given| given.mass);
            (k, mass)
        })
        .collect();
    let sum: f64 = bodies.iter().map(|(_, m)| m).sum();
    if !(sum.is_finite() && sum > 0.0) {
        return;
    }
    let factor = total / sum;
    for (k, _) in bodies {
        let instance = &mut document["assembly"]["instances"][k];
        if let Some(inertial) = instance.get_mut("inertial") {
            let mass = inertial["mass"].as_f64().unwrap_or(0.0);
            inertial["mass"] = json!(mass * factor);
            if let Some(Value::Object(inertia)) = inertial.get_mut("inertia") {
                for value in inertia.values_mut() {
                    *value = json!(value.as_f64().unwrap_or(0.0) * factor);
                }
            }
            continue;
        }
        let density = assembly.instances[k].material.density * factor;
        let name = assembly.instances[k].name.clone();
        instance["material"] = json!(name);
        let materials = document
            .as_object_mut()
            .expect("a document is an object")
            .entry("materials")
            .or_insert_with(|| json!({}));
        let material = materials
            .as_object_mut()
            .expect("materials are an object")
            .entry(name)
            .or_insert_with(|| json!({}));
        material["density"] = json!(density);
    }
}
