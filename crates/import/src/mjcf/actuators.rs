//! `<actuator>`: every element is read as MuJoCo's XML reader reads it (`OneActuator`):
//! into one general form (gain, bias and dynamics types and parameters, gear and ranges),
//! starting from its class's actuator default, which each actuator element in a
//! `<default>` writes into whatever its tag. Then:
//!
//! - when every actuator is a `<motor>` on its own hinge or slide joint, in the joints'
//!   order, each joint takes its motor's value directly (its `gear`, and a `max_effort`
//!   from the ctrl and force ranges), as before: the actions are the same;
//! - otherwise every actuator becomes an assembly actuator (`general`, MuJoCo's compiled
//!   form), in `<actuator>` order: the actions are MuJoCo's `ctrl`, and the joints take
//!   none of their own.

use gymfleet_assembly::{ActuatorDef, ActuatorKind, DynamicsKind};

use super::*;

/// The actuator elements MuJoCo has.
const TAGS: [&str; 13] = [
    "motor",
    "position",
    "velocity",
    "intvelocity",
    "damper",
    "cylinder",
    "general",
    "muscle",
    "adhesion",
    "plugin",
    "dcmotor",
    "pid",
    "orientation",
];

/// Whether `tag` names an actuator element.
pub(super) fn is_actuator(tag: &str) -> bool {
    TAGS.contains(&tag)
}

/// MuJoCo's gain, bias and dynamics types, those gymfleet computes and the others by name.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Type {
    None,
    Fixed,
    Affine,
    Integrator,
    Filter,
    FilterExact,
    Other,
}

/// The general form of one actuator (MuJoCo's `mjsActuator`, the parts gymfleet reads).
#[derive(Debug, Clone)]
pub(super) struct General {
    gaintype: Type,
    biastype: Type,
    dyntype: Type,
    gainprm: [f64; 3],
    biasprm: [f64; 3],
    /// `dynprm[0]`: a filter's time constant.
    timeconst: f64,
    gear: f64,
    ctrlrange: [f64; 2],
    forcerange: [f64; 2],
    actrange: [f64; 2],
    ctrllimited: Option<bool>,
    forcelimited: Option<bool>,
    actlimited: Option<bool>,
    actearly: bool,
    /// A tag gymfleet does not compute (`<muscle>`, `<adhesion>`, …).
    unsupported: Option<&'static str>,
}

impl Default for General {
    /// MuJoCo's defaults.
    fn default() -> Self {
        General {
            gaintype: Type::Fixed,
            biastype: Type::None,
            dyntype: Type::None,
            gainprm: [1.0, 0.0, 0.0],
            biasprm: [0.0; 3],
            timeconst: 1.0,
            gear: 1.0,
            ctrlrange: [0.0; 2],
            forcerange: [0.0; 2],
            actrange: [0.0; 2],
            ctrllimited: None,
            forcelimited: None,
            actlimited: None,
            actearly: false,
            unsupported: None,
        }
    }
}

/// One `<actuator>` element, read.
#[derive(Debug, Clone)]
pub(super) struct Parsed {
    name: String,
    tag: &'static str,
    /// `joint` (or `jointinparent`), or `tendon`.
    joint: Option<String>,
    tendon: Option<String>,
    general: General,
    line: u32,
}

/// Attribute lookup: an element's own, or a default class's for one tag.
type Lookup<'x> = dyn Fn(&str) -> Option<&'x str> + 'x;

