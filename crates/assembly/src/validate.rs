//! Semantic validation: a parsed [`Document`] becomes an SI [`Assembly`], or every
//! problem found is reported with its JSON path.

use std::collections::hash_map::Entry;
use std::collections::{BTreeMap, HashMap};

use crate::document::{
    ConvexMode, Document, InertialDef, InstanceDef, JointDef, MaterialDef, MeshDef, PartDef,
    Primitive, Vec3,
};
use crate::error::{quoted, quoted_list, shown, AssemblyError, Issue, Result};
use crate::mesh::{ConvexParts, MAX_MESH_TRIANGLES, MAX_MESH_VERTICES};
use crate::model::{Assembly, Inertial, Instance, Joint, JointType, Material, Shape, MM_PER_M};
use crate::topology::{Edge, Role, Topology};

/// Largest mass an instance's `inertial` may give, kg.
const MAX_MASS_KG: f64 = 1e6;
/// Farthest an instance's given centre of mass may lie from its origin, mm (1 km).
const MAX_COM_MM: f64 = 1e6;

/// Validates a parsed document and converts it to SI units.
///
/// All problems are collected, so a user can fix a document in one round trip.
pub fn validate(doc: &Document) -> Result<Assembly> {
    let mut v = Validator::default();
    let materials = v.materials(&doc.materials);
    let parts = v.parts(&doc.parts, &materials);
    let floating_base = doc.floating_base.unwrap_or(false);
    let instances = v.instances(&doc.assembly.instances, &parts, &materials, floating_base);
    // Which instances are planes (fixed grounds, never a joint's child), by document index.
    let planes: Vec<bool> = doc
        .assembly
        .instances
        .iter()
        .map(|i| parts.get(&i.part).and_then(|p| p.shape.as_ref()) == Some(&Shape::Plane))
        .collect();
    let joints = v.joints(
        &doc.assembly.joints,
        &doc.assembly.instances,
        &planes,
        floating_base,
    );
    let (simulation, simulation_issues) = crate::simulation::simulation(doc.simulation.as_ref());
    v.issues.extend(simulation_issues);
    let (sites, site_issues) = crate::sites::sites(&doc.assembly.sites, &doc.assembly.instances);
    v.issues.extend(site_issues);
    let (tendons, tendon_issues) = crate::tendons::tendons(&doc.assembly.tendons, &joints);
    v.issues.extend(tendon_issues);
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
            tendons,
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

    fn materials(&mut self, defs: &BTreeMap<String, MaterialDef>) -> HashMap<String, Material> {
        let mut out = HashMap::new();
        for (name, def) in defs {
            let path = format!("materials.{name}");
            let default = Material::default();
            let density = def.density.unwrap_or(default.density);
            if !(density.is_finite() && density > 0.0) {
                self.push(
                    format!("{path}.density"),
                    format!("expected a positive density in kg/m³, got {density}"),
                );
            }
            let friction = def.friction.unwrap_or(default.friction);
            if !(friction.is_finite() && friction >= 0.0) {
                self.push(
                    format!("{path}.friction"),
                    format!("expected a friction coefficient >= 0, got {friction}"),
                );
            }
            let restitution = def.restitution.unwrap_or(default.restitution);
            if !(restitution.is_finite() && (0.0..=1.0).contains(&restitution)) {
                self.push(
                    format!("{path}.restitution"),
                    format!("expected a restitution in [0, 1], got {restitution}"),
                );
            }
            out.insert(
                name.clone(),
                Material {
                    density,
                    friction,
                    restitution,
                },
            );
        }
        out
    }

    fn material_ref(
        &mut self,
        path: &str,
        name: &Option<String>,
        materials: &HashMap<String, Material>,
    ) -> Option<Material> {
        let name = name.as_ref()?;
        let found = materials.get(name).copied();
        if found.is_none() {
            let mut known: Vec<&str> = materials.keys().map(String::as_str).collect();
            known.sort_unstable();
            self.push(
                path,
                format!(
                    "unknown material {} (known: {})",
                    quoted(name),
                    list(&known)
                ),
            );
        }
        found
    }

    fn parts(
        &mut self,
        defs: &[PartDef],
        materials: &HashMap<String, Material>,
    ) -> HashMap<String, CheckedPart> {
        let mut out = HashMap::new();
        let mut first_index: HashMap<&str, usize> = HashMap::new();
        for (i, part) in defs.iter().enumerate() {
            let path = format!("parts[{i}]");
            if let Some(first) = first_index.get(part.name.as_str()) {
                self.push(
                    format!("{path}.name"),
                    format!(
                        "duplicate part name {} (also parts[{first}]): part names must be unique",
                        quoted(&part.name)
                    ),
                );
            }
            let shape = self.shape(&format!("{path}.primitive"), &part.primitive);
            let material =
                self.material_ref(&format!("{path}.material"), &part.material, materials);
            if first_index.contains_key(part.name.as_str()) {
                continue;
            }
            first_index.insert(part.name.as_str(), i);
            out.insert(part.name.clone(), CheckedPart { shape, material });
        }
        out
    }

    fn shape(&mut self, path: &str, primitive: &Primitive) -> Option<Shape> {
        let before = self.issues.len();
        let shape = match *primitive {
            Primitive::Mesh(ref mesh) => return self.mesh(path, mesh),
            Primitive::Plane => Shape::Plane,
            Primitive::Cube { size } => Shape::Cuboid {
                size: [
                    self.positive_length(&format!("{path}.size.x"), size.x),
                    self.positive_length(&format!("{path}.size.y"), size.y),
                    self.positive_length(&format!("{path}.size.z"), size.z),
                ],
            },
            Primitive::Cylinder { radius, height } => Shape::Cylinder {
                radius: self.positive_length(&format!("{path}.radius"), radius),
                height: self.positive_length(&format!("{path}.height"), height),
            },
            Primitive::Sphere { radius } => Shape::Sphere {
                radius: self.positive_length(&format!("{path}.radius"), radius),
            },
            Primitive::Capsule { radius, height } => {
                let r = self.positive_length(&format!("{path}.radius"), radius);
                let h = self.positive_length(&format!("{path}.height"), height);
                if self.issues.len() == before && height < 2.0 * radius {
                    self.push(
                        format!("{path}.height"),
                        format!(
                            "a capsule's height includes its two caps: expected at least 2 × radius = {} mm, got {height}",
                            2.0 * radius
                        ),
                    );
                }
                Shape::Capsule {
                    radius: r,
                    height: h,
                }
            }
        };
        (self.issues.len() == before).then_some(shape)
    }

    /// A mesh primitive made convex (`None` after an issue).
    fn mesh(&mut self, path: &str, mesh: &MeshDef) -> Option<Shape> {
        if let Some(file) = &mesh.file {
            self.push(
                format!("{path}.file"),
                format!(
                    "{}: a mesh file is read from the request's assets (a zip or tar archive of the files the document names), and this request has none",
                    quoted(file)
                ),
            );
            return None;
        }
        let vertices = mesh.vertices.as_deref().unwrap_or_default();
        if vertices.len() > MAX_MESH_VERTICES {
            self.push(
                format!("{path}.vertices"),
                format!(
                    "a mesh may have at most {MAX_MESH_VERTICES} vertices, got {}",
                    vertices.len()
                ),
            );
            return None;
        }
        let scale = match mesh.scale {
            Some(s) => {
                let before = self.issues.len();
                let s = self.components(
                    &format!("{path}.scale"),
                    s,
                    |v| v.is_finite() && v != 0.0 && v.abs() <= 1e6,
                    |v| format!("expected a finite, non-zero factor within ±1e6, got {v}"),
                );
                if self.issues.len() > before {
                    return None;
                }
                s
            }
            None => [1.0; 3],
        };
        let mut in_m = Vec::with_capacity(vertices.len());
        for (i, v) in vertices.iter().enumerate() {
            let v = [v[0] * scale[0], v[1] * scale[1], v[2] * scale[2]];
            if v.iter().any(|c| !(c.is_finite() && c.abs() <= MAX_COM_MM)) {
                self.push(
                    format!("{path}.vertices[{i}]"),
                    format!(
                        "expected coordinates within ±{MAX_COM_MM:e} mm, got [{}, {}, {}]",
                        v[0], v[1], v[2]
                    ),
                );
                return None;
            }
            in_m.push(v.map(|c| c / MM_PER_M));
        }
        if let Some(indices) = &mesh.indices {
            if indices.len() > MAX_MESH_TRIANGLES {
                self.push(
                    format!("{path}.indices"),
                    format!(
                        "a mesh may have at most {MAX_MESH_TRIANGLES} triangles, got {}",
                        indices.len()
                    ),
                );
                return None;
            }
            if let Some((t, bad)) = indices.iter().enumerate().find_map(|(t, tri)| {
                tri.iter()
                    .find(|&&i| i as usize >= vertices.len())
                    .map(|&i| (t, i))
            }) {
                self.push(
                    format!("{path}.indices[{t}]"),
                    format!(
                        "vertex index {bad} is out of range: the mesh has {} vertices",
                        vertices.len()
                    ),
                );
                return None;
            }
        }
        let mode = mesh.convex.unwrap_or(ConvexMode::Hull);
        match ConvexParts::new(&in_m, mesh.indices.as_deref(), mode) {
            Ok(parts) => Some(Shape::Convex(parts)),
            Err(message) => {
                self.push(path.to_string(), message);
                None
            }
        }
    }

    fn instances(
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
            let plane = shape == Shape::Plane;
            if plane && i == 0 && floating_base {
                self.push(
                    format!("{path}.part"),
                    format!(
                        "part {} is a plane (a half-space, a ground), which cannot be the floating base (the first instance); list the robot's base first",
                        quoted(&inst.part)
                    ),
                );
                continue;
            }
            let grounded = plane || (i == 0 && !floating_base);
            let mass = shape.volume() * material.density;
            if shape != Shape::Plane && inst.inertial.is_none() && !(mass.is_finite() && mass > 0.0)
            {
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
            });
        }
        out
    }

    fn joints(
        &mut self,
        defs: &[JointDef],
        instances: &[InstanceDef],
        planes: &[bool],
        floating_base: bool,
    ) -> Vec<Joint> {
        // Look names up in the document's instances, so that one bad instance does not
        // turn every joint that names it into a second, misleading error.
        let mut index: HashMap<&str, usize> = HashMap::new();
        for (i, inst) in instances.iter().enumerate() {
            index.entry(inst.name.as_str()).or_insert(i);
        }
        let mut names: HashMap<String, usize> = HashMap::new();
        let mut out = Vec::with_capacity(defs.len());
        // The spanning tree and the loops, from the joints whose instances resolve (the
        // references are reported below, joint by joint).
        let edges: Vec<Option<Edge>> = defs
            .iter()
            .map(|def| {
                Some(Edge {
                    parent: *index.get(def.parent.as_str())?,
                    child: *index.get(def.child.as_str())?,
                    actuated: def.actuated.unwrap_or(true),
                    observed: def.observed.unwrap_or(true),
                })
            })
            .collect();
        let roots: Vec<bool> = (0..instances.len())
            .map(|i| i == 0 || planes.get(i).copied().unwrap_or(false))
            .collect();
        let topology = crate::topology::choose(&edges, &roots);
        // Each joint on a loop's path, with the joint that closes that loop.
        let mut on_loop: Vec<Option<usize>> = vec![None; defs.len()];
        for (j, edge) in edges.iter().enumerate() {
            if let (Some(Role::Loop), Some(e)) = (topology.roles[j], edge) {
                on_loop[j].get_or_insert(j);
                for k in topology.path(e.parent, e.child) {
                    on_loop[k].get_or_insert(j);
                }
            }
        }

        for (j, def) in defs.iter().enumerate() {
            let path = format!("assembly.joints[{j}]");
            let before = self.issues.len();
            let parent = self.instance_ref(&format!("{path}.parent"), &def.parent, &index);
            let child = self.instance_ref(&format!("{path}.child"), &def.child, &index);
            let name = def.name.clone().unwrap_or_else(|| def.child.clone());
            match names.entry(name.clone()) {
                // A defaulted name clashes with a joint of the same child: that is a
                // child with two parents, which `topology` reports on `child`.
                Entry::Occupied(first)
                    if def.name.is_none()
                        && defs[*first.get()].child == def.child
                        && topology.roles[j].is_none() => {}
                Entry::Occupied(first) => self.push(
                    format!("{path}.name"),
                    format!(
                        "duplicate joint name {} (also assembly.joints[{}]); give one of them a \"name\"",
                        quoted(&name),
                        first.get()
                    ),
                ),
                Entry::Vacant(slot) => {
                    slot.insert(j);
                }
            }

            let anchor = match def.anchor {
                Some(a) => self
                    .vec3(&format!("{path}.anchor"), a)
                    .map(|c| c / MM_PER_M),
                None if def.kind == JointType::Fixed => [0.0; 3],
                None => {
                    self.push(
                        format!("{path}.anchor"),
                        format!(
                            "missing field `anchor`: a {} joint needs an anchor (world mm)",
                            def.kind.as_str()
                        ),
                    );
                    [0.0; 3]
                }
            };
            let axis = self.axis(&path, def);
            let document_limits = self.limits(&path, def);
            let initial = self.initial(&path, def, document_limits);
            let damping = self.non_negative(&format!("{path}.damping"), def.damping, "damping");
            let max_effort = def.max_effort.inspect(|&e| {
                if !(e.is_finite() && e > 0.0) {
                    self.push(
                        format!("{path}.max_effort"),
                        format!("expected a positive effort in N·m or N, got {e}"),
                    );
                }
            });
            let armature = self.dof_quantity(
                &path,
                def,
                ("armature", def.armature),
                "an armature >= 0 (kg·m² or kg)",
                "to add armature to",
            );
            let (stiffness, spring_rest) = self.spring(&path, def);
            let friction = self.dof_quantity(
                &path,
                def,
                ("friction", def.friction),
                "a friction >= 0 (N·m or N)",
                "to resist with friction",
            );
            let role = topology.roles[j];
            // A loop-closing joint is passive (a driven one is refused in `topology`).
            let actuated = def.actuated.unwrap_or(true) && role != Some(Role::Loop);
            let observed = def.observed.unwrap_or(true);
            if let (Some(closer), true) = (on_loop[j], initial != 0.0) {
                self.push(
                    format!("{path}.initial"),
                    format!(
                        "joint {} is on the kinematic loop that joint {} closes; an initial position would open the loop (loops start at the document's pose): remove \"initial\"",
                        quoted(def.name.as_deref().unwrap_or(&def.child)),
                        quoted(defs[closer].name.as_deref().unwrap_or(&defs[closer].child))
                    ),
                );
            }
            let (gear, reference) = self.gear_and_reference(&path, def, actuated);
            if !actuated && max_effort.is_some() {
                self.push(
                    format!("{path}.max_effort"),
                    "a passive joint (\"actuated\": false) takes no effort to clamp; \
                     remove max_effort or the actuated flag"
                        .to_string(),
                );
            }

            if let (Some(p), Some(c)) = (parent, child) {
                let roots = Roots {
                    planes,
                    floating_base,
                };
                self.topology(&path, def, (p, c), role, &topology, instances, roots);
            }
            if self.issues.len() == before {
                if let (Some(parent), Some(child)) = (parent, child) {
                    out.push(Joint {
                        name,
                        kind: def.kind,
                        parent,
                        child,
                        anchor,
                        axis,
                        limits: document_limits.map(|l| l.map(|v| v * limit_to_si(def.kind))),
                        document_limits,
                        damping: damping.unwrap_or(0.0),
                        max_effort,
                        actuated,
                        armature: armature.unwrap_or(0.0),
                        initial: initial * limit_to_si(def.kind),
                        stiffness,
                        spring_rest: spring_rest * limit_to_si(def.kind),
                        friction: friction.unwrap_or(0.0),
                        gear,
                        reference,
                        closes_loop: role == Some(Role::Loop),
                        observed,
                        on_loop: on_loop[j].is_some(),
                    });
                }
            }
        }
        out
    }

    fn instance_ref(
        &mut self,
        path: &str,
        name: &str,
        index: &HashMap<&str, usize>,
    ) -> Option<usize> {
        let found = index.get(name).copied();
        if found.is_none() {
            let mut known: Vec<&str> = index.keys().copied().collect();
            known.sort_unstable();
            self.push(
                path,
                format!(
                    "unknown instance {} (known: {})",
                    quoted(name),
                    list(&known)
                ),
            );
        }
        found
    }

    fn axis(&mut self, path: &str, def: &JointDef) -> [f64; 3] {
        let needs_axis = matches!(
            def.kind,
            JointType::Revolute | JointType::Prismatic | JointType::Cylindrical
        );
        let Some(axis) = def.axis else {
            if needs_axis {
                self.push(
                    format!("{path}.axis"),
                    format!(
                        "missing field `axis`: a {} joint needs an axis",
                        def.kind.as_str()
                    ),
                );
            }
            return [1.0, 0.0, 0.0];
        };
        // Scale by the largest component first, so that huge but finite components
        // do not overflow the norm.
        let a = axis.to_array();
        let scale = a.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let a = a.map(|c| c / scale);
        let norm = a.iter().map(|c| c * c).sum::<f64>().sqrt();
        if !(scale.is_finite() && scale > 1e-9 && norm.is_finite()) {
            self.push(
                format!("{path}.axis"),
                format!(
                    "expected a non-zero finite direction, got {{x: {}, y: {}, z: {}}}",
                    axis.x, axis.y, axis.z
                ),
            );
            return [1.0, 0.0, 0.0];
        }
        a.map(|c| c / norm)
    }

    /// The joint's `[min, max]` as written (deg or mm; an open side is infinite).
    fn limits(&mut self, path: &str, def: &JointDef) -> Option<[f64; 2]> {
        if def.min.is_none() && def.max.is_none() {
            return None;
        }
        if !def.kind.supports_limits() {
            let field = if def.min.is_some() { "min" } else { "max" };
            self.push(
                format!("{path}.{field}"),
                format!(
                    "a {} joint has no limits; min/max apply to revolute and prismatic joints only",
                    def.kind.as_str()
                ),
            );
            return None;
        }
        let unit = match def.kind {
            JointType::Prismatic => "mm",
            _ => "deg",
        };
        let mut bound = |field: &str, value: Option<f64>, default: f64| match value {
            Some(v) if v.is_finite() => v,
            Some(v) => {
                self.push(
                    format!("{path}.{field}"),
                    format!("expected a finite limit in {unit}, got {v}"),
                );
                default
            }
            None => default,
        };
        let min = bound("min", def.min, f64::NEG_INFINITY);
        let max = bound("max", def.max, f64::INFINITY);
        if min > max {
            self.push(
                format!("{path}.min"),
                format!("expected min <= max, got min {min} > max {max} ({unit})"),
            );
        }
        Some([min, max])
    }

    /// A joint's `initial` position (deg or mm, 0 when unset), which must lie within its
    /// limits: where the joint starts, positions being measured from the document's pose.
    fn initial(&mut self, path: &str, def: &JointDef, limits: Option<[f64; 2]>) -> f64 {
        let unit = if def.kind == JointType::Prismatic {
            "mm"
        } else {
            "deg"
        };
        let initial = match def.initial {
            None => 0.0,
            Some(_) if !def.kind.supports_limits() => {
                self.push(
                    format!("{path}.initial"),
                    format!(
                        "a {} joint has no initial position; initial applies to revolute and prismatic joints only",
                        def.kind.as_str()
                    ),
                );
                return 0.0;
            }
            Some(v) if !v.is_finite() => {
                self.push(
                    format!("{path}.initial"),
                    format!("expected a finite position in {unit}, got {v}"),
                );
                return 0.0;
            }
            Some(v) => v,
        };
        if let Some([min, max]) = limits.filter(|[min, max]| min <= max) {
            if !(min..=max).contains(&initial) {
                let field = if def.initial.is_some() {
                    "initial"
                } else if min > 0.0 {
                    "min"
                } else {
                    "max"
                };
                self.push(
                    format!("{path}.{field}"),
                    format!(
                        "the joint starts at {initial} {unit} (its `initial`; positions are measured from the document's pose), outside its limits [{min}, {max}]"
                    ),
                );
            }
        }
        initial
    }

    /// A joint's `gear` (finite, non-zero, on an actuated revolute or prismatic joint;
    /// default 1) and `reference` (finite, within ±1e9 deg or mm, on a revolute or
    /// prismatic joint; default 0).
    fn gear_and_reference(&mut self, path: &str, def: &JointDef, actuated: bool) -> (f64, f64) {
        let one_dof = matches!(def.kind, JointType::Revolute | JointType::Prismatic);
        let mut gear = 1.0;
        if let Some(g) = def.gear {
            if !(g.is_finite() && g != 0.0 && g.abs() <= 1e9) {
                self.push(
                    format!("{path}.gear"),
                    format!(
                        "expected a finite, non-zero gear within ±1e9, got {}",
                        shown(g)
                    ),
                );
            } else if !one_dof {
                self.push(
                    format!("{path}.gear"),
                    format!(
                        "a gear needs a revolute or prismatic joint, not a {} joint",
                        def.kind.as_str()
                    ),
                );
            } else if !actuated {
                self.push(
                    format!("{path}.gear"),
                    "a passive joint (\"actuated\": false) has no motor to gear; \
                     remove gear or the actuated flag"
                        .to_string(),
                );
            } else {
                gear = g;
            }
        }
        let mut reference = 0.0;
        if let Some(r) = def.reference {
            if !(r.is_finite() && r.abs() <= 1e9) {
                self.push(
                    format!("{path}.reference"),
                    format!(
                        "expected a finite position within ±1e9 (deg or mm), got {}",
                        shown(r)
                    ),
                );
            } else if !one_dof {
                self.push(
                    format!("{path}.reference"),
                    format!(
                        "a reference position needs a revolute or prismatic joint, not a {} joint",
                        def.kind.as_str()
                    ),
                );
            } else {
                reference = r;
            }
        }
        (gear, reference)
    }

    /// A joint's per-DOF quantity that must be finite and >= 0 (armature, friction), and that
    /// a fixed joint, with no DOF, cannot take above zero.
    fn dof_quantity(
        &mut self,
        path: &str,
        def: &JointDef,
        (field, value): (&str, Option<f64>),
        expected: &str,
        on_fixed: &str,
    ) -> Option<f64> {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v >= 0.0)) {
            self.push(
                format!("{path}.{field}"),
                format!("expected {expected}, got {v}"),
            );
        }
        if def.kind == JointType::Fixed && value.is_some_and(|v| v > 0.0) {
            self.push(
                format!("{path}.{field}"),
                format!("a fixed joint has no DOF {on_fixed}"),
            );
        }
        value
    }

    /// A joint's passive spring: its stiffness (SI) and rest position (deg or mm).
    fn spring(&mut self, path: &str, def: &JointDef) -> (f64, f64) {
        let unit = if def.kind == JointType::Prismatic {
            ("N/m", "mm")
        } else {
            ("N·m/rad", "deg")
        };
        let stiffness = match def.stiffness {
            None => 0.0,
            Some(_) if !def.kind.supports_limits() => {
                self.push(
                    format!("{path}.stiffness"),
                    format!(
                        "a {} joint takes no spring; stiffness applies to revolute and prismatic joints only",
                        def.kind.as_str()
                    ),
                );
                return (0.0, 0.0);
            }
            Some(k) if !(k.is_finite() && k >= 0.0) => {
                self.push(
                    format!("{path}.stiffness"),
                    format!("expected a stiffness >= 0 in {}, got {k}", unit.0),
                );
                return (0.0, 0.0);
            }
            Some(k) => k,
        };
        let rest = match def.spring_rest {
            None => 0.0,
            Some(_) if def.stiffness.is_none() => {
                self.push(
                    format!("{path}.spring_rest"),
                    "a spring rest position needs a `stiffness`".to_string(),
                );
                0.0
            }
            Some(r) if !r.is_finite() => {
                self.push(
                    format!("{path}.spring_rest"),
                    format!("expected a finite position in {}, got {r}", unit.1),
                );
                0.0
            }
            Some(r) => r,
        };
        (stiffness, rest)
    }

    /// An instance's `inertial`, checked and in SI (`None` after an issue).
    fn inertial(&mut self, path: &str, def: &InertialDef, shape: &Shape) -> Option<Inertial> {
        let before = self.issues.len();
        if !(def.mass.is_finite() && def.mass > 0.0 && def.mass <= MAX_MASS_KG) {
            self.push(
                format!("{path}.mass"),
                format!(
                    "expected a mass in (0, {MAX_MASS_KG:e}] kg, got {}",
                    def.mass
                ),
            );
        }
        let center_of_mass = match def.center_of_mass {
            Some(c) => self
                .components(
                    &format!("{path}.center_of_mass"),
                    c,
                    |v| v.is_finite() && v.abs() <= MAX_COM_MM,
                    |v| format!("expected a coordinate within ±{MAX_COM_MM:e} mm, got {v}"),
                )
                .map(|v| v / MM_PER_M),
            None => shape.centroid(),
        };
        let inertia = def.inertia.map(|i| {
            let m = [[i.xx, i.xy, i.xz], [i.xy, i.yy, i.yz], [i.xz, i.yz, i.zz]];
            if m.iter().flatten().any(|v| !v.is_finite()) {
                self.push(
                    format!("{path}.inertia"),
                    "expected finite entries (kg·m²)".to_string(),
                );
            } else if let Some(problem) = crate::model::inertia_problem(&m) {
                self.push(
                    format!("{path}.inertia"),
                    format!(
                        "[[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]] kg·m² is {problem}",
                        m[0][0],
                        m[0][1],
                        m[0][2],
                        m[1][0],
                        m[1][1],
                        m[1][2],
                        m[2][0],
                        m[2][1],
                        m[2][2]
                    ),
                );
            }
            m
        });
        (self.issues.len() == before).then_some(Inertial {
            mass: def.mass,
            center_of_mass,
            inertia,
        })
    }

    fn non_negative(&mut self, path: &str, value: Option<f64>, what: &str) -> Option<f64> {
        let v = value?;
        if !(v.is_finite() && v >= 0.0) {
            self.push(path, format!("expected a {what} >= 0, got {v}"));
        }
        Some(v)
    }

    /// Reports a joint the tree and the loops could not place, and the rules of loops:
    /// a loop-closing joint is not explicitly driven, an unobserved joint closes a loop.
    #[allow(clippy::too_many_arguments)]
    fn topology(
        &mut self,
        path: &str,
        def: &JointDef,
        (parent, child): (usize, usize),
        role: Option<Role>,
        topology: &Topology,
        instances: &[InstanceDef],
        roots: Roots<'_>,
    ) {
        match role {
            Some(Role::Tree) => return,
            Some(Role::Loop) => {
                if def.actuated == Some(true) {
                    self.push(
                        format!("{path}.actuated"),
                        format!(
                            "joint {} -> {} closes a kinematic loop, and a loop-closing joint is passive; remove \"actuated\": true, or mark another joint of the loop \"actuated\": false so that this one joins the tree (the tree takes actuated joints first)",
                            quoted(&def.parent),
                            quoted(&def.child)
                        ),
                    );
                }
                return;
            }
            None => {}
        }
        if parent == child {
            self.push(
                format!("{path}.child"),
                format!(
                    "joint connects instance {} to itself; parent and child must differ",
                    quoted(&def.child)
                ),
            );
            return;
        }
        if def.observed == Some(false) {
            self.push(
                format!("{path}.observed"),
                format!(
                    "only a joint that closes a kinematic loop may be unobserved, and {} and {} are not otherwise joined; remove \"observed\": false",
                    quoted(&def.parent),
                    quoted(&def.child)
                ),
            );
            return;
        }
        if child == 0 {
            let what = if roots.floating_base {
                "the floating base (the first instance), the root of the tree,"
            } else {
                "grounded (the first instance)"
            };
            self.push(
                format!("{path}.child"),
                format!(
                    "instance {} is {what} and cannot be a joint child; swap parent and child",
                    quoted(&def.child)
                ),
            );
            return;
        }
        if roots.planes.get(child).copied().unwrap_or(false) {
            self.push(
                format!("{path}.child"),
                format!(
                    "instance {} is a plane, a ground fixed to the world, and cannot be a joint child; swap parent and child",
                    quoted(&def.child)
                ),
            );
            return;
        }
        if let Some((existing, _)) = topology.parent[child] {
            self.push(
                format!("{path}.child"),
                format!(
                    "instance {} already has parent {}; a second parent is only for a joint that closes a kinematic loop, and {} is not otherwise joined to {}",
                    quoted(&def.child),
                    quoted(&instances[existing].name),
                    quoted(&def.parent),
                    quoted(&def.child)
                ),
            );
        }
    }
}

/// What roots the kinematic trees: which instances are planes (fixed wherever they are
/// listed), and whether the first instance floats.
#[derive(Clone, Copy)]
struct Roots<'a> {
    planes: &'a [bool],
    floating_base: bool,
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
