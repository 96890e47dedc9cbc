//! Keyframes *(ext)*: named initial states (MJCF's `<keyframe><key>`), checked against the
//! document's joints and floating base.

use crate::document::{BaseKeyDef, KeyframeDef, Vec3};

use crate::error::{check_names, quoted, quoted_list, shown, Issue};
use crate::model::{Actuator, Joint, JointType, MM_PER_M};

/// Most keyframes in one document.
pub const MAX_KEYFRAMES: usize = 1024;
/// Largest magnitude of a keyframe's value (deg, mm, deg/s, mm/s).
const MAX_VALUE: f64 = 1e9;

/// A named initial state, checked: what a reset that names it starts from, before its
/// noise.
#[derive(Debug, Clone, PartialEq)]
pub struct Keyframe {
    /// Its name.
    pub name: String,
    /// `(joint index, position)`: revolute (deg) and prismatic (mm) joints' positions as
    /// observed (the joint's `reference` included), in document order of the joints.
    pub positions: Vec<(usize, f64)>,
    /// `(joint index, velocity)`, deg/s or mm/s.
    pub velocities: Vec<(usize, f64)>,
    /// `(ball joint index, rotation)`: the rotation vector, deg (as a ball joint is
    /// observed), and the angular velocity in the parent-side joint axes, deg/s.
    pub balls: Vec<(usize, [f64; 3], [f64; 3])>,
    /// The floating base's start, if the keyframe moves it.
    pub base: Option<BaseKey>,
    /// `(instance, start)` of the free bodies it moves: the reference frame's pose, its
    /// origin's velocity (world) and its angular velocity in its own axes, SI.
    pub free_bodies: Vec<(usize, BaseKey)>,
    /// `(instance, pose)` of the mocap bodies it places (velocities 0), SI.
    pub mocap: Vec<(usize, BaseKey)>,
    /// The command held at the reset: `(what, control)`, in document order.
    pub controls: Vec<(KeyControl, f64)>,
    /// `(actuator, activation)` at the reset.
    pub activations: Vec<(usize, f64)>,
}

/// What a keyframe's control drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyControl {
    /// A directly actuated joint (index into the joints): its torque-mode value.
    Joint(usize),
    /// An actuator (index into the actuators): its control.
    Actuator(usize),
}

/// The document's instances as keyframes name them: names, and which are free and which
/// mocap bodies.
pub(crate) struct KeyBodies<'a> {
    pub(crate) names: Vec<&'a str>,
    pub(crate) free: Vec<bool>,
    pub(crate) mocap: Vec<bool>,
    pub(crate) actuators: &'a [Actuator],
}

/// A floating base's start: its instance's frame, SI, world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaseKey {
    /// The instance's origin, m.
    pub position: [f64; 3],
    /// Its orientation `[qw, qx, qy, qz]`, unit.
    pub orientation: [f64; 4],
    /// Its origin's velocity, m/s.
    pub linear_velocity: [f64; 3],
    /// Its angular velocity, rad/s.
    pub angular_velocity: [f64; 3],
}