impl<'a, 'i> Converter<'a, 'i> {
    pub(super) fn actuators(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for (order, element) in elements(node).enumerate() {
            let tag = element.tag_name().name();
            let Some(&tag) = TAGS.iter().find(|t| **t == tag) else {
                return Err(self.unsupported(element, "is not an actuator".into()));
            };
            let class = element.attribute("class").unwrap_or("main");
            let mut general = self.class_actuator(element, class)?;
            let own = |name: &str| element.attribute(name);
            self.apply(element, tag, &own, &mut general)?;
            if let Some(what) = general.unsupported {
                return Err(self.unsupported(element, what.into()));
            }
            for attr in ["site", "body", "cranksite"] {
                if element.attribute(attr).is_some() {
                    return Err(self.unsupported(
                        element,
                        format!("{attr} transmissions are not supported (an actuator drives a joint or a fixed tendon)"),
                    ));
                }
            }
            let joint = element
                .attribute("joint")
                .or_else(|| element.attribute("jointinparent"))
                .map(str::to_string);
            let tendon = element.attribute("tendon").map(str::to_string);
            if joint.is_none() && tendon.is_none() {
                return Err(
                    self.unsupported(element, "an actuator must drive a joint or a tendon".into())
                );
            }
            if general.actearly {
                self.warn(
                    element,
                    "actearly: the force reads the activation at the step's start, one step behind MuJoCo's".into(),
                );
            }
            let line = self.line(element);
            let name = element
                .attribute("name")
                .map(str::to_string)
                .unwrap_or_else(|| format!("actuator{order}"));
            if tag == "motor" && tendon.is_none() {
                if let Some(j) = &joint {
                    let bound = |range: [f64; 2], limited: Option<bool>| match limited {
                        Some(true) | None if range[0] < range[1] => {
                            Some(range[0].abs().max(range[1].abs()))
                        }
                        _ => None,
                    };
                    let g = &general;
                    let ctrl = bound(g.ctrlrange, g.ctrllimited).map(|c| c * g.gear.abs());
                    let force = bound(g.forcerange, g.forcelimited);
                    let max_effort = match (ctrl, force) {
                        (Some(a), Some(b)) => Some(a.min(b)),
                        (a, b) => a.or(b),
                    }
                    .filter(|e| *e > 0.0);
                    let motor = Motor {
                        max_effort,
                        gear: g.gear,
                        order,
                    };
                    // A second motor on a joint makes the actuators general (below).
                    self.motors.entry(j.clone()).or_insert(motor);
                }
            }
            self.actuator_list.push(Parsed {
                name,
                tag,
                joint,
                tendon,
                general,
                line,
            });
        }
        Ok(())
    }

    /// The actuator default of class `class`: its parent's, then each actuator element
    /// of its `<default>` written into it.
    fn class_actuator(&self, element: Node<'a, 'i>, class: &str) -> Result<General> {
        let Some(c) = self.classes.get(class) else {
            if class == "main" {
                return Ok(General::default());
            }
            return Err(self.bad(
                element,
                "class",
                format!("no default class is named {class:?}"),
            ));
        };
        let mut general = match &c.parent {
            Some(parent) => self.class_actuator(element, parent)?,
            None => General::default(),
        };
        for &tag in &c.actuator_tags {
            let Some(&tag) = TAGS.iter().find(|t| **t == tag) else {
                continue;
            };
            let attributes = c.attributes.get(tag);
            let lookup = |name: &str| attributes.and_then(|a| a.get(name)).copied();
            self.apply(element, tag, &lookup, &mut general)?;
        }
        Ok(general)
    }

