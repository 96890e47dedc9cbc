//! Couplings *(ext)*: a joint's or a fixed tendon's displacement held at a linear function
//! of another's (MJCF's `<equality><joint>` and `<equality><tendon>` with a linear
//! `polycoef`), checked against the document's joints and tendons and written as one
//! linear equation over joint displacements.

use crate::document::CouplingDef;
use crate::error::{check_names, quoted, Issue};
use crate::model::{Joint, Tendon};
use crate::tendons::scalar_joint;

/// Most couplings in one document.
pub const MAX_COUPLINGS: usize = 1024;
/// Largest magnitude of a polycoef term.
const MAX_TERM: f64 = 1e6;

/// A coupling as one equation: `Σ coef · (position − its position at the document's pose)
/// = offset` over revolute and prismatic joints (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct Coupling {
    /// Its name.
    pub name: String,
    /// (joint index in document order, coefficient), each joint once, no coefficient 0.
    pub terms: Vec<(usize, f64)>,
    /// The right-hand side, SI.
    pub offset: f64,
}

/// The document's couplings, checked against its validated joints and tendons; every
/// problem is an issue.
pub(crate) fn couplings(
    defs: &[CouplingDef],
    joints: &[Joint],
    tendons: &[Tendon],
) -> (Vec<Coupling>, Vec<Issue>) {
    let mut issues = Vec::new();
    let names: Vec<&str> = defs.iter().map(|d| d.name.as_str()).collect();
    if !check_names(
        "assembly.couplings",
        "coupling",
        &names,
        MAX_COUPLINGS,
        &mut issues,
    ) {
        return (Vec::new(), issues);
    }
    let mut out = Vec::with_capacity(defs.len());
    for (k, def) in defs.iter().enumerate() {
        let path = format!("assembly.couplings[{k}]");
        let before = issues.len();
        let [offset, ratio] = polycoef(&path, def.polycoef.as_deref(), &mut issues);
        let sides = match (&def.joint1, &def.tendon1) {
            (Some(_), Some(_)) => Err(Issue::new(
                format!("{path}.tendon1"),
                "a coupling holds a joint (joint1) or a tendon (tendon1), not both",
            )),
            (None, None) => Err(Issue::new(
                format!("{path}.joint1"),
                "missing: a coupling holds a joint (joint1) or a fixed tendon (tendon1)",
            )),
            (Some(first), None) => joint_sides(&path, def, first, joints),
            (None, Some(first)) => tendon_sides(&path, def, first, tendons),
        };
        let (held, followed) = match sides {
            Ok(sides) => sides,
            Err(issue) => {
                issues.push(issue);
                continue;
            }
        };
        // held − ratio · followed = offset, the terms merged by joint.
        let mut terms: Vec<(usize, f64)> = Vec::new();
        let scaled = followed.iter().map(|&(j, c)| (j, -ratio * c));
        for (j, c) in held.iter().copied().chain(scaled) {
            match terms.iter_mut().find(|(m, _)| *m == j) {
                Some((_, sum)) => *sum += c,
                None => terms.push((j, c)),
            }
        }
        terms.retain(|&(_, c)| c != 0.0);
        if terms.is_empty() {
            issues.push(Issue::new(
                format!("{path}.polycoef"),
                "the coupling's two sides cancel: it holds nothing",
            ));
        }
        if issues.len() == before {
            out.push(Coupling {
                name: def.name.clone(),
                terms,
                offset,
            });
        }
    }
    (out, issues)
}

/// `[offset, ratio]`: the polycoef's two terms, default MuJoCo's `[0, 1]`.
fn polycoef(path: &str, given: Option<&[f64]>, issues: &mut Vec<Issue>) -> [f64; 2] {
    let terms = given.unwrap_or(&[0.0, 1.0]);
    if terms.is_empty() || terms.len() > 2 {
        issues.push(Issue::new(
            format!("{path}.polycoef"),
            format!(
                "expected [offset] or [offset, ratio], got {} terms",
                terms.len()
            ),
        ));
        return [0.0, 1.0];
    }
    for (k, &t) in terms.iter().enumerate() {
        if !(t.is_finite() && t.abs() <= MAX_TERM) {
            issues.push(Issue::new(
                format!("{path}.polycoef[{k}]"),
                format!("expected a number within ±{MAX_TERM}, got {t}"),
            ));
        }
    }
    [terms[0], terms.get(1).copied().unwrap_or(1.0)]
}

type Sides = (Vec<(usize, f64)>, Vec<(usize, f64)>);

/// A joint coupling's two sides as joint terms: joint1, and joint2 if named.
fn joint_sides(
    path: &str,
    def: &CouplingDef,
    first: &str,
    joints: &[Joint],
) -> Result<Sides, Issue> {
    if def.tendon2.is_some() {
        return Err(Issue::new(
            format!("{path}.tendon2"),
            "a joint coupling follows a joint (joint2), not a tendon",
        ));
    }
    let held = scalar_joint(first, joints, "a coupling's")
        .map_err(|m| Issue::new(format!("{path}.joint1"), m))?;
    let followed = match &def.joint2 {
        None => Vec::new(),
        Some(second) => {
            let j = scalar_joint(second, joints, "a coupling's")
                .map_err(|m| Issue::new(format!("{path}.joint2"), m))?;
            if j == held {
                return Err(Issue::new(
                    format!("{path}.joint2"),
                    format!(
                        "{} is joint1 too; a coupling is between two joints",
                        quoted(second)
                    ),
                ));
            }
            vec![(j, 1.0)]
        }
    };
    Ok((vec![(held, 1.0)], followed))
}

/// A tendon coupling's two sides as joint terms: tendon1's, and tendon2's if named.
fn tendon_sides(
    path: &str,
    def: &CouplingDef,
    first: &str,
    tendons: &[Tendon],
) -> Result<Sides, Issue> {
    if def.joint2.is_some() {
        return Err(Issue::new(
            format!("{path}.joint2"),
            "a tendon coupling follows a tendon (tendon2), not a joint",
        ));
    }
    let fixed = |name: &str, field: &str| -> Result<Vec<(usize, f64)>, Issue> {
        match tendons.iter().find(|t| t.name == name) {
            None => Err(Issue::new(
                format!("{path}.{field}"),
                format!("no tendon is named {}", quoted(name)),
            )),
            Some(t) if t.is_spatial() => Err(Issue::new(
                format!("{path}.{field}"),
                format!(
                    "{} is a spatial tendon; a coupling's tendons are fixed tendons",
                    quoted(name)
                ),
            )),
            Some(t) => Ok(t.joints.clone()),
        }
    };
    let held = fixed(first, "tendon1")?;
    let followed = match &def.tendon2 {
        None => Vec::new(),
        Some(second) => fixed(second, "tendon2")?,
    };
    Ok((held, followed))
}