/// The document's keyframes and the index of its `initial_keyframe`, checked against its
/// validated joints; every problem is an issue.
pub(crate) fn keyframes(
    defs: &[KeyframeDef],
    initial: Option<&str>,
    joints: &[Joint],
    floating_base: bool,
    bodies: &KeyBodies,
) -> (Vec<Keyframe>, Option<usize>, Vec<Issue>) {
    let mut issues = Vec::new();
    let names: Vec<&str> = defs.iter().map(|d| d.name.as_str()).collect();
    if !check_names(
        "assembly.keyframes",
        "keyframe",
        &names,
        MAX_KEYFRAMES,
        &mut issues,
    ) {
        return (Vec::new(), None, issues);
    }
    let mut out = Vec::with_capacity(defs.len());
    for (k, def) in defs.iter().enumerate() {
        let path = format!("assembly.keyframes[{k}]");
        let before = issues.len();
        let positions = values(&path, "positions", &def.positions, joints, &mut issues);
        let velocities = values(&path, "velocities", &def.velocities, joints, &mut issues);
        let balls = balls(&path, def, joints, &mut issues);
        let base = def.base.as_ref().and_then(|b| {
            if !floating_base {
                issues.push(Issue::new(
                    format!("{path}.base"),
                    "the document has no floating base (set floating_base to true)",
                ));
                return None;
            }
            base(&format!("{path}.base"), b, &mut issues)
        });
        let free_bodies = placed(&path, "free_bodies", &def.free_bodies, bodies, &mut issues);
        let mocap = placed(&path, "mocap", &def.mocap, bodies, &mut issues);
        let controls = controls(&path, &def.controls, joints, bodies.actuators, &mut issues);
        let activations = activations(&path, &def.activations, bodies.actuators, &mut issues);
        if let Some(t) = def.time.filter(|t| !t.is_finite()) {
            issues.push(Issue::new(
                format!("{path}.time"),
                format!("expected a finite time in s, got {}", shown(t)),
            ));
        }
        if issues.len() == before {
            out.push(Keyframe {
                name: def.name.clone(),
                positions,
                velocities,
                balls,
                base,
                free_bodies,
                mocap,
                controls,
                activations,
            });
        }
    }
    let initial = initial.and_then(|name| {
        let found = names.iter().position(|n| *n == name);
        if found.is_none() {
            issues.push(Issue::new(
                "assembly.initial_keyframe",
                format!(
                    "no keyframe is named {}; the keyframes are {}",
                    quoted(name),
                    quoted_list(&names)
                ),
            ));
        }
        found
    });
    (out, initial, issues)
}

/// A keyframe's `positions` or `velocities`: one value per named revolute or prismatic
/// joint of the tree.
fn values(
    path: &str,
    field: &str,
    given: &std::collections::BTreeMap<String, f64>,
    joints: &[Joint],
    issues: &mut Vec<Issue>,
) -> Vec<(usize, f64)> {
    let mut out = Vec::with_capacity(given.len());
    for (name, &value) in given {
        let at = format!("{path}.{field}.{name}");
        let Some(j) = joints.iter().position(|j| j.name == *name) else {
            issues.push(Issue::new(
                at,
                format!("no joint is named {}", quoted(name)),
            ));
            continue;
        };
        let joint = &joints[j];
        if !matches!(joint.kind, JointType::Revolute | JointType::Prismatic) {
            issues.push(Issue::new(
                at,
                format!(
                    "{} is a {:?} joint; a keyframe sets revolute and prismatic joints",
                    quoted(name),
                    joint.kind
                ),
            ));
        } else if joint.on_loop {
            issues.push(Issue::new(
                at,
                format!(
                    "{} is on a kinematic loop, which a keyframe cannot move one joint of",
                    quoted(name)
                ),
            ));
        } else if finite(&at, value, issues) {
            out.push((j, value));
        }
    }
    out.sort_by_key(|(j, _)| *j);
    out
}

