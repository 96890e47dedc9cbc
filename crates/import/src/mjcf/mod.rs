//! MJCF (MuJoCo's XML) → assembly JSON. See the crate documentation for the subset.
//!
//! The mapping: every geom becomes an instance (its own part, placed in world mm with the
//! document's Euler angles); a body's first geom is the body's instance and its other geoms
//! are welded to it with fixed joints. A body's joints connect its parent's instance to its
//! instance, through helper instances (1 mg spheres that collide with nothing) when it has
//! several; a body without joints is welded to its parent. The world's geoms are the
//! grounded instance and parts welded to it. Masses come from the geoms (volume × density,
//! as MuJoCo's `inertiafromgeom`), or from `<inertial>` on the body's instance.

use std::collections::{BTreeMap, HashMap, HashSet};

use glam::{DMat3, DQuat, DVec3};
use gymfleet_assembly::{
    AssemblyDef, CollisionDef, CouplingDef, Document, FluidDef, HeightfieldDef, InertialDef,
    InstanceDef, Integrator, JointDef, JointType, MaterialDef, MeshDef, PartDef, Primitive,
    SimulationDef, SiteDef, TendonDef, TendonJointDef, Vec3, MAX_HEIGHTFIELD_SIDE,
};
use roxmltree::Node;

use crate::frame::{euler_xyz_degrees, inertial_def, vec3, z_onto, Frame};
use crate::xml::{elements, Names, Warnings, XmlReader};
use crate::{Converted, ImportError, Result};

mod actuator_form;
mod actuators;
mod attributes;
mod bodies;
mod body_parts;
mod contacts;
mod equality;
mod hfields;
pub(crate) use hfields::hfield_heights;
mod geoms;
mod include;
mod joints;
mod keyframes;
mod meshes;
mod sensors;
mod soft;
mod tendons;

pub use include::{expand_includes, MAX_INCLUDED_BYTES, MAX_INCLUDE_DEPTH};

/// Deepest nesting of `<body>` elements converted (the server's default cap on instances
/// is as large). The tree is converted recursively; deeper trees are refused, so that no
/// document can overflow the converting thread's stack (about 6 KiB per level in a debug
/// build: 3 MiB at this depth, within the step pool's 16 MiB threads).
pub const MAX_BODY_DEPTH: usize = 512;

/// Millimetres per metre.
const MM: f64 = 1000.0;
/// The mass of the helper instances the conversion adds (kg): between two joints of one
/// body, or for a body without geoms; small beside any real link, large enough for the
/// solver.
const HELPER_MASS: f64 = 1e-6;
/// A helper instance's radius (mm).
const HELPER_RADIUS: f64 = 1.0;
/// The radius of the ball a body given no rotational inertia turns like (m).
const POINT_RADIUS_M: f64 = 1e-3;
/// MuJoCo's default geom density, kg/m³.
const DEFAULT_DENSITY: f64 = 1000.0;

/// Converts an MJCF document into gymfleet's assembly JSON; its mesh files are named
/// from the assets' root ([`mjcf_to_document_in`] names them from the model's folder).
pub fn mjcf_to_document(xml: &str) -> Result<Converted> {
    mjcf_to_document_in(xml, "")
}

