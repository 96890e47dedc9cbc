//! Tendons *(ext)*: named linear combinations of joint positions (MJCF's
//! `<tendon><fixed>`) and paths through sites (`<tendon><spatial>`), checked against the
//! document's joints and sites.

use crate::document::TendonDef;
use crate::error::{check_names, quoted, Issue};
use crate::model::{Joint, JointType, Site, Tendon};

/// Most tendons in one document.
pub const MAX_TENDONS: usize = 1024;
/// Most joints in one fixed tendon, and most sites in one spatial tendon.
pub const MAX_TENDON_JOINTS: usize = 64;
/// Largest magnitude of a coefficient.
const MAX_COEF: f64 = 1e6;
/// Largest stiffness or damping (SI per unit length or rate).
const MAX_GAIN: f64 = 1e9;
/// Largest magnitude of a rest length (m or rad).
const MAX_LENGTH: f64 = 1e6;

/// The document's tendons, checked against its validated joints; every problem is an issue.
pub(crate) fn tendons(
    defs: &[TendonDef],
    joints: &[Joint],
    sites: &[Site],
) -> (Vec<Tendon>, Vec<Issue>) {
    let mut issues = Vec::new();
    let mut out = Vec::with_capacity(defs.len());
    let names: Vec<&str> = defs.iter().map(|d| d.name.as_str()).collect();
    if !check_names(
        "assembly.tendons",
        "tendon",
        &names,
        MAX_TENDONS,
        &mut issues,
    ) {
        return (out, issues);
    }
    for (k, def) in defs.iter().enumerate() {
        let path = format!("assembly.tendons[{k}]");
        let before = issues.len();
        let path_sites = spatial_path(&path, def, sites, &mut issues);
        if def.sites.is_empty() && (def.joints.is_empty() || def.joints.len() > MAX_TENDON_JOINTS) {
            issues.push(Issue::new(
                format!("{path}.joints"),
                format!(
                    "expected 1 to {MAX_TENDON_JOINTS} joints (a fixed tendon) or 2 to {MAX_TENDON_JOINTS} sites (a spatial tendon), got {} joints",
                    def.joints.len()
                ),
            ));
        }
        let members = tendon_joints(&path, def, joints, &mut issues);
        let mut gain = |name: &str, value: Option<f64>| {
            let value = value.unwrap_or(0.0);
            if !(value.is_finite() && (0.0..=MAX_GAIN).contains(&value)) {
                issues.push(Issue::new(
                    format!("{path}.{name}"),
                    format!("expected a {name} in [0, {MAX_GAIN}], got {value}"),
                ));
            }
            value
        };
        let stiffness = gain("stiffness", def.stiffness);
        let damping = gain("damping", def.damping);
        check_lengths(&path, def, &mut issues);
        if issues.len() == before {
            out.push(Tendon {
                name: def.name.clone(),
                joints: members,
                sites: path_sites,
                stiffness,
                damping,
                spring_length: def.spring_length,
                range: def.range,
            });
        }
    }
    (out, issues)
}

/// A fixed tendon's joints and coefficients, each joint once.
fn tendon_joints(
    path: &str,
    def: &TendonDef,
    joints: &[Joint],
    issues: &mut Vec<Issue>,
) -> Vec<(usize, f64)> {
    let mut members = Vec::with_capacity(def.joints.len());
    for (j, member) in def.joints.iter().enumerate().take(MAX_TENDON_JOINTS) {
        let at = format!("{path}.joints[{j}]");
        match scalar_joint(&member.joint, joints, "a tendon's") {
            Err(message) => issues.push(Issue::new(format!("{at}.joint"), message)),
            Ok(i) if members.iter().any(|(m, _)| *m == i) => issues.push(Issue::new(
                format!("{at}.joint"),
                format!("{} is listed twice", quoted(&member.joint)),
            )),
            Ok(i) => members.push((i, member.coef)),
        }
        if !(member.coef.is_finite() && member.coef.abs() <= MAX_COEF) {
            issues.push(Issue::new(
                format!("{at}.coef"),
                format!(
                    "expected a coefficient within ±{MAX_COEF}, got {}",
                    member.coef
                ),
            ));
        }
    }
    members
}

/// A tendon's spring length and range: finite, bounded, and a spatial tendon's range a
/// rope's.
fn check_lengths(path: &str, def: &TendonDef, issues: &mut Vec<Issue>) {
    if let Some(l) = def.spring_length {
        if !(l.is_finite() && l.abs() <= MAX_LENGTH) {
            issues.push(Issue::new(
                format!("{path}.spring_length"),
                format!("expected a length within ±{MAX_LENGTH} (m or rad), got {l}"),
            ));
        }
    }
    if let Some([lo, hi]) = def.range {
        if !(lo.is_finite()
            && hi.is_finite()
            && lo.abs() <= MAX_LENGTH
            && hi.abs() <= MAX_LENGTH
            && lo < hi)
        {
            issues.push(Issue::new(
                format!("{path}.range"),
                format!("expected [min, max] with min < max, each within ±{MAX_LENGTH} (m or rad), got [{lo}, {hi}]"),
            ));
        } else if !def.sites.is_empty() && lo > 0.0 {
            issues.push(Issue::new(
                format!("{path}.range"),
                format!("a spatial tendon's range is a rope's: only its max holds, and min must be 0 or less, got {lo}"),
            ));
        }
    }
}

/// A spatial tendon's sites, by index (empty for a fixed tendon); every problem is an
/// issue.
fn spatial_path(
    path: &str,
    def: &TendonDef,
    sites: &[Site],
    issues: &mut Vec<Issue>,
) -> Vec<usize> {
    if def.sites.is_empty() {
        return Vec::new();
    }
    if !def.joints.is_empty() {
        issues.push(Issue::new(
            format!("{path}.sites"),
            "a tendon names joints (a fixed tendon) or sites (a spatial tendon), not both",
        ));
    }
    if def.sites.len() < 2 || def.sites.len() > MAX_TENDON_JOINTS {
        issues.push(Issue::new(
            format!("{path}.sites"),
            format!(
                "expected 2 to {MAX_TENDON_JOINTS} sites, got {}",
                def.sites.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(def.sites.len());
    for (k, name) in def.sites.iter().enumerate().take(MAX_TENDON_JOINTS) {
        match sites.iter().position(|s| &s.name == name) {
            Some(i) => out.push(i),
            None => issues.push(Issue::new(
                format!("{path}.sites[{k}]"),
                format!("no site is named {}", quoted(name)),
            )),
        }
    }
    out
}

/// The index of joint `name` if it is a revolute or prismatic joint of the tree (what a
/// fixed tendon and a coupling combine); else why not. `whose` names the user: "a
/// tendon's".
pub(crate) fn scalar_joint(name: &str, joints: &[Joint], whose: &str) -> Result<usize, String> {
    match joints.iter().position(|x| x.name == name) {
        None => Err(format!("no joint is named {}", quoted(name))),
        Some(i) if !matches!(joints[i].kind, JointType::Revolute | JointType::Prismatic) => {
            Err(format!(
                "{} is a {:?} joint; {whose} joints are revolute or prismatic",
                quoted(name),
                joints[i].kind
            ))
        }
        Some(i) if joints[i].closes_loop => Err(format!(
            "{} closes a kinematic loop; {whose} joints are joints of the tree",
            quoted(name)
        )),
        Some(i) => Ok(i),
    }
}
