//! Contact rules beside the collision bits (MJCF's `<contact>`): pairs of instances kept
//! from colliding (`<exclude>`), and pairs that always collide, with their own friction
//! and contact dimensionality (`<pair>`), whatever their bits say.

use crate::document::{ContactExcludeDef, ContactPairDef, ContactsDef, InstanceDef};
use crate::error::{quoted, quoted_list, shown, Issue};
use crate::model::{ContactPair, Contacts};

/// Most exclusions and pairs in one document, each.
pub const MAX_CONTACT_RULES: usize = 65_536;
/// Largest friction coefficient a pair may give.
const MAX_FRICTION: f64 = 1e3;

/// The document's contact rules, checked against its instances; every problem is an issue.
pub(crate) fn contacts(
    def: Option<&ContactsDef>,
    instances: &[InstanceDef],
) -> (Contacts, Vec<Issue>) {
    let mut issues = Vec::new();
    let mut out = Contacts::default();
    let Some(def) = def else {
        return (out, issues);
    };
    for (what, len) in [("exclude", def.exclude.len()), ("pairs", def.pairs.len())] {
        if len > MAX_CONTACT_RULES {
            issues.push(Issue::new(
                format!("assembly.contacts.{what}"),
                format!("expected at most {MAX_CONTACT_RULES} entries, got {len}"),
            ));
            return (out, issues);
        }
    }
    for (k, rule) in def.exclude.iter().enumerate() {
        let path = format!("assembly.contacts.exclude[{k}]");
        out.exclude
            .extend(exclusion(&path, rule, instances, &mut issues));
    }
    for (k, rule) in def.pairs.iter().enumerate() {
        let path = format!("assembly.contacts.pairs[{k}]");
        out.pairs.extend(pair(&path, rule, instances, &mut issues));
    }
    out.exclude.sort_unstable();
    out.exclude.dedup();
    (out, issues)
}

/// The instance named `name` (at `path`), reported when no instance has that name.
fn instance(
    path: String,
    name: &str,
    instances: &[InstanceDef],
    issues: &mut Vec<Issue>,
) -> Option<usize> {
    let found = instances.iter().position(|i| i.name == name);
    if found.is_none() {
        let known: Vec<&str> = instances.iter().map(|i| i.name.as_str()).collect();
        issues.push(Issue::new(
            path,
            format!(
                "unknown instance {} (known: {})",
                quoted(name),
                quoted_list(&known)
            ),
        ));
    }
    found
}

/// One `<exclude>`: two distinct known instances, as an ordered pair.
fn exclusion(
    path: &str,
    rule: &ContactExcludeDef,
    instances: &[InstanceDef],
    issues: &mut Vec<Issue>,
) -> Option<(usize, usize)> {
    let a = instance(format!("{path}.a"), &rule.a, instances, issues);
    let b = instance(format!("{path}.b"), &rule.b, instances, issues);
    let (a, b) = (a?, b?);
    if a == b {
        issues.push(Issue::new(
            format!("{path}.b"),
            format!(
                "names instance {} again: an instance never collides with itself",
                quoted(&rule.b)
            ),
        ));
        return None;
    }
    Some((a.min(b), a.max(b)))
}

/// One `<pair>`: two distinct known instances, a friction in range and a contact
/// dimensionality this simulator has (1 is frictionless).
fn pair(
    path: &str,
    rule: &ContactPairDef,
    instances: &[InstanceDef],
    issues: &mut Vec<Issue>,
) -> Option<ContactPair> {
    let a = instance(format!("{path}.a"), &rule.a, instances, issues);
    let b = instance(format!("{path}.b"), &rule.b, instances, issues);
    let friction = rule.friction;
    if let Some(f) = friction.filter(|f| !(f.is_finite() && (0.0..=MAX_FRICTION).contains(f))) {
        issues.push(Issue::new(
            format!("{path}.friction"),
            format!(
                "expected a friction coefficient in [0, {MAX_FRICTION}], got {}",
                shown(f)
            ),
        ));
    }
    let frictionless = match rule.condim {
        None | Some(3) => false,
        Some(1) => true,
        Some(other) => {
            issues.push(Issue::new(
                format!("{path}.condim"),
                format!(
                    "expected 1 (frictionless) or 3 (sliding friction), got {other}; torsional and rolling friction (4, 6) are not simulated"
                ),
            ));
            false
        }
    };
    match (a, b) {
        (Some(a), Some(b)) if a == b => {
            issues.push(Issue::new(
                format!("{path}.b"),
                format!("names instance {} again", quoted(&rule.b)),
            ));
            None
        }
        (Some(a), Some(b)) => Some(ContactPair {
            a: a.min(b),
            b: a.max(b),
            friction: if frictionless { Some(0.0) } else { friction },
        }),
        _ => None,
    }
}
