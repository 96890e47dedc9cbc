//! Sensors *(ext)*: named readings (MJCF's `<sensor>`), checked against the document's
//! joints, actuators, tendons, sites and instances. What each reads is MuJoCo's sensor of
//! the same type; the world evaluates them (`gymfleet-physics`, `sensors.rs`).

use crate::document::{InstanceDef, SensorDef, SensorFrameDef, SensorType};
use crate::error::{check_names, quoted, quoted_list, shown, Issue};
use crate::model::{Actuator, Joint, JointType, Site, Tendon};

/// Most sensors in one document.
pub const MAX_SENSORS: usize = 4096;
/// Largest cutoff or noise a sensor may carry.
const MAX_VALUE: f64 = 1e12;

/// A sensor, checked: what it reads, by index.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensor {
    /// Its name.
    pub name: String,
    /// Its type.
    pub kind: SensorType,
    /// What it reads.
    pub object: SensorObject,
    /// A frame sensor's reference frame (`None`: the world).
    pub reference: Option<SensorFrame>,
    /// MuJoCo's `cutoff` (0: none).
    pub cutoff: f64,
    /// MuJoCo's `noise` (metadata only).
    pub noise: f64,
}

/// What a sensor reads, by index into the assembly's lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensorObject {
    /// A revolute or prismatic joint.
    Joint(usize),
    /// An actuator of [`crate::Assembly::actuators`].
    Actuator(usize),
    /// A joint actuated directly (its own action value): its force is its effort over its
    /// gear.
    DirectActuator(usize),
    /// A fixed tendon.
    Tendon(usize),
    /// A frame: a site's or an instance's.
    Frame(SensorFrame),
    /// An instance and everything jointed below it.
    Subtree(usize),
}

/// A frame a sensor reads or is expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensorFrame {
    /// A site's frame (index into [`crate::Assembly::sites`]).
    Site(usize),
    /// An instance's frame (its placement's).
    Instance(usize),
}

/// What the document's lists hold, for the sensors to name.
pub(crate) struct Objects<'a> {
    pub(crate) instances: &'a [InstanceDef],
    pub(crate) joints: &'a [Joint],
    pub(crate) sites: &'a [Site],
    pub(crate) actuators: &'a [Actuator],
    pub(crate) tendons: &'a [Tendon],
}

/// What a type reads: the one field its object is given by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reads {
    Joint,
    Actuator,
    Tendon,
    Frame,
    Subtree,
    Site,
}

fn reads(kind: SensorType) -> Reads {
    use SensorType::*;
    match kind {
        Jointpos | Jointvel => Reads::Joint,
        Actuatorfrc => Reads::Actuator,
        Tendonpos | Tendonvel => Reads::Tendon,
        Framepos | Framequat | Framexaxis | Frameyaxis | Framezaxis | Framelinvel | Frameangvel
        | Framelinacc | Frameangacc => Reads::Frame,
        Subtreecom | Subtreelinvel | Subtreeangmom => Reads::Subtree,
        Gyro | Accelerometer | Velocimeter | Magnetometer | Touch | Force | Torque
        | Rangefinder => Reads::Site,
    }
}

/// The document's sensors, checked; every problem is an issue.
pub(crate) fn sensors(defs: &[SensorDef], objects: &Objects) -> (Vec<Sensor>, Vec<Issue>) {
    let mut issues = Vec::new();
    let names: Vec<&str> = defs.iter().map(|d| d.name.as_str()).collect();
    if !check_names(
        "assembly.sensors",
        "sensor",
        &names,
        MAX_SENSORS,
        &mut issues,
    ) {
        return (Vec::new(), issues);
    }
    let mut out = Vec::with_capacity(defs.len());
    for (k, def) in defs.iter().enumerate() {
        let path = format!("assembly.sensors[{k}]");
        let before = issues.len();
        let object = object(&path, def, objects, &mut issues);
        let reference = match (&def.reference, reads(def.kind)) {
            (None, _) => None,
            (Some(r), Reads::Frame) if !def.kind.needs_acceleration() => {
                frame(&format!("{path}.reference"), r, objects, &mut issues)
            }
            (Some(_), _) => {
                issues.push(Issue::new(
                    format!("{path}.reference"),
                    format!(
                        "a {} sensor has no reference frame (the frame position, \
                         orientation, axis and velocity sensors do)",
                        def.kind.as_str()
                    ),
                ));
                None
            }
        };
        let mut number = |field: &str, value: Option<f64>| {
            let v = value.unwrap_or(0.0);
            if !(v.is_finite() && (0.0..=MAX_VALUE).contains(&v)) {
                issues.push(Issue::new(
                    format!("{path}.{field}"),
                    format!("expected a number in [0, {MAX_VALUE:e}], got {}", shown(v)),
                ));
            }
            v
        };
        let cutoff = number("cutoff", def.cutoff);
        let noise = number("noise", def.noise);
        if let (Some(object), true) = (object, issues.len() == before) {
            out.push(Sensor {
                name: def.name.clone(),
                kind: def.kind,
                object,
                reference,
                cutoff,
                noise,
            });
        }
    }
    (out, issues)
}

