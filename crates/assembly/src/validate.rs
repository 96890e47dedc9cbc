//! Semantic validation: a parsed [`Document`] becomes an SI [`Assembly`], or every
//! problem found is reported with its JSON path.
//!
//! This file holds the [`Validator`] (the issues found so far, and the checks every
//! section shares); its children check one section each, as `impl Validator` blocks:
//! `parts.rs` (materials, parts, shapes, meshes, inertials), `instances.rs`, `joints.rs`
//! (ends, tree and loops) and `joint_terms.rs` (a joint's axis, limits, initial
//! position, gear, DOF quantities, spring).

use crate::document::{Document, Vec3};
use crate::error::{quoted_list, AssemblyError, Issue, Result};
use crate::model::{Assembly, JointType, Material, Shape, MM_PER_M};

mod instances;
mod joint_terms;
mod joints;
mod parts;

/// Largest mass an instance's `inertial` may give, kg.
const MAX_MASS_KG: f64 = 1e6;
/// Farthest an instance's given centre of mass may lie from its origin, mm (1 km).
const MAX_COM_MM: f64 = 1e6;

/// What holds each instance where it is, if anything (never a joint's child), by
/// document index.
fn anchors(
    instances: &[crate::document::InstanceDef],
    parts: &std::collections::HashMap<String, CheckedPart>,
) -> Vec<Anchor> {
    instances
        .iter()
        .map(|i| {
            if parts
                .get(&i.part)
                .and_then(|p| p.shape.as_ref())
                .is_some_and(Shape::is_ground)
            {
                Anchor::Plane
            } else if i.mocap == Some(true) {
                Anchor::Mocap
            } else if i.fixed == Some(true) {
                Anchor::Fixed
            } else {
                Anchor::None
            }
        })
        .collect()
}

/// Validates a parsed document and converts it to SI units.
///
/// All problems are collected, so a user can fix a document in one round trip.
pub fn validate(doc: &Document) -> Result<Assembly> {
    let mut v = Validator::default();
    let materials = v.materials(&doc.materials);
    let parts = v.parts(&doc.parts, &materials);
    let floating_base = doc.floating_base.unwrap_or(false);
    let instances = v.instances(&doc.assembly.instances, &parts, &materials, floating_base);
    let anchors = anchors(&doc.assembly.instances, &parts);
    let mut joints = v.joints(
        &doc.assembly.joints,
        &doc.assembly.instances,
        &anchors,
        floating_base,
    );
    let (simulation, simulation_issues) = crate::simulation::simulation(doc.simulation.as_ref());
    v.issues.extend(simulation_issues);
    let (sites, site_issues) = crate::sites::sites(&doc.assembly.sites, &doc.assembly.instances);
    v.issues.extend(site_issues);
    let (tendons, tendon_issues) = crate::tendons::tendons(&doc.assembly.tendons, &joints, &sites);
    v.issues.extend(tendon_issues);
    let (couplings, coupling_issues) =
        crate::couplings::couplings(&doc.assembly.couplings, &joints, &tendons);
    v.issues.extend(coupling_issues);
    let (contacts, contact_issues) =
        crate::contacts::contacts(doc.assembly.contacts.as_ref(), &doc.assembly.instances);
    v.issues.extend(contact_issues);
    let (actuators, actuator_issues) =
        crate::actuators::actuators(&doc.assembly.actuators, &joints, &tendons);
    v.issues.extend(actuator_issues);
    let driven = crate::actuators::drive_joints(&actuators, &doc.assembly.joints, &mut joints);
    v.issues.extend(driven);
    let key_bodies = crate::keyframes::KeyBodies {
        names: instances.iter().map(|i| i.name.as_str()).collect(),
        free: crate::model::free_flags(&instances, &joints, floating_base),
        mocap: instances.iter().map(|i| i.mocap).collect(),
        actuators: &actuators,
    };
    let (keyframes, initial_keyframe, keyframe_issues) = crate::keyframes::keyframes(
        &doc.assembly.keyframes,
        doc.assembly.initial_keyframe.as_deref(),
        &joints,
        floating_base,
        &key_bodies,
    );
    v.issues.extend(keyframe_issues);
    let objects = crate::sensors::Objects {
        instances: &doc.assembly.instances,
        joints: &joints,
        sites: &sites,
        actuators: &actuators,
        tendons: &tendons,
    };
    let (sensors, sensor_issues) = crate::sensors::sensors(&doc.assembly.sensors, &objects);
    v.issues.extend(sensor_issues);
    if v.issues.is_empty() {
        Ok(Assembly {
            instances,
            joints,
            source: std::sync::Arc::from(""),
            gravity: simulation.gravity,
            dt: simulation.dt,
            floating_base,
            sites,
            fluid: simulation.fluid,
            integrator: simulation.integrator,
            tendons,
            couplings,
            contacts,
            actuators,
            keyframes,
            initial_keyframe,
            sensors,
            magnetic: simulation.magnetic,
        })
    } else {
        Err(AssemblyError::Invalid { issues: v.issues })
    }
}

