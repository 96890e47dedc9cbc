//! Sites: named points of instances (MJCF `<site>`s and body origins, kept by the MJCF
//! import), which tasks refer to by name (`{"site": "fingertip"}`). Each is a point in its
//! instance's frame, in mm, so it moves with the instance.

use crate::document::{InstanceDef, SiteDef};
use crate::error::{check_names, quoted, quoted_list, shown, Issue};
use crate::model::Site;

/// Most sites in one document.
pub const MAX_SITES: usize = 4096;
/// Largest magnitude of a site's coordinate, mm (100 km).
const MAX_MM: f64 = 1e8;

/// The document's sites, checked against its instances; every problem is an issue.
pub(crate) fn sites(defs: &[SiteDef], instances: &[InstanceDef]) -> (Vec<Site>, Vec<Issue>) {
    let mut issues = Vec::new();
    let mut out = Vec::with_capacity(defs.len());
    let names: Vec<&str> = defs.iter().map(|d| d.name.as_str()).collect();
    if !check_names("assembly.sites", "site", &names, MAX_SITES, &mut issues) {
        return (out, issues);
    }
    for (k, def) in defs.iter().enumerate() {
        let path = format!("assembly.sites[{k}]");
        let before = issues.len();
        let instance = instances.iter().position(|i| i.name == def.instance);
        if instance.is_none() {
            let known: Vec<&str> = instances.iter().map(|i| i.name.as_str()).collect();
            issues.push(Issue::new(
                format!("{path}.instance"),
                format!(
                    "unknown instance {} (known: {})",
                    quoted(&def.instance),
                    quoted_list(&known)
                ),
            ));
        }
        let point = def.point.to_array();
        for (axis, c) in ["x", "y", "z"].iter().zip(point) {
            if !(c.is_finite() && c.abs() <= MAX_MM) {
                issues.push(Issue::new(
                    format!("{path}.point.{axis}"),
                    format!(
                        "expected a finite coordinate within ±1e8 mm, got {}",
                        shown(c)
                    ),
                ));
            }
        }
        let rotation = def.rotation.map_or([0.0; 3], |r| r.to_array());
        for (axis, c) in ["x", "y", "z"].iter().zip(rotation) {
            if !(c.is_finite() && c.abs() <= 1e6) {
                issues.push(Issue::new(
                    format!("{path}.rotation.{axis}"),
                    format!(
                        "expected a finite angle within ±1e6 degrees, got {}",
                        shown(c)
                    ),
                ));
            }
        }
        let volume = def.volume.map(|v| {
            let size = v.size.to_array();
            for (axis, c) in ["x", "y", "z"].iter().zip(size) {
                if !(c.is_finite() && (0.0..=MAX_MM).contains(&c)) {
                    issues.push(Issue::new(
                        format!("{path}.volume.size.{axis}"),
                        format!("expected a size in [0, 1e8] mm, got {}", shown(c)),
                    ));
                }
            }
            (v.kind, size.map(|c| c / crate::model::MM_PER_M))
        });
        if let (Some(instance), true) = (instance, issues.len() == before) {
            out.push(Site {
                name: def.name.clone(),
                instance,
                point,
                rotation: rotation.map(f64::to_radians),
                volume,
            });
        }
    }
    (out, issues)
}