/// The object `def` reads, from the one field its type takes.
fn object(
    path: &str,
    def: &SensorDef,
    objects: &Objects,
    issues: &mut Vec<Issue>,
) -> Option<SensorObject> {
    let kind = def.kind.as_str();
    let wanted = reads(def.kind);
    let given = [
        ("joint", def.joint.is_some()),
        ("actuator", def.actuator.is_some()),
        ("tendon", def.tendon.is_some()),
        ("site", def.site.is_some()),
        ("instance", def.instance.is_some()),
    ];
    let allowed: &[&str] = match wanted {
        Reads::Joint => &["joint"],
        Reads::Actuator => &["actuator"],
        Reads::Tendon => &["tendon"],
        Reads::Frame => &["site", "instance"],
        Reads::Subtree => &["instance"],
        Reads::Site => &["site"],
    };
    if let Some((field, _)) = given.iter().find(|(f, set)| *set && !allowed.contains(f)) {
        issues.push(Issue::new(
            format!("{path}.{field}"),
            format!(
                "a {kind} sensor reads a {}, not a {field}",
                allowed.join(" or a ")
            ),
        ));
        return None;
    }
    if given.iter().filter(|(_, set)| *set).count() != 1 {
        issues.push(Issue::new(
            path,
            format!(
                "a {kind} sensor needs exactly one {}",
                allowed.join(" or one ")
            ),
        ));
        return None;
    }
    let found = |list: &str, known: Vec<&str>, name: &str, issues: &mut Vec<Issue>| {
        find(path, list, &known, name, issues)
    };
    let joint_names = || objects.joints.iter().map(|j| j.name.as_str()).collect();
    match wanted {
        Reads::Joint => {
            let name = def.joint.as_deref()?;
            let j = found("joint", joint_names(), name, issues)?;
            scalar_joint(path, kind, name, j, objects, issues)
        }
        Reads::Actuator => actuator(path, def.actuator.as_deref()?, objects, issues),
        Reads::Tendon => {
            let known = objects.tendons.iter().map(|t| t.name.as_str()).collect();
            found("tendon", known, def.tendon.as_deref()?, issues).map(SensorObject::Tendon)
        }
        Reads::Subtree => {
            let known = objects.instances.iter().map(|i| i.name.as_str()).collect();
            found("instance", known, def.instance.as_deref()?, issues).map(SensorObject::Subtree)
        }
        Reads::Frame | Reads::Site => {
            let given = SensorFrameDef {
                site: def.site.clone(),
                instance: def.instance.clone(),
            };
            frame(path, &given, objects, issues).map(SensorObject::Frame)
        }
    }
}

/// The index of `name` among `known` (the document's `list`), or an issue.
fn find(
    path: &str,
    list: &str,
    known: &[&str],
    name: &str,
    issues: &mut Vec<Issue>,
) -> Option<usize> {
    let at = known.iter().position(|n| *n == name);
    if at.is_none() {
        issues.push(Issue::new(
            format!("{path}.{list}"),
            format!(
                "unknown {list} {} (known: {})",
                quoted(name),
                quoted_list(known)
            ),
        ));
    }
    at
}

/// Joint `j`, which a joint sensor reads: revolute or prismatic.
fn scalar_joint(
    path: &str,
    kind: &str,
    name: &str,
    j: usize,
    objects: &Objects,
    issues: &mut Vec<Issue>,
) -> Option<SensorObject> {
    let joint = &objects.joints[j];
    if !matches!(joint.kind, JointType::Revolute | JointType::Prismatic) {
        issues.push(Issue::new(
            format!("{path}.joint"),
            format!(
                "a {kind} sensor reads a revolute or prismatic joint; {} is {}",
                quoted(name),
                joint.kind.as_str()
            ),
        ));
        return None;
    }
    Some(SensorObject::Joint(j))
}

/// An `actuatorfrc`'s actuator: one of the document's actuators, else a joint actuated
/// directly (one DOF, its own action value).
fn actuator(
    path: &str,
    name: &str,
    objects: &Objects,
    issues: &mut Vec<Issue>,
) -> Option<SensorObject> {
    if let Some(a) = objects.actuators.iter().position(|a| a.name == name) {
        return Some(SensorObject::Actuator(a));
    }
    let direct = |j: &&Joint| j.actuated && j.tree_dof() == 1;
    let at = objects
        .joints
        .iter()
        .position(|j| j.name == name && direct(&j));
    if at.is_none() {
        let mut known: Vec<&str> = objects.actuators.iter().map(|a| a.name.as_str()).collect();
        known.extend(
            objects
                .joints
                .iter()
                .filter(direct)
                .map(|j| j.name.as_str()),
        );
        issues.push(Issue::new(
            format!("{path}.actuator"),
            format!(
                "unknown actuator {} (actuators and directly actuated joints: {})",
                quoted(name),
                quoted_list(&known)
            ),
        ));
    }
    at.map(SensorObject::DirectActuator)
}

/// A site's or an instance's frame (exactly one of the two named).
fn frame(
    path: &str,
    def: &SensorFrameDef,
    objects: &Objects,
    issues: &mut Vec<Issue>,
) -> Option<SensorFrame> {
    match (&def.site, &def.instance) {
        (Some(name), None) => {
            let at = objects.sites.iter().position(|s| s.name == *name);
            if at.is_none() {
                let known: Vec<&str> = objects.sites.iter().map(|s| s.name.as_str()).collect();
                issues.push(Issue::new(
                    format!("{path}.site"),
                    format!(
                        "unknown site {} (known: {})",
                        quoted(name),
                        quoted_list(&known)
                    ),
                ));
            }
            at.map(SensorFrame::Site)
        }
        (None, Some(name)) => {
            let at = objects.instances.iter().position(|i| i.name == *name);
            if at.is_none() {
                let known: Vec<&str> = objects.instances.iter().map(|i| i.name.as_str()).collect();
                issues.push(Issue::new(
                    format!("{path}.instance"),
                    format!(
                        "unknown instance {} (known: {})",
                        quoted(name),
                        quoted_list(&known)
                    ),
                ));
            }
            at.map(SensorFrame::Instance)
        }
        _ => {
            issues.push(Issue::new(path, "expected exactly one of site or instance"));
            None
        }
    }
}