#[derive(Default)]
struct Validator {
    issues: Vec<Issue>,
}

/// A part after checking: its shape in metres and its own material, if any.
struct CheckedPart {
    shape: Option<Shape>,
    material: Option<Material>,
}

impl Validator {
    fn push(&mut self, path: impl Into<String>, message: impl Into<String>) {
        self.issues.push(Issue::new(path, message));
    }

    fn finite(&mut self, path: &str, value: f64) -> bool {
        if value.is_finite() {
            true
        } else {
            self.push(path, format!("expected a finite number, got {value}"));
            false
        }
    }

    fn positive_length(&mut self, path: &str, mm: f64) -> f64 {
        if !(mm.is_finite() && mm > 0.0) {
            self.push(path, format!("expected a positive length in mm, got {mm}"));
        }
        mm / MM_PER_M
    }

    /// `v`'s components, each checked by `ok`; one issue per failing component at
    /// `{path}.x|y|z`, worded by `expected` from the value.
    fn components(
        &mut self,
        path: &str,
        v: Vec3,
        ok: impl Fn(f64) -> bool,
        expected: impl Fn(f64) -> String,
    ) -> [f64; 3] {
        for (axis, c) in [("x", v.x), ("y", v.y), ("z", v.z)] {
            if !ok(c) {
                self.push(format!("{path}.{axis}"), expected(c));
            }
        }
        v.to_array()
    }

    fn vec3(&mut self, path: &str, v: Vec3) -> [f64; 3] {
        for (name, c) in [("x", v.x), ("y", v.y), ("z", v.z)] {
            self.finite(&format!("{path}.{name}"), c);
        }
        v.to_array()
    }

    fn non_negative(&mut self, path: &str, value: Option<f64>, what: &str) -> Option<f64> {
        let v = value?;
        if !(v.is_finite() && v >= 0.0) {
            self.push(path, format!("expected a {what} >= 0, got {v}"));
        }
        Some(v)
    }
}

/// What holds an instance where it is, wherever it is listed: such an instance roots a
/// tree and is never a joint's child.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Anchor {
    /// Nothing: the instance hangs from a joint, or is the first instance, or moves freely.
    None,
    /// A plane: a ground.
    Plane,
    /// `"fixed": true`: static geometry.
    Fixed,
    /// `"mocap": true`: a kinematic body its pose targets move.
    Mocap,
}

/// What roots the kinematic trees: what holds each instance (see [`Anchor`]), and whether
/// the first instance floats.
#[derive(Clone, Copy)]
struct Roots<'a> {
    anchors: &'a [Anchor],
    floating_base: bool,
}

impl Roots<'_> {
    fn anchor(&self, i: usize) -> Anchor {
        self.anchors.get(i).copied().unwrap_or(Anchor::None)
    }

    /// Whether the world holds instance `i`: grounded (the first instance without a
    /// floating base, a plane, a fixed instance) or a mocap body.
    fn held(&self, i: usize) -> bool {
        (i == 0 && !self.floating_base) || self.anchor(i) != Anchor::None
    }
}

fn list(names: &[&str]) -> String {
    quoted_list(names)
}

/// The factor from a limit as written (deg, or mm for prismatic joints) to SI.
fn limit_to_si(kind: JointType) -> f64 {
    match kind {
        JointType::Prismatic => 1.0 / MM_PER_M,
        _ => 1f64.to_radians(),
    }
}
