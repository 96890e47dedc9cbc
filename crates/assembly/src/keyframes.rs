//! Keyframes *(ext)*: named initial states (MJCF's `<keyframe><key>`), checked against the
//! document's joints and floating base.

use crate::document::{BaseKeyDef, KeyframeDef, Vec3};
use crate::error::{check_names, quoted, quoted_list, shown, Issue};
use crate::model::{Joint, JointType, MM_PER_M};

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
    /// The floating base's start, if the keyframe moves it.
    pub base: Option<BaseKey>,
    /// `(instance, start)` of the free bodies it moves: the reference frame's pose, its
    /// origin's velocity (world) and its angular velocity in its own axes, SI.
    pub free_bodies: Vec<(usize, BaseKey)>,
    /// `(instance, pose)` of the mocap bodies it places (velocities 0), SI.
    pub mocap: Vec<(usize, BaseKey)>,
}

/// The document's instances as keyframes name them: names, and which are free and which
/// mocap bodies.
pub(crate) struct KeyBodies<'a> {
    pub(crate) names: Vec<&'a str>,
    pub(crate) free: Vec<bool>,
    pub(crate) mocap: Vec<bool>,
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
                base,
                free_bodies,
                mocap,
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
                    if names.is_empty() {
                        "none".to_string()
                    } else {
                        quoted_list(&names)
                    }
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
        } else if !(value.is_finite() && value.abs() <= MAX_VALUE) {
            issues.push(Issue::new(
                at,
                format!(
                    "expected a finite number within ±{}, got {}",
                    shown(MAX_VALUE),
                    shown(value)
                ),
            ));
        } else {
            out.push((j, value));
        }
    }
    out.sort_by_key(|(j, _)| *j);
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
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        quoted_list(&known)
                    }
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
