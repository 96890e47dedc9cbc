//! Instances: each placed part, its pose, name and overrides, checked.

use std::collections::hash_map::Entry;
use std::collections::HashMap;

use crate::document::InstanceDef;
use crate::error::quoted;
use crate::model::{Instance, LocalFrame, Material, MM_PER_M};

use super::{list, CheckedPart, Validator};

/// What every instance's checks share: the checked parts and materials, whether the first
/// instance floats, and the names taken so far.
struct InstancesContext<'d> {
    parts: &'d HashMap<String, CheckedPart>,
    materials: &'d HashMap<String, Material>,
    floating_base: bool,
    seen: HashMap<&'d str, usize>,
}

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
        let mut cx = InstancesContext {
            parts,
            materials,
            floating_base,
            seen: HashMap::new(),
        };
        let mut out = Vec::with_capacity(defs.len());
        for (i, inst) in defs.iter().enumerate() {
            out.extend(self.instance(i, inst, &mut cx));
        }
        out
    }

    /// Instance `i`: its fields checked in the order the documents write them, then its
    /// shape's rules; the instance when its part and shape are known.
    fn instance<'d>(
        &mut self,
        i: usize,
        inst: &'d InstanceDef,
        cx: &mut InstancesContext<'d>,
    ) -> Option<Instance> {
        let path = format!("assembly.instances[{i}]");
        let part = self.part_ref(&path, inst, cx.parts);
        self.instance_name(&path, i, inst, &mut cx.seen);
        let position = inst
            .position
            .map(|p| self.vec3(&format!("{path}.position"), p))
            .unwrap_or_default();
        let rotation = inst
            .rotation
            .map(|r| self.vec3(&format!("{path}.rotation"), r))
            .unwrap_or_default();
        let own_material =
            self.material_ref(&format!("{path}.material"), &inst.material, cx.materials);
        let part = part?;
        let shape = part.shape.clone()?;
        let material = own_material.or(part.material).unwrap_or_default();
        let inertial = inst
            .inertial
            .as_ref()
            .and_then(|def| self.inertial(&format!("{path}.inertial"), def, &shape));
        // A plane is a ground wherever it is listed; the first instance is one too,
        // unless it is the floating base (which a plane cannot be).
        // A heightfield is a ground as a plane is.
        let plane = shape.is_ground();
        let first_floats = i == 0 && cx.floating_base;
        if plane && first_floats {
            self.push(
                format!("{path}.part"),
                format!(
                    "part {} is a {}, which cannot be the floating base (the first instance); list the robot's base first",
                    quoted(&inst.part),
                    ground_kind(&shape).1
                ),
            );
            return None;
        }
        let (fixed, mocap) = self.holds(&path, inst, &shape, first_floats);
        let body_frame = self.body_frame(&path, inst);
        let grounded = !mocap && (plane || fixed || (i == 0 && !cx.floating_base));
        // Sizes and densities are each finite and positive, but their product can
        // still overflow (or underflow) f64; the physics layer needs a real mass.
        let mass = shape.volume() * material.density;
        if !plane && inst.inertial.is_none() && !(mass.is_finite() && mass > 0.0) {
            self.push(
                path.clone(),
                format!(
                    "expected a finite, positive mass (volume × density), got {mass} kg; check the part's size and the material's density"
                ),
            );
        }
        Some(Instance {
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
        })
    }

    /// The instance's part, refused when no part has its name.
    fn part_ref<'p>(
        &mut self,
        path: &str,
        inst: &InstanceDef,
        parts: &'p HashMap<String, CheckedPart>,
    ) -> Option<&'p CheckedPart> {
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
        part
    }

    /// The instance's name: not empty, and no other instance's.
    fn instance_name<'d>(
        &mut self,
        path: &str,
        i: usize,
        inst: &'d InstanceDef,
        seen: &mut HashMap<&'d str, usize>,
    ) {
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
    }

    /// `fixed` and `mocap`: at most one, neither on the floating base, and no mocap ground.
    fn holds(
        &mut self,
        path: &str,
        inst: &InstanceDef,
        shape: &crate::model::Shape,
        first_floats: bool,
    ) -> (bool, bool) {
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
        if shape.is_ground() && mocap {
            self.push(
                format!("{path}.mocap"),
                format!(
                    "a {} is a ground, fixed to the world: it cannot be a mocap body",
                    ground_kind(shape).0
                ),
            );
        }
        (fixed, mocap)
    }

    /// The body's frame in the part's (m, rad), when the instance gives one.
    fn body_frame(&mut self, path: &str, inst: &InstanceDef) -> Option<LocalFrame> {
        inst.body_frame.map(|f| LocalFrame {
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
        })
    }
}

/// What a ground shape is called in messages: its name, and that with what it is.
fn ground_kind(shape: &crate::model::Shape) -> (&'static str, &'static str) {
    match shape {
        crate::model::Shape::Heightfield(_) => ("heightfield", "heightfield (terrain, a ground)"),
        _ => ("plane", "plane (a half-space, a ground)"),
    }
}
