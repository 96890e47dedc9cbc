//! Fixed tendons *(ext)*: named linear combinations of joint positions (MJCF's
//! `<tendon><fixed>`), checked against the document's joints.

use crate::document::TendonDef;
use crate::error::{check_names, quoted, Issue};
use crate::model::{Joint, JointType, Tendon};

/// Most tendons in one document.
pub const MAX_TENDONS: usize = 1024;
/// Most joints in one tendon.
pub const MAX_TENDON_JOINTS: usize = 64;
/// Largest magnitude of a coefficient.
const MAX_COEF: f64 = 1e6;
/// Largest stiffness or damping (SI per unit length or rate).
const MAX_GAIN: f64 = 1e9;
/// Largest magnitude of a rest length (m or rad).
const MAX_LENGTH: f64 = 1e6;

/// The document's tendons, checked against its validated joints; every problem is an issue.
pub(crate) fn tendons(defs: &[TendonDef], joints: &[Joint]) -> (Vec<Tendon>, Vec<Issue>) {
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
        if def.joints.is_empty() || def.joints.len() > MAX_TENDON_JOINTS {
            issues.push(Issue::new(
                format!("{path}.joints"),
                format!(
                    "expected 1 to {MAX_TENDON_JOINTS} joints, got {}",
                    def.joints.len()
                ),
            ));
        }
        let mut members = Vec::with_capacity(def.joints.len());
        for (j, member) in def.joints.iter().enumerate().take(MAX_TENDON_JOINTS) {
            let at = format!("{path}.joints[{j}]");
            match joints.iter().position(|x| x.name == member.joint) {
                None => issues.push(Issue::new(
                    format!("{at}.joint"),
                    format!("no joint is named {}", quoted(&member.joint)),
                )),
                Some(i)
                    if !matches!(joints[i].kind, JointType::Revolute | JointType::Prismatic) =>
                {
                    issues.push(Issue::new(
                        format!("{at}.joint"),
                        format!(
                            "{} is a {:?} joint; a tendon's joints are revolute or prismatic",
                            quoted(&member.joint),
                            joints[i].kind
                        ),
                    ))
                }
                Some(i) if joints[i].closes_loop => issues.push(Issue::new(
                    format!("{at}.joint"),
                    format!(
                        "{} closes a kinematic loop; a tendon's joints are joints of the tree",
                        quoted(&member.joint)
                    ),
                )),
                Some(i) if members.iter().any(|(m, _)| *m == i) => issues.push(Issue::new(
                    format!("{at}.joint"),
                    format!("{} is listed twice", quoted(&member.joint)),
                )),
                Some(i) => members.push((i, member.coef)),
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
            }
        }
        if issues.len() == before {
            out.push(Tendon {
                name: def.name.clone(),
                joints: members,
                stiffness,
                damping,
                spring_length: def.spring_length,
                range: def.range,
            });
        }
    }
    (out, issues)
}