/// [`mjcf_to_document`] for a model file in `folder` of its assets: mesh files (under
/// `compiler meshdir`, `../` included) are named from the assets' root, as
/// [`crate::asset_path`] resolves them.
pub fn mjcf_to_document_in(xml: &str, folder: &str) -> Result<Converted> {
    let doc = roxmltree::Document::parse(xml).map_err(|e| ImportError::Xml(e.to_string()))?;
    let root = doc.root_element();
    let mut c = Converter::new(&doc);
    c.folder = folder.to_string();
    if root.tag_name().name() != "mujoco" {
        return Err(c.unsupported(root, "the root element must be <mujoco>".into()));
    }
    if let Some(include) = doc.descendants().find(|n| n.tag_name().name() == "include") {
        return Err(c.unsupported(
            include,
            "the included file is not at hand: send the model's files as assets (or convert the model by its path)".into(),
        ));
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
            "keyframe" => {} // After the bodies, whose joints its keys set.
            "sensor" => {}   // After the bodies, whose sites its sensors sit on.
            "size" | "visual" | "statistic" | "custom" => {
                c.warn(child, "ignored (no effect on the dynamics)".into());
            }
            "asset" => c.assets(child)?,
            "tendon" => c.tendons(child)?,
            "contact" | "equality" if elements(child).next().is_none() => {
                c.warn(child, "empty, ignored".into());
            }
            "equality" | "contact" => {} // After the bodies they name.
            other => return Err(c.unsupported(child, format!("<{other}> is not supported yet"))),
        }
    }
    // MuJoCo merges every <worldbody> (an included file often brings one).
    let worlds: Vec<Node> = elements(root)
        .filter(|n| n.tag_name().name() == "worldbody")
        .collect();
    if worlds.is_empty() {
        return Err(c.unsupported(root, "no <worldbody>".into()));
    }
    c.worldbody(&worlds)?;
    for equality in elements(root).filter(|n| n.tag_name().name() == "equality") {
        c.equalities(equality)?;
    }
    for contact in elements(root).filter(|n| n.tag_name().name() == "contact") {
        c.contacts(contact)?;
    }
    for sensor in elements(root).filter(|n| n.tag_name().name() == "sensor") {
        c.sensors(sensor)?;
    }
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
    /// The actuator elements it sets (`<motor>`, `<position>`, …), in order: MuJoCo
    /// keeps one actuator default per class, which each of them writes into.
    actuator_tags: Vec<&'a str>,
}

/// What `<option><flag>` switches off, honoured in the conversion.
#[derive(Debug, Default, Clone, Copy)]
struct SwitchedOff {
    /// `contact` (or `constraint`): no geom collides with any.
    contacts: bool,
    /// `limit` (or `constraint`): joints and tendons are unlimited.
    limits: bool,
    /// `equality` (or `constraint`): `<equality>` is left out.
    equalities: bool,
}

/// A motor's effect on its joint, when the actuators are plain joint motors in the joints'
/// order (actions are then the joints' own, `actuators.rs`).
#[derive(Debug, Clone, Copy)]
struct Motor {
    /// Effort bound, N·m or N, if the motor bounds it.
    max_effort: Option<f64>,
    /// The motor's gear: actions are MuJoCo's ctrl, the effort gear × ctrl.
    gear: f64,
    /// The motor's position among the actuators.
    order: usize,
}

