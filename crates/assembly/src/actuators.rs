//! Actuators *(ext)*: MuJoCo's `<actuator>` elements, checked against the document's joints
//! and tendons and reduced, as MuJoCo's compiler reduces its shortcuts, to one general
//! form: `force = gain · input + bias`, the gain and the bias each affine in the
//! actuator's length and velocity, the input the control or an activation.

use crate::document::{ActuatorDef, ActuatorKind, DynamicsKind};
use crate::error::{check_names, quoted, quoted_list, Issue};
use crate::model::{Actuator, Dynamics, Joint, JointType, Tendon, Transmission};

/// Most actuators in one document.
pub const MAX_ACTUATORS: usize = 1024;
/// Largest magnitude of a gear, a gain, a bias term, a time constant, an area or a range
/// bound.
const MAX_VALUE: f64 = 1e9;

/// The fields each kind reads, beside `name`, `type`, the transmission, `gear` and the
/// control and force ranges.
fn allowed(kind: ActuatorKind) -> &'static [&'static str] {
    match kind {
        ActuatorKind::Motor => &[],
        ActuatorKind::Position => &["kp", "kv", "dampratio", "timeconst", "act_range"],
        ActuatorKind::Intvelocity => &["kp", "kv", "dampratio", "act_range"],
        ActuatorKind::Velocity => &["kv"],
        ActuatorKind::Damper => &["kv"],
        ActuatorKind::Cylinder => &["timeconst", "area", "diameter", "bias", "act_range"],
        ActuatorKind::General => &[
            "gain",
            "bias",
            "dynamics",
            "timeconst",
            "dampratio",
            "act_range",
        ],
    }
}

/// The kind-specific fields `def` sets.
fn given(def: &ActuatorDef) -> Vec<&'static str> {
    let mut out = Vec::new();
    let mut note = |name: &'static str, set: bool| {
        if set {
            out.push(name);
        }
    };
    note("kp", def.kp.is_some());
    note("kv", def.kv.is_some());
    note("dampratio", def.dampratio.is_some());
    note("timeconst", def.timeconst.is_some());
    note("area", def.area.is_some());
    note("diameter", def.diameter.is_some());
    note("gain", def.gain.is_some());
    note("bias", def.bias.is_some());
    note("dynamics", def.dynamics.is_some());
    note("act_range", def.act_range.is_some());
    out
}

struct Check<'a> {
    path: String,
    issues: &'a mut Vec<Issue>,
}

impl Check<'_> {
    fn push(&mut self, field: &str, message: String) {
        self.issues
            .push(Issue::new(format!("{}.{field}", self.path), message));
    }

    /// A finite value within [`MAX_VALUE`], at least `min`.
    fn value(&mut self, field: &str, value: Option<f64>, default: f64, min: f64) -> f64 {
        let v = value.unwrap_or(default);
        if !(v.is_finite() && v.abs() <= MAX_VALUE && v >= min) {
            let bound = if min == f64::NEG_INFINITY {
                format!("within ±{MAX_VALUE:e}")
            } else {
                format!("in [{min}, {MAX_VALUE:e}]")
            };
            self.push(field, format!("expected a number {bound}, got {v}"));
        }
        v
    }

    fn range(&mut self, field: &str, range: Option<[f64; 2]>) -> Option<[f64; 2]> {
        let [lo, hi] = range?;
        let ok = |v: f64| v.is_finite() && v.abs() <= MAX_VALUE;
        if !(ok(lo) && ok(hi) && lo < hi) {
            self.push(
                field,
                format!("expected [min, max] with min < max, each within ±{MAX_VALUE:e}, got [{lo}, {hi}]"),
            );
        }
        Some([lo, hi])
    }

    fn triple(&mut self, field: &str, v: Option<[f64; 3]>, default: [f64; 3]) -> [f64; 3] {
        let v = v.unwrap_or(default);
        if let Some(k) = v
            .iter()
            .position(|x| !(x.is_finite() && x.abs() <= MAX_VALUE))
        {
            self.push(
                &format!("{field}[{k}]"),
                format!("expected a number within ±{MAX_VALUE:e}, got {}", v[k]),
            );
        }
        v
    }
}

/// The document's actuators, checked against its validated joints and tendons; every
/// problem is an issue.
pub(crate) fn actuators(
    defs: &[ActuatorDef],
    joints: &[Joint],
    tendons: &[Tendon],
) -> (Vec<Actuator>, Vec<Issue>) {
    let mut issues = Vec::new();
    let mut out = Vec::with_capacity(defs.len());
    let names: Vec<&str> = defs.iter().map(|d| d.name.as_str()).collect();
    if !check_names(
        "assembly.actuators",
        "actuator",
        &names,
        MAX_ACTUATORS,
        &mut issues,
    ) {
        return (out, issues);
    }
    for (k, def) in defs.iter().enumerate() {
        let path = format!("assembly.actuators[{k}]");
        out.extend(actuator(path, def, joints, tendons, &mut issues));
    }
    (out, issues)
}