    /// Writes one actuator element's attributes (`get`) into `g`, as MuJoCo's reader does
    /// for its tag. Errors name `element` (the actuator being read).
    fn apply(
        &self,
        element: Node<'a, 'i>,
        tag: &'static str,
        get: &Lookup<'_>,
        g: &mut General,
    ) -> Result<()> {
        let nums = |name: &str| -> Result<Option<Vec<f64>>> {
            let Some(text) = get(name) else {
                return Ok(None);
            };
            text.split_whitespace()
                .map(|t| t.parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect::<Option<Vec<f64>>>()
                .filter(|v| !v.is_empty())
                .map(Some)
                .ok_or_else(|| {
                    self.bad(
                        element,
                        name,
                        format!("expected finite numbers, got {text:?}"),
                    )
                })
        };
        let one = |name: &str| -> Result<Option<f64>> { Ok(nums(name)?.map(|v| v[0])) };
        let pair = |name: &str| -> Result<Option<[f64; 2]>> {
            match nums(name)? {
                None => Ok(None),
                Some(v) if v.len() == 2 => Ok(Some([v[0], v[1]])),
                Some(v) => Err(self.bad(
                    element,
                    name,
                    format!("expected 2 numbers, got {}", v.len()),
                )),
            }
        };
        let limited = |name: &str| -> Result<Option<Option<bool>>> {
            match get(name) {
                None => Ok(None),
                Some("auto") => Ok(Some(None)),
                Some("true") => Ok(Some(Some(true))),
                Some("false") => Ok(Some(Some(false))),
                Some(other) => Err(self.bad(
                    element,
                    name,
                    format!("expected true, false or auto, got {other:?}"),
                )),
            }
        };
        let negative = |name: &str, v: f64| -> Result<()> {
            if v < 0.0 {
                return Err(self.bad(element, name, format!("cannot be negative, got {v}")));
            }
            Ok(())
        };
        // The attributes every actuator reads.
        if let Some(v) = nums("gear")? {
            g.gear = v[0];
            if v[1..].iter().any(|x| *x != 0.0) {
                return Err(self.unsupported(
                    element,
                    format!("gear {v:?}: only the first component of a gear is used by joint and tendon transmissions"),
                ));
            }
        }
        for (name, range) in [
            ("ctrlrange", &mut g.ctrlrange),
            ("forcerange", &mut g.forcerange),
            ("actrange", &mut g.actrange),
        ] {
            if let Some(v) = pair(name)? {
                *range = v;
            }
        }
        for (name, flag) in [
            ("ctrllimited", &mut g.ctrllimited),
            ("forcelimited", &mut g.forcelimited),
            ("actlimited", &mut g.actlimited),
        ] {
            if let Some(v) = limited(name)? {
                *flag = v;
            }
        }
        // `inheritrange` (a range from the joint's, written into ctrlrange by MuJoCo's
        // compiler), from the element or its class: 0 is MuJoCo's "off".
        if let Some(v) = get("inheritrange").filter(|v| v.trim().parse::<f64>() != Ok(0.0)) {
            return Err(self.bad(
                element,
                "inheritrange",
                format!("{v:?}: inheritrange is not supported yet; give ctrlrange"),
            ));
        }
        if let Some(v) = get("actearly") {
            g.actearly = v == "true";
        }
        if let Some(v) = get("actdim") {
            if !matches!(v.trim(), "-1" | "0" | "1") {
                return Err(self.unsupported(
                    element,
                    format!("actdim {v:?}: an actuator has one activation at most here"),
                ));
            }
        }
        match tag {
            "general" => {
                for (name, slot, allowed) in [
                    ("gaintype", &mut g.gaintype, &["fixed", "affine"][..]),
                    ("biastype", &mut g.biastype, &["none", "affine"][..]),
                    (
                        "dyntype",
                        &mut g.dyntype,
                        &["none", "integrator", "filter", "filterexact"][..],
                    ),
                ] {
                    let Some(v) = get(name) else { continue };
                    *slot = match v {
                        "none" => Type::None,
                        "fixed" => Type::Fixed,
                        "affine" => Type::Affine,
                        "integrator" => Type::Integrator,
                        "filter" => Type::Filter,
                        "filterexact" => Type::FilterExact,
                        _ => Type::Other,
                    };
                    if !allowed.contains(&v) {
                        return Err(self.unsupported(
                            element,
                            format!(
                                "{name} {v:?} is not supported (supported: {})",
                                allowed.join(", ")
                            ),
                        ));
                    }
                }
                for (name, slot) in [("gainprm", &mut g.gainprm), ("biasprm", &mut g.biasprm)] {
                    if let Some(v) = nums(name)? {
                        *slot = [0.0; 3];
                        for (k, x) in v.iter().enumerate() {
                            if k < 3 {
                                slot[k] = *x;
                            } else if *x != 0.0 {
                                return Err(self.unsupported(
                                    element,
                                    format!("{name} {v:?}: only the first three parameters are used by the affine form"),
                                ));
                            }
                        }
                    }
                }
                if let Some(v) = nums("dynprm")? {
                    g.timeconst = v[0];
                }
            }
            "motor" => {
                g.gainprm[0] = 1.0;
                g.dyntype = Type::None;
                g.gaintype = Type::Fixed;
                g.biastype = Type::None;
            }
            "position" | "intvelocity" => {
                let kp = one("kp")?.unwrap_or(g.gainprm[0]);
                let kv = one("kv")?;
                let dampratio = one("dampratio")?;
                let timeconst = one("timeconst")?;
                if kv.is_some() && dampratio.is_some() {
                    return Err(self.bad(
                        element,
                        "dampratio",
                        "kv and dampratio cannot both be defined".into(),
                    ));
                }
                g.gainprm[0] = kp;
                g.biasprm[1] = -kp;
                if let Some(kv) = kv {
                    negative("kv", kv)?;
                    g.biasprm[2] = -kv;
                }
                if let Some(d) = dampratio {
                    negative("dampratio", d)?;
                    g.biasprm[2] = d;
                }
                if let Some(t) = timeconst {
                    negative("timeconst", t)?;
                    g.timeconst = t;
                    g.dyntype = if t == 0.0 {
                        Type::None
                    } else {
                        Type::FilterExact
                    };
                }
                g.gaintype = Type::Fixed;
                g.biastype = Type::Affine;
                if tag == "intvelocity" {
                    g.dyntype = Type::Integrator;
                }
            }
            "velocity" => {
                let kv = one("kv")?.unwrap_or(g.gainprm[0]);
                g.biasprm = [0.0, 0.0, -kv];
                g.gainprm[0] = kv;
                g.dyntype = Type::None;
                g.gaintype = Type::Fixed;
                g.biastype = Type::Affine;
            }
            "damper" => {
                let inherited = g.gaintype == Type::Affine;
                let kv = one("kv")?.unwrap_or(if inherited { -g.gainprm[2] } else { 0.0 });
                negative("kv", kv)?;
                g.gainprm = [0.0, 0.0, -kv];
                g.ctrllimited = Some(true);
                g.dyntype = Type::None;
                g.gaintype = Type::Affine;
                g.biastype = Type::None;
            }
            "cylinder" => {
                let timeconst = one("timeconst")?.unwrap_or(g.timeconst);
                let mut bias = g.biasprm;
                if let Some(v) = nums("bias")? {
                    for (k, x) in v.iter().take(3).enumerate() {
                        bias[k] = *x;
                    }
                }
                let mut area = one("area")?.unwrap_or(g.gainprm[0]);
                if let Some(d) = one("diameter")? {
                    area = std::f64::consts::PI / 4.0 * d * d;
                }
                g.timeconst = timeconst;
                g.biasprm = bias;
                g.gainprm[0] = area;
                g.dyntype = Type::Filter;
                g.gaintype = Type::Fixed;
                g.biastype = Type::Affine;
            }
            _ => {
                g.unsupported = Some(match tag {
                    "muscle" => "muscle actuators are not supported yet (MuJoCo's muscle model: its length–force and velocity curves)",
                    "adhesion" => "adhesion actuators are not supported (they act on contacts)",
                    _ => "this actuator type is not supported (supported: motor, position, velocity, intvelocity, damper, cylinder, general)",
                });
            }
        }
        Ok(())
    }

    /// The actuators' part of the document: none when they are plain joint motors in the
    /// joints' order (the joints take them, `joints.rs`), else every actuator, in order,
    /// and the joints they drive take no action of their own.
    pub(super) fn actuator_defs(&mut self) -> Result<Vec<ActuatorDef>> {
        let known: HashSet<&String> = self.moving_joints.iter().collect();
        for a in &self.actuator_list {
            if let Some(j) = &a.joint {
                if !known.contains(j) {
                    return Err(ImportError::BadAttribute {
                        element: a.tag.into(),
                        attribute: "joint".into(),
                        line: a.line,
                        reason: format!("no hinge, slide or ball joint is named {j:?}"),
                    });
                }
            }
            if let Some(t) = &a.tendon {
                if !self.tendons.iter().any(|f| f.name == *t) {
                    return Err(ImportError::BadAttribute {
                        element: a.tag.into(),
                        attribute: "tendon".into(),
                        line: a.line,
                        reason: format!("no fixed tendon is named {t:?}"),
                    });
                }
            }
        }
        if self.direct_motors() {
            return Ok(Vec::new());
        }
        // The joints the motors had configured take no action of their own.
        let driven: HashSet<&String> = self.motors.keys().collect();
        for j in &mut self.joints {
            if j.name.as_ref().is_some_and(|n| driven.contains(n)) {
                j.actuated = Some(false);
                j.gear = None;
                j.max_effort = None;
            }
        }
        let mut names = Names::default();
        let list = std::mem::take(&mut self.actuator_list);
        list.iter()
            .map(|a| self.actuator_def(a, &mut names))
            .collect()
    }

    /// Whether every actuator is a `<motor>` on its own joint, in the joints' order.
    fn direct_motors(&self) -> bool {
        let mut seen = HashSet::new();
        let all_motors = self.actuator_list.iter().all(|a| {
            a.tag == "motor"
                && a.tendon.is_none()
                && a.joint.as_ref().is_some_and(|j| seen.insert(j.clone()))
        });
        if !all_motors {
            return false;
        }
        let by_tree: Vec<usize> = self
            .moving_joints
            .iter()
            .filter_map(|j| self.motors.get(j).map(|m| m.order))
            .collect();
        by_tree.windows(2).all(|w| w[0] < w[1])
    }

    /// One actuator in MuJoCo's compiled general form.
    fn actuator_def(&self, a: &Parsed, names: &mut Names) -> Result<ActuatorDef> {
        let g = &a.general;
        let bad = |attribute: &str, reason: String| ImportError::BadAttribute {
            element: a.tag.into(),
            attribute: attribute.into(),
            line: a.line,
            reason,
        };
        // MuJoCo's `autolimits`: a range given is a limit, unless said otherwise.
        let range = |name: &str, r: [f64; 2], limited: Option<bool>| -> Result<Option<[f64; 2]>> {
            let given = r != [0.0, 0.0];
            match limited {
                Some(false) => Ok(None),
                None if !given => Ok(None),
                _ if r[0] >= r[1] => Err(bad(
                    name,
                    format!(
                        "expected min < max for a limited range, got [{}, {}]",
                        r[0], r[1]
                    ),
                )),
                _ => Ok(Some(r)),
            }
        };
        let ctrl_range = range("ctrlrange", g.ctrlrange, g.ctrllimited)?;
        let force_range = range("forcerange", g.forcerange, g.forcelimited)?;
        let has_activation = g.dyntype != Type::None;
        let act_range = if has_activation {
            range("actrange", g.actrange, g.actlimited)?
        } else {
            None
        };
        let gain = match g.gaintype {
            Type::Affine => g.gainprm,
            _ => [g.gainprm[0], 0.0, 0.0],
        };
        let mut bias = match g.biastype {
            Type::Affine => g.biasprm,
            _ => [0.0; 3],
        };
        // A positive velocity bias of a position-like actuator is a damping ratio.
        let dampratio = if g.biastype == Type::Affine && gain[0] == -bias[1] && bias[2] > 0.0 {
            let ratio = bias[2];
            bias[2] = 0.0;
            Some(ratio)
        } else {
            None
        };
        let (dynamics, timeconst) = match g.dyntype {
            Type::Integrator => (Some(DynamicsKind::Integrator), None),
            Type::Filter => (Some(DynamicsKind::Filter), Some(g.timeconst)),
            Type::FilterExact => (Some(DynamicsKind::Filterexact), Some(g.timeconst)),
            _ => (None, None),
        };
        if timeconst.is_some_and(|t| t <= 0.0) {
            return Err(bad(
                "timeconst",
                format!(
                    "a filter's time constant must be positive, got {}",
                    g.timeconst
                ),
            ));
        }
        let mut def = ActuatorDef::motor(names.unique(&a.name), "");
        def.kind = ActuatorKind::General;
        def.joint = a.joint.clone();
        def.tendon = a.tendon.clone();
        def.gear = (g.gear != 1.0).then_some(g.gear);
        def.ctrl_range = ctrl_range;
        def.force_range = force_range;
        def.act_range = act_range;
        def.gain = Some(gain);
        def.bias = (bias != [0.0; 3]).then_some(bias);
        def.dynamics = dynamics;
        def.timeconst = timeconst;
        def.dampratio = dampratio;
        Ok(def)
    }
}