struct Converter<'a, 'i> {
    doc: &'a roxmltree::Document<'i>,
    radian: bool,
    inertia_from_geom: InertiaFromGeom,
    classes: HashMap<String, Class<'a>>,
    warnings: Warnings,
    motors: HashMap<String, Motor>,
    /// Every `<actuator>` element in the general form, in order (`actuators.rs`).
    actuator_list: Vec<actuators::Parsed>,
    parts: Vec<PartDef>,
    materials: BTreeMap<String, MaterialDef>,
    /// `<option>`'s `cone`, `impratio`, `o_solref`/`o_solimp`/`o_margin` and `<flag override>`.
    contact_options: soft::ContactOptions,
    /// The document's `simulation` (gravity, dt, fluid) from `<option>`.
    simulation: SimulationDef,
    instances: Vec<InstanceDef>,
    /// Each instance's frame in the world (m), as written into its `position`/`rotation`.
    frames: HashMap<String, Frame>,
    joints: Vec<JointDef>,
    names: Names,
    joint_names: Names,
    /// Named points: every named body's origin and every `<site>` in a body.
    sites: Vec<SiteDef>,
    site_names: Names,
    /// Joint names with a DOF, in document (tree) order.
    moving_joints: Vec<String>,
    /// The instance of the first body with a free joint: the floating base.
    floating: Option<String>,
    /// `compiler settotalmass`: every body's mass and inertia scaled to this total (kg).
    total_mass: Option<f64>,
    /// Instances that are not bodies' own mass: the world's geoms and helpers.
    massless: HashSet<String>,
    /// `compiler meshdir` (else `assetdir`): where mesh files are, from the model's folder.
    mesh_dir: Option<String>,
    /// `compiler strippath="true"`: mesh file names lose their folders.
    strip_path: bool,
    /// `<asset><mesh>`s by name.
    meshes: HashMap<String, meshes::MeshAsset>,
    /// `<asset><hfield>`s by name.
    hfields: HashMap<String, hfields::HfieldAsset>,
    /// `<tendon><fixed>`s and `<tendon><spatial>`s, in document order.
    tendons: Vec<tendons::TendonRead>,
    /// `<equality><joint>`s and `<equality><tendon>`s, in document order.
    couplings: Vec<CouplingDef>,
    /// The model file's folder in its assets, which its mesh files are named from.
    folder: String,
    /// What `<option><flag>` switches off.
    switched_off: SwitchedOff,
    /// `compiler inertiagrouprange`: only geoms of these groups weigh anything.
    inertia_groups: (i64, i64),
    /// The top-level body with a free joint that is the floating base: the first with a
    /// joint below it.
    base_body: Option<roxmltree::NodeId>,
    /// The instance that stands for the world (what hangs from it by a joint), once made.
    world: Option<String>,
    /// Each named geom's instance, for `<contact><pair>`.
    geom_instances: HashMap<String, String>,
    /// Each named body's instances (the world's: its geoms), for `<contact><exclude>`.
    body_instances: HashMap<String, Vec<String>>,
    /// `<contact>`'s rules, read so far.
    contact_rules: gymfleet_assembly::ContactsDef,
    /// Each named body's instance and world frame (m), and the world's as "world", for
    /// `<equality>`.
    bodies: HashMap<String, (String, Frame)>,
    /// MuJoCo's qpos layout, joint by joint, for `<keyframe>`.
    qpos_slots: Vec<keyframes::QposSlot>,
    /// Each named `<site>`'s site, and each named body's origin site, for `<sensor>`.
    site_of: HashMap<String, String>,
    body_sites: HashMap<String, String>,
    /// The mocap bodies' instances and body frames (world, m), in body order: MuJoCo's
    /// mocap order, for a `<key>`'s `mpos` and `mquat`.
    mocap_bodies: Vec<(String, Frame)>,
    /// What each actuator's `ctrl` sets in a keyframe (its name, or its joint's for plain
    /// joint motors) and whether it has an activation, in MuJoCo's actuator order.
    key_actuators: Vec<(String, bool)>,
    /// The `<sensor>`s, converted after the bodies.
    sensors: Vec<gymfleet_assembly::SensorDef>,
    /// The `<sensor>` elements' children seen so far, converted or skipped (MuJoCo's
    /// sensor index, which names an unnamed sensor).
    sensor_count: usize,
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
            actuator_list: Vec::new(),
            parts: Vec::new(),
            materials: BTreeMap::new(),
            contact_options: soft::ContactOptions::default(),
            simulation: SimulationDef {
                gravity: None,
                dt: None,
                fluid: None,
                integrator: None,
                magnetic: None,
            },
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
            mesh_dir: None,
            strip_path: false,
            meshes: HashMap::new(),
            hfields: HashMap::new(),
            tendons: Vec::new(),
            couplings: Vec::new(),
            folder: String::new(),
            switched_off: SwitchedOff::default(),
            inertia_groups: (0, 5),
            base_body: None,
            world: None,
            geom_instances: HashMap::new(),
            body_instances: HashMap::new(),
            contact_rules: Default::default(),
            bodies: HashMap::new(),
            qpos_slots: Vec::new(),
            site_of: HashMap::new(),
            body_sites: HashMap::new(),
            sensors: Vec::new(),
            sensor_count: 0,
            mocap_bodies: Vec::new(),
            key_actuators: Vec::new(),
        }
    }

    fn assets(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for child in elements(node) {
            match child.tag_name().name() {
                "texture" | "material" | "skin" => {
                    self.warn(child, "ignored (appearance only)".into())
                }
                "mesh" => self.mesh_asset(child)?,
                "hfield" => self.hfield_asset(child)?,
                other => {
                    return Err(self.unsupported(child, format!("<{other}> is not supported yet")))
                }
            }
        }
        Ok(())
    }

    fn unique(&mut self, wanted: &str) -> String {
        self.names.unique(wanted)
    }

    fn finish(mut self) -> Result<Converted> {
        // What a key's ctrl and act name, before the actuators are converted.
        let direct = self.direct_motors();
        self.key_actuators = self
            .actuator_list
            .iter()
            .map(|a| {
                let name = if direct { a.joint.clone() } else { None };
                (name.unwrap_or_else(|| a.name.clone()), a.has_activation())
            })
            .collect();
        let actuators = self.actuator_defs()?;
        // `<flag contact="disable">`: nothing collides.
        if self.switched_off.contacts {
            for instance in &mut self.instances {
                instance.collision = Some(CollisionDef {
                    group: Some(0),
                    mask: Some(0),
                });
            }
        }
        // The first instance is the floating base, or else grounded: the world's.
        let first = match &self.floating {
            Some(base) => self.instances.iter().position(|i| i.name == *base),
            None => {
                if !self.instances.iter().any(|i| i.fixed == Some(true)) {
                    self.world_instance();
                }
                self.instances.iter().position(|i| i.fixed == Some(true))
            }
        };
        if let Some(at) = first {
            let instance = self.instances.remove(at);
            self.instances.insert(0, instance);
        }
        let tendons = self.tendon_defs()?;
        let contacts = self.contacts_def();
        let keyframes = self.keyframe_defs()?;
        // MuJoCo integrates with `Euler` unless `<option integrator>` says otherwise: the
        // document says so, since its own default is the implicit form.
        self.simulation.integrator.get_or_insert(Integrator::Euler);
        soft::finish_soft_contacts(
            &mut self.materials,
            &self.contact_options,
            self.simulation.dt,
        );
        soft::finish_soft_limits(&mut self.joints, self.simulation.dt);
        let simulation = Some(self.simulation);
        let mut document = Document {
            parts: self.parts,
            materials: self.materials,
            assembly: AssemblyDef {
                instances: self.instances,
                joints: self.joints,
                sites: self.sites,
                tendons,
                couplings: self.couplings,
                contacts,
                actuators,
                keyframes,
                initial_keyframe: None,
                sensors: self.sensors,
            },
            simulation,
            floating_base: self.floating.is_some().then_some(true),
        };
        if let Some(total) = self.total_mass {
            scale_total_mass(&mut document, total, &self.massless);
        }
        Ok(Converted::of(&document, self.warnings.into_vec()))
    }
}

/// MuJoCo's `compiler settotalmass`: scales every body's mass and inertia (the world's geoms
/// and the conversion's helpers excepted) so that they add up to `total` kg. A geom's mass
/// from its volume scales through its material's density, a given one (`inertial`) with
/// its tensor. A document that does not validate is left as it is: its own parse reports
/// why.
fn scale_total_mass(document: &mut Document, total: f64, massless: &HashSet<String>) {
    let Ok(assembly) = gymfleet_assembly::validate(document) else {
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
        let instance = &mut document.assembly.instances[k];
        if let Some(inertial) = &mut instance.inertial {
            inertial.mass *= factor;
            if let Some(i) = &mut inertial.inertia {
                for value in [
                    &mut i.xx, &mut i.yy, &mut i.zz, &mut i.xy, &mut i.xz, &mut i.yz,
                ] {
                    *value *= factor;
                }
            }
            continue;
        }
        let density = assembly.instances[k].material.density * factor;
        let name = assembly.instances[k].name.clone();
        instance.material = Some(name.clone());
        document.materials.entry(name).or_default().density = Some(density);
    }
}
