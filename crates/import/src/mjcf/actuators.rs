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

use super::actuator_form::{General, Type};
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

/// One `<actuator>` element, read.
#[derive(Debug, Clone)]
pub(super) struct Parsed {
    pub(super) name: String,
    tag: &'static str,
    /// `joint` (or `jointinparent`), or `tendon`.
    pub(super) joint: Option<String>,
    tendon: Option<String>,
    general: General,
    line: u32,
}

impl Parsed {
    /// Whether it has an activation (MuJoCo's `act` holds one for it).
    pub(super) fn has_activation(&self) -> bool {
        self.general.dyntype != actuator_form::Type::None
    }
}

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
            super::actuator_form::apply(self, element, tag, &own, &mut general)?;
            if let Some(what) = general.unsupported {
                return Err(self.unsupported(element, what.into()));
            }
            for attr in ["site", "body", "cranksite"] {
                if element.attribute(attr).is_some() {
                    return Err(self.unsupported(
                        element,
                        format!("{attr} transmissions are not supported (an actuator drives a joint or a tendon)"),
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
            super::actuator_form::apply(self, element, tag, &lookup, &mut general)?;
        }
        Ok(general)
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
                        reason: format!("no tendon is named {t:?}"),
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
    pub(super) fn direct_motors(&self) -> bool {
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