/// A keyframe's `rotations` and `spins`: ball joints' rotations (quaternions, as MuJoCo's
/// qpos) and angular velocities (the child's axes, as MuJoCo's qvel), into the rotation
/// vector and the angular velocity in the parent-side axes that a ball joint is observed
/// with.
fn balls(
    path: &str,
    def: &KeyframeDef,
    joints: &[Joint],
    issues: &mut Vec<Issue>,
) -> Vec<(usize, [f64; 3], [f64; 3])> {
    let mut out: Vec<(usize, [f64; 3], [f64; 3])> = Vec::new();
    let names: std::collections::BTreeSet<&String> =
        def.rotations.keys().chain(def.spins.keys()).collect();
    for name in names {
        let field = if def.rotations.contains_key(name) {
            "rotations"
        } else {
            "spins"
        };
        let at = format!("{path}.{field}.{name}");
        let Some(j) = joints.iter().position(|j| j.name == *name) else {
            issues.push(Issue::new(
                at,
                format!("no joint is named {}", quoted(name)),
            ));
            continue;
        };
        if joints[j].kind != JointType::Ball {
            issues.push(Issue::new(
                at,
                format!(
                    "{} is a {:?} joint; rotations and spins are a ball joint's",
                    quoted(name),
                    joints[j].kind
                ),
            ));
            continue;
        }
        let q = def
            .rotations
            .get(name)
            .copied()
            .unwrap_or([1.0, 0.0, 0.0, 0.0]);
        let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 1e-9) {
            issues.push(Issue::new(
                format!("{path}.rotations.{name}"),
                "expected a quaternion [qw, qx, qy, qz] of finite numbers, not all zero",
            ));
            continue;
        }
        let [w, x, y, z] = q.map(|c| c / norm);
        let spin = def.spins.get(name).map_or([0.0; 3], |v| v.to_array());
        if !spin
            .iter()
            .all(|c| finite(&format!("{path}.spins.{name}"), *c, issues))
        {
            continue;
        }
        // The rotation vector of the shorter rotation, deg.
        let (w, v) = if w < 0.0 {
            (-w, [-x, -y, -z])
        } else {
            (w, [x, y, z])
        };
        let s = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let angle = 2.0 * s.atan2(w);
        let rv = if s > 1e-12 {
            v.map(|c| (c / s * angle).to_degrees())
        } else {
            [0.0; 3]
        };
        // The child's angular velocity turned into the parent-side axes: q · ω · q⁻¹.
        let t = [
            2.0 * (v[1] * spin[2] - v[2] * spin[1]),
            2.0 * (v[2] * spin[0] - v[0] * spin[2]),
            2.0 * (v[0] * spin[1] - v[1] * spin[0]),
        ];
        let parent = [
            spin[0] + w * t[0] + (v[1] * t[2] - v[2] * t[1]),
            spin[1] + w * t[1] + (v[2] * t[0] - v[0] * t[2]),
            spin[2] + w * t[2] + (v[0] * t[1] - v[1] * t[0]),
        ];
        out.push((j, rv, parent));
    }
    out.sort_by_key(|b| b.0);
    out
}

/// A finite value of a keyframe's map, or an issue at `at`.
fn finite(at: &str, value: f64, issues: &mut Vec<Issue>) -> bool {
    let ok = value.is_finite() && value.abs() <= MAX_VALUE;
    if !ok {
        issues.push(Issue::new(
            at,
            format!(
                "expected a finite number within ±{}, got {}",
                shown(MAX_VALUE),
                shown(value)
            ),
        ));
    }
    ok
}

/// A keyframe's `controls`: one per named actuator, or joint actuated directly (one DOF).
fn controls(
    path: &str,
    given: &std::collections::BTreeMap<String, f64>,
    joints: &[Joint],
    actuators: &[Actuator],
    issues: &mut Vec<Issue>,
) -> Vec<(KeyControl, f64)> {
    let direct = |j: &Joint| j.actuated && j.tree_dof() == 1;
    let mut out = Vec::with_capacity(given.len());
    for (name, &value) in given {
        let at = format!("{path}.controls.{name}");
        let target = match actuators.iter().position(|a| a.name == *name) {
            Some(k) => Some(KeyControl::Actuator(k)),
            None => joints
                .iter()
                .position(|j| j.name == *name && direct(j))
                .map(KeyControl::Joint),
        };
        let Some(target) = target else {
            let mut known: Vec<&str> = actuators.iter().map(|a| a.name.as_str()).collect();
            known.extend(joints.iter().filter(|j| direct(j)).map(|j| j.name.as_str()));
            issues.push(Issue::new(
                at,
                format!(
                    "no actuator or directly actuated joint is named {} (the document's: {})",
                    quoted(name),
                    quoted_list(&known)
                ),
            ));
            continue;
        };
        if finite(&at, value, issues) {
            out.push((target, value));
        }
    }
    out
}

