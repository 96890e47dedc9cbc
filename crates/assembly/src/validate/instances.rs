//! Instances: each placed part, its pose, name and overrides, checked.

use std::collections::hash_map::Entry;
use std::collections::HashMap;

use crate::document::InstanceDef;
use crate::error::quoted;
use crate::model::{Instance, LocalFrame, Material, MM_PER_M};

use super::{list, CheckedPart, Validator};

impl Validator {
    pub(super) fn instances(
        &mut self,
        defs: &[InstanceDef],
        parts: &HashMap<String, CheckedPart>,
        materials: &HashMap<String, Material>,
        floating_base: bool,
    ) -> Vec<Instance> {
        if defs.is_empty() {
            self.push(
                "assembly.instances",
                if floating_base {
                    "expected at least one instance (the first one is the floating base)"
                } else {
                    "expected at least one instance (the first one is grounded)"
                },
            );
        }
        let mut seen: HashMap<&str, usize> = HashMap::new();
        let mut out = Vec::with_capacity(defs.len());
        for (i, inst) in defs.iter().enumerate() {
            let path = format!("assembly.instances[{i}]");
            // Fields are checked in the order the documents write them.
            let part = parts.get(&inst.part);
            if part.is_none() {
                let mut known: Vec<&str> = parts.keys().map(String::as_str).collect();
                known.sort_unstable();
                self.push(
                    format!("{path}.part"),
                    format!(
                        "unknown part {} (known: {})",
                        quoted(&inst.part),
                        list(&known)
                    ),
                );
            }
            if inst.name.is_empty() {
                self.push(format!("{path}.name"), "expected a non-empty instance name");
            }
            match seen.entry(inst.name.as_str()) {
                Entry::Occupied(first) => self.push(
                    format!("{path}.name"),
                    format!(
                        "duplicate instance name {} (also assembly.instances[{}]): instance names must be unique",
                        quoted(&inst.name),
                        first.get()
                    ),
                ),
                Entry::Vacant(slot) => {
                    slot.insert(i);
                }
            }
            let position = inst
                .position
                .map(|p| self.vec3(&format!("{path}.position"), p))
                .unwrap_or_default();
            let rotation = inst
                .rotation
                .map(|r| self.vec3(&format!("{path}.rotation"), r))
                .unwrap_or_default();
            let own_material =
                self.material_ref(&format!("{path}.material"), &inst.material, materials);
            let Some(part) = part else { continue };
            let Some(shape) = part.shape.clone() else {
                continue;
            };
            let material = own_material.or(part.material).unwrap_or_default();
            let inertial = inst
                .inertial
                .as_ref()
                .and_then(|def| self.inertial(&format!("{path}.inertial"), def, &shape));
            // Sizes and densities are each finite and positive, but their product can
            // still overflow (or underflow) f64; the physics layer needs a real mass.
            // A plane is a ground wherever it is listed; the first instance is one too,
            // unless it is the floating base (which a plane cannot be).
            // A heightfield is a ground as a plane is.
            let plane = shape.is_ground();
            if plane && i == 0 && floating_base {
                self.push(
                    format!("{path}.part"),
                    format!(
                        "part {} is a {}, which cannot be the floating base (the first instance); list the robot's base first",
                        quoted(&inst.part),
                        ground_kind(&shape).1
                    ),
                );
                continue;
            }
            let first_floats = i == 0 && floating_base;
            let fixed = inst.fixed == Some(true);
            let mocap = inst.mocap == Some(true);
            for (flag, set) in [("fixed", fixed), ("mocap", mocap)] {
                if set && first_floats {
                    self.push(
                        format!("{path}.{flag}"),
                        "the floating base (the first instance) moves freely: it cannot be fixed or a mocap body; list it elsewhere, or remove floating_base",
                    );
                }
            }
            if fixed && mocap {
                self.push(
                    format!("{path}.mocap"),
                    "an instance is fixed or a mocap body (moved by its targets), not both",
                );
            }
            if plane && mocap {
                self.push(
                    format!("{path}.mocap"),
                    format!(
                        "a {} is a ground, fixed to the world: it cannot be a mocap body",
                        ground_kind(&shape).0
                    ),
                );
            }
            let body_frame = inst.body_frame.map(|f| LocalFrame {
                position: f
                    .position
                    .map(|p| self.vec3(&format!("{path}.body_frame.position"), p))
                    .unwrap_or_default()
                    .map(|c| c / MM_PER_M),
                rotation: f
                    .rotation
                    .map(|r| self.vec3(&format!("{path}.body_frame.rotation"), r))
                    .unwrap_or_default()
                    .map(f64::to_radians),
            });
            let grounded = !mocap && (plane || fixed || (i == 0 && !floating_base));
            let mass = shape.volume() * material.density;
            if !plane && inst.inertial.is_none() && !(mass.is_finite() && mass > 0.0) {
                self.push(
                    path.clone(),
                    format!(
                        "expected a finite, positive mass (volume × density), got {mass} kg; check the part's size and the material's density"
                    ),
                );
            }
            out.push(Instance {
                name: inst.name.clone(),
                shape,
                material,
                position: position.map(|c| c / MM_PER_M),
                rotation: rotation.map(f64::to_radians),
                grounded,
                collision: inst
                    .collision
                    .map_or((1, 1), |c| (c.group.unwrap_or(1), c.mask.unwrap_or(1))),
                inertial,
                mocap,
                body_frame,
            });
        }
        out
    }
}

/// What a ground shape is called in messages: its name, and that with what it is.
fn ground_kind(shape: &crate::model::Shape) -> (&'static str, &'static str) {
    match shape {
        crate::model::Shape::Heightfield(_) => ("heightfield", "heightfield (terrain, a ground)"),
        _ => ("plane", "plane (a half-space, a ground)"),
    }
}