/// One actuator (at `path`): its transmission, the fields its kind reads, its ranges and
/// parameters, and its kind's rules; the actuator when none failed.
fn actuator(
    path: String,
    def: &ActuatorDef,
    joints: &[Joint],
    tendons: &[Tendon],
    issues: &mut Vec<Issue>,
) -> Option<Actuator> {
    let before = issues.len();
    let mut c = Check {
        path,
        issues: &mut *issues,
    };
    let transmission = transmission(&mut c, def, joints, tendons);
    for field in given(def) {
        if !allowed(def.kind).contains(&field) {
            c.push(
                field,
                format!(
                    "a {} actuator has no {field} (it reads {})",
                    def.kind.as_str(),
                    readable(def.kind)
                ),
            );
        }
    }
    let gear = c.value("gear", def.gear, 1.0, f64::NEG_INFINITY);
    let ctrl_range = c.range("ctrl_range", def.ctrl_range);
    let force_range = c.range("force_range", def.force_range);
    let act_range = c.range("act_range", def.act_range);
    if def.kv.is_some() && def.dampratio.is_some() {
        c.push(
            "dampratio",
            "give kv or dampratio, not both (kv is the damping, dampratio the damping as a ratio of critical)".into(),
        );
    }
    let (gain, bias, dynamics, dampratio) = reduce(&mut c, def);
    kind_rules(
        &mut c,
        def,
        (gain, bias, dampratio),
        ctrl_range,
        act_range,
        dynamics,
    );
    let transmission = transmission.filter(|_| issues.len() == before)?;
    Some(Actuator {
        name: def.name.clone(),
        kind: def.kind,
        transmission,
        gear,
        ctrl_range,
        force_range,
        act_range,
        gain,
        bias,
        dynamics,
        dampratio,
    })
}

/// The rules between an actuator's reduced parameters: dampratio on a position-like
/// actuator only, a damper's non-negative ctrl_range, and act_range only with activation
/// dynamics.
fn kind_rules(
    c: &mut Check<'_>,
    def: &ActuatorDef,
    (gain, bias, dampratio): ([f64; 3], [f64; 3], Option<f64>),
    ctrl_range: Option<[f64; 2]>,
    act_range: Option<[f64; 2]>,
    dynamics: Dynamics,
) {
    if dampratio.is_some() && gain[0] != -bias[1] {
        c.push(
            "dampratio",
            format!(
                "dampratio needs a position-like actuator (gain[0] = −bias[1]), got gain[0] = {} and bias[1] = {}",
                gain[0], bias[1]
            ),
        );
    }
    if def.kind == ActuatorKind::Damper {
        match ctrl_range {
            None => c.push(
                "ctrl_range",
                "a damper needs a ctrl_range, its coefficient's bounds (min >= 0)".into(),
            ),
            Some([lo, _]) if lo < 0.0 => c.push(
                "ctrl_range",
                format!(
                    "a damper's controls scale its damping and cannot be negative, got min {lo}"
                ),
            ),
            _ => {}
        }
    }
    if act_range.is_some() && dynamics == Dynamics::None {
        c.push(
            "act_range",
            "an actuator without activation dynamics has no activation to clamp".into(),
        );
    }
}

/// The kind-specific fields, for messages.
fn readable(kind: ActuatorKind) -> String {
    let fields = allowed(kind);
    if fields.is_empty() {
        "only gear, ctrl_range and force_range".into()
    } else {
        fields.join(", ")
    }
}

/// The joint or tendon `def` drives.
fn transmission(
    c: &mut Check<'_>,
    def: &ActuatorDef,
    joints: &[Joint],
    tendons: &[Tendon],
) -> Option<Transmission> {
    match (&def.joint, &def.tendon) {
        (Some(_), Some(_)) => {
            c.push(
                "tendon",
                "an actuator drives one joint or one tendon, not both".into(),
            );
            None
        }
        (None, None) => {
            c.push(
                "joint",
                "expected the joint (or the tendon) the actuator drives".into(),
            );
            None
        }
        (Some(name), None) => match joints.iter().position(|j| j.name == *name) {
            None => {
                let known: Vec<&str> = joints
                    .iter()
                    .filter(|j| j.kind.dof() > 0 && !j.closes_loop)
                    .map(|j| j.name.as_str())
                    .collect();
                c.push(
                    "joint",
                    format!(
                        "no joint is named {} (joints: {})",
                        quoted(name),
                        quoted_list(&known)
                    ),
                );
                None
            }
            Some(i) if !matches!(joints[i].kind, JointType::Revolute | JointType::Prismatic) => {
                c.push(
                    "joint",
                    format!(
                        "{} is a {} joint; an actuator drives a revolute or prismatic joint",
                        quoted(name),
                        joints[i].kind.as_str()
                    ),
                );
                None
            }
            Some(i) if joints[i].closes_loop => {
                c.push(
                    "joint",
                    format!(
                        "{} closes a kinematic loop; an actuator drives a joint of the tree",
                        quoted(name)
                    ),
                );
                None
            }
            Some(i) => Some(Transmission::Joint(i)),
        },
        (None, Some(name)) => match tendons.iter().position(|t| t.name == *name) {
            None => {
                let known: Vec<&str> = tendons.iter().map(|t| t.name.as_str()).collect();
                c.push(
                    "tendon",
                    format!(
                        "no tendon is named {} (tendons: {})",
                        quoted(name),
                        quoted_list(&known)
                    ),
                );
                None
            }
            Some(t) => Some(Transmission::Tendon(t)),
        },
    }
}