/// A keyframe's `activations`: one per named actuator that has an activation.
fn activations(
    path: &str,
    given: &std::collections::BTreeMap<String, f64>,
    actuators: &[Actuator],
    issues: &mut Vec<Issue>,
) -> Vec<(usize, f64)> {
    let mut out = Vec::with_capacity(given.len());
    for (name, &value) in given {
        let at = format!("{path}.activations.{name}");
        match actuators.iter().position(|a| a.name == *name) {
            Some(k) if actuators[k].has_activation() => {
                if finite(&at, value, issues) {
                    out.push((k, value));
                }
            }
            found => {
                let with: Vec<&str> = actuators
                    .iter()
                    .filter(|a| a.has_activation())
                    .map(|a| a.name.as_str())
                    .collect();
                issues.push(Issue::new(
                    at,
                    format!(
                        "{} (actuators with an activation: {})",
                        match found {
                            Some(_) => format!("actuator {} has no activation (no dynamics)", quoted(name)),
                            None => format!("no actuator is named {}", quoted(name)),
                        },
                        quoted_list(&with)
                    ),
                ));
            }
        }
    }
    out
}

/// A keyframe's `free_bodies` or `mocap`: a pose (and for a free body, velocities) per
/// named free or mocap body.
fn placed(
    path: &str,
    field: &str,
    given: &std::collections::BTreeMap<String, BaseKeyDef>,
    bodies: &KeyBodies,
    issues: &mut Vec<Issue>,
) -> Vec<(usize, BaseKey)> {
    let mocap = field == "mocap";
    let (what, kinds) = if mocap {
        ("mocap body", &bodies.mocap)
    } else {
        ("free body", &bodies.free)
    };
    let mut out = Vec::with_capacity(given.len());
    for (name, def) in given {
        let at = format!("{path}.{field}.{name}");
        let i = bodies.names.iter().position(|n| n == name);
        let Some(i) = i.filter(|&i| kinds[i]) else {
            let known: Vec<&str> = (0..kinds.len())
                .filter(|&i| kinds[i])
                .map(|i| bodies.names[i])
                .collect();
            issues.push(Issue::new(
                at,
                format!(
                    "no {what} is named {} (the document's: {})",
                    quoted(name),
                    quoted_list(&known)
                ),
            ));
            continue;
        };
        if mocap && (def.linear_velocity.is_some() || def.angular_velocity.is_some()) {
            issues.push(Issue::new(
                at,
                "a mocap body's keyframe is a pose: give no velocities",
            ));
            continue;
        }
        if let Some(key) = base(&at, def, issues) {
            out.push((i, key));
        }
    }
    out.sort_by_key(|(i, _)| *i);
    out
}

/// A keyframe's pose and velocities (a floating base's, a free or mocap body's), in SI.
fn base(path: &str, def: &BaseKeyDef, issues: &mut Vec<Issue>) -> Option<BaseKey> {
    let before = issues.len();
    let mut vector = |name: &str, v: Option<Vec3>, scale: f64| -> [f64; 3] {
        let v = v.map_or([0.0; 3], |v| v.to_array());
        for (axis, c) in ["x", "y", "z"].iter().zip(v) {
            if !(c.is_finite() && c.abs() <= MAX_VALUE) {
                issues.push(Issue::new(
                    format!("{path}.{name}.{axis}"),
                    format!(
                        "expected a finite number within ±{}, got {}",
                        shown(MAX_VALUE),
                        shown(c)
                    ),
                ));
            }
        }
        v.map(|c| c * scale)
    };
    let position = vector("position", Some(def.position), 1.0 / MM_PER_M);
    let linear_velocity = vector("linear_velocity", def.linear_velocity, 1.0 / MM_PER_M);
    let angular_velocity = vector("angular_velocity", def.angular_velocity, 1f64.to_radians());
    let q = def.orientation;
    let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    if !(norm.is_finite() && norm > 1e-9) {
        issues.push(Issue::new(
            format!("{path}.orientation"),
            format!(
                "expected a quaternion [qw, qx, qy, qz] of finite numbers, not all zero, got [{}]",
                q.iter().map(|c| shown(*c)).collect::<Vec<_>>().join(", ")
            ),
        ));
    }
    (issues.len() == before).then(|| BaseKey {
        position,
        orientation: q.map(|c| c / norm),
        linear_velocity,
        angular_velocity,
    })
}