/// MuJoCo's shortcuts in the general form: (gain, bias, dynamics, dampratio).
fn reduce(c: &mut Check<'_>, def: &ActuatorDef) -> ([f64; 3], [f64; 3], Dynamics, Option<f64>) {
    let dampratio = def
        .dampratio
        .map(|d| c.value("dampratio", Some(d), 0.0, 0.0))
        .filter(|d| *d > 0.0);
    match def.kind {
        ActuatorKind::Motor => ([1.0, 0.0, 0.0], [0.0; 3], Dynamics::None, None),
        ActuatorKind::Position | ActuatorKind::Intvelocity => {
            let kp = c.value("kp", def.kp, 1.0, 0.0);
            let kv = c.value("kv", def.kv, 0.0, 0.0);
            let dynamics = if def.kind == ActuatorKind::Intvelocity {
                Dynamics::Integrator
            } else {
                match c.value("timeconst", def.timeconst, 0.0, 0.0) {
                    t if t > 0.0 => Dynamics::FilterExact { timeconst: t },
                    _ => Dynamics::None,
                }
            };
            ([kp, 0.0, 0.0], [0.0, -kp, -kv], dynamics, dampratio)
        }
        ActuatorKind::Velocity => {
            let kv = c.value("kv", def.kv, 1.0, 0.0);
            ([kv, 0.0, 0.0], [0.0, 0.0, -kv], Dynamics::None, None)
        }
        ActuatorKind::Damper => {
            let kv = c.value("kv", def.kv, 0.0, 0.0);
            ([0.0, 0.0, -kv], [0.0; 3], Dynamics::None, None)
        }
        ActuatorKind::Cylinder => {
            let timeconst = positive_timeconst(c, def.timeconst);
            let area = match (def.area, def.diameter) {
                (Some(_), Some(_)) => {
                    c.push("diameter", "give area or diameter, not both".into());
                    1.0
                }
                (_, Some(d)) => {
                    let d = c.value("diameter", Some(d), 0.0, 0.0);
                    std::f64::consts::PI / 4.0 * d * d
                }
                (area, None) => c.value("area", area, 1.0, 0.0),
            };
            let bias = c.triple("bias", def.bias, [0.0; 3]);
            ([area, 0.0, 0.0], bias, Dynamics::Filter { timeconst }, None)
        }
        ActuatorKind::General => {
            let gain = c.triple("gain", def.gain, [1.0, 0.0, 0.0]);
            let bias = c.triple("bias", def.bias, [0.0; 3]);
            let dynamics = match def.dynamics.unwrap_or_default() {
                DynamicsKind::None => {
                    if def.timeconst.is_some() {
                        c.push(
                            "timeconst",
                            "an actuator without a filter has no time constant (set dynamics to filter or filterexact)".into(),
                        );
                    }
                    Dynamics::None
                }
                DynamicsKind::Integrator => Dynamics::Integrator,
                DynamicsKind::Filter => Dynamics::Filter {
                    timeconst: positive_timeconst(c, def.timeconst),
                },
                DynamicsKind::Filterexact => Dynamics::FilterExact {
                    timeconst: positive_timeconst(c, def.timeconst),
                },
            };
            (gain, bias, dynamics, dampratio)
        }
    }
}

fn positive_timeconst(c: &mut Check<'_>, value: Option<f64>) -> f64 {
    let t = value.unwrap_or(1.0);
    if !(t.is_finite() && t > 0.0 && t <= MAX_VALUE) {
        c.push(
            "timeconst",
            format!("expected a filter time constant in (0, {MAX_VALUE:e}] s, got {t}"),
        );
    }
    t
}

/// Issues for joints that an actuator drives but that also say how a direct action drives
/// them (`actuated: true`, `gear`, `max_effort`), and marks the driven joints passive to
/// direct actions.
pub(crate) fn drive_joints(
    actuators: &[Actuator],
    defs: &[crate::document::JointDef],
    joints: &mut [Joint],
) -> Vec<Issue> {
    let mut issues = Vec::new();
    for a in actuators {
        let Transmission::Joint(j) = a.transmission else {
            continue;
        };
        // Validated joints are the document's, in its order.
        let Some(d) = defs.get(j) else {
            continue;
        };
        let def = j;
        for (field, set) in [
            ("actuated", d.actuated == Some(true)),
            ("gear", d.gear.is_some()),
            ("max_effort", d.max_effort.is_some()),
        ] {
            if set {
                issues.push(Issue::new(
                    format!("assembly.joints[{def}].{field}"),
                    format!(
                        "joint {} is driven by actuator {}, and takes no action of its own; put gear and ranges on the actuator and remove {field}",
                        quoted(&joints[j].name),
                        quoted(&a.name)
                    ),
                ));
            }
        }
        joints[j].actuated = false;
    }
    issues
}
