//! Materials and parts: each part's shape (primitives and meshes, in metres), its material
//! and its inertial, checked.

use std::collections::{BTreeMap, HashMap};

use crate::document::{
    ConvexMode, FrictionCone, InertialDef, MaterialDef, MeshDef, PartDef, Primitive, SoftContactDef,
};
use crate::error::quoted;
use crate::mesh::{ConvexParts, MAX_MESH_TRIANGLES, MAX_MESH_VERTICES};
use crate::model::{Inertial, Material, Shape, SoftContact, MM_PER_M};

use super::{list, CheckedPart, Validator, MAX_COM_MM, MAX_MASS_KG};

impl Validator {
    pub(super) fn materials(
        &mut self,
        defs: &BTreeMap<String, MaterialDef>,
    ) -> HashMap<String, Material> {
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
            let soft_contact = def
                .soft_contact
                .as_ref()
                .map(|soft| self.soft_contact(&format!("{path}.soft_contact"), soft));
            out.insert(
                name.clone(),
                Material {
                    density,
                    friction,
                    restitution,
                    soft_contact,
                },
            );
        }
        out
    }

    /// A material's compliant contact, with MuJoCo's defaults and ranges: `solref` both
    /// positive (time constant, damping ratio) or both negative (stiffness, damping);
    /// impedances in (0, 1), a width >= 0, a midpoint in (0, 1), a power >= 1.
    fn soft_contact(&mut self, path: &str, def: &SoftContactDef) -> SoftContact {
        let default = SoftContact::default();
        let solref = self.solref(path, def.solref.unwrap_or(default.solref));
        let solimp = self.solimp(path, def.solimp.unwrap_or(default.solimp), "mm");
        let solmix = def.solmix.unwrap_or(default.solmix);
        if !(solmix.is_finite() && solmix >= 0.0) {
            self.push(
                format!("{path}.solmix"),
                format!("expected a weight >= 0, got {solmix}"),
            );
        }
        let mut length = |name: &str, value: Option<f64>| {
            let value = value.unwrap_or(0.0);
            if !(value.is_finite() && value >= 0.0) {
                self.push(
                    format!("{path}.{name}"),
                    format!("expected a distance in mm >= 0, got {value}"),
                );
            }
            value
        };
        let margin = length("margin", def.margin);
        let gap = length("gap", def.gap);
        let torsional_friction = length(
            "torsional_friction",
            def.torsional_friction.or(Some(default.torsional_friction)),
        );
        let rolling_friction = length(
            "rolling_friction",
            def.rolling_friction.or(Some(default.rolling_friction)),
        );
        let condim = def.condim.unwrap_or(default.condim);
        if ![1, 3, 4, 6].contains(&condim) {
            self.push(
                format!("{path}.condim"),
                format!("expected 1 (frictionless), 3 (sliding), 4 (and torsional) or 6 (and rolling friction), got {condim}"),
            );
        }
        let impratio = def.impratio.unwrap_or(default.impratio);
        if !(impratio.is_finite() && impratio > 0.0) {
            self.push(
                format!("{path}.impratio"),
                format!("expected a ratio > 0, got {impratio}"),
            );
        }
        SoftContact {
            solref,
            solimp,
            solmix,
            priority: def.priority.unwrap_or(default.priority),
            margin,
            gap,
            pyramidal: def.cone.unwrap_or_default() == FrictionCone::Pyramidal,
            impratio,
            condim,
            torsional_friction,
            rolling_friction,
        }
    }

    /// MuJoCo's `solref`: both positive (time constant, damping ratio) or both negative
    /// (stiffness, damping).
    pub(super) fn solref(&mut self, path: &str, solref: [f64; 2]) -> [f64; 2] {
        let standard = solref.iter().all(|v| v.is_finite() && *v > 0.0);
        let direct = solref.iter().all(|v| v.is_finite() && *v <= 0.0) && solref[0] < 0.0;
        if !(standard || direct) {
            self.push(
                format!("{path}.solref"),
                format!("expected [time constant s > 0, damping ratio > 0] or [-stiffness < 0, -damping <= 0], got {solref:?}"),
            );
        }
        solref
    }

    /// MuJoCo's `solimp`: impedances in (0, 1), a width >= 0 (in `unit`), a midpoint in
    /// (0, 1), a power >= 1.
    pub(super) fn solimp(&mut self, path: &str, solimp: [f64; 5], unit: &str) -> [f64; 5] {
        let [dmin, dmax, width, midpoint, power] = solimp;
        let impedance = |d: f64| d.is_finite() && d > 0.0 && d < 1.0;
        if !(impedance(dmin)
            && impedance(dmax)
            && width.is_finite()
            && width >= 0.0
            && impedance(midpoint)
            && power.is_finite()
            && power >= 1.0)
        {
            self.push(
                format!("{path}.solimp"),
                format!("expected [dmin, dmax in (0, 1), width {unit} >= 0, midpoint in (0, 1), power >= 1], got {solimp:?}"),
            );
        }
        solimp
    }

    pub(super) fn material_ref(
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

    pub(super) fn parts(
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

    pub(super) fn shape(&mut self, path: &str, primitive: &Primitive) -> Option<Shape> {
        let before = self.issues.len();
        let shape = match *primitive {
            Primitive::Mesh(ref mesh) => return self.mesh(path, mesh),
            Primitive::Plane => Shape::Plane,
            Primitive::Heightfield(ref def) => {
                let field = crate::heightfield::heightfield(path, def, &mut self.issues)?;
                Shape::Heightfield(std::sync::Arc::new(field))
            }
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
            Primitive::Ellipsoid { radii } => {
                let radii = [("x", radii.x), ("y", radii.y), ("z", radii.z)]
                    .map(|(axis, r)| self.positive_length(&format!("{path}.radii.{axis}"), r));
                if self.issues.len() != before {
                    return None;
                }
                match crate::ConvexParts::ellipsoid(radii) {
                    Ok(hull) => Shape::Ellipsoid { radii, hull },
                    Err(reason) => {
                        self.push(format!("{path}.radii"), reason);
                        return None;
                    }
                }
            }
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
    pub(super) fn mesh(&mut self, path: &str, mesh: &MeshDef) -> Option<Shape> {
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
        let in_m = self.mesh_vertices(path, vertices, scale)?;
        if let Some(indices) = &mesh.indices {
            self.mesh_indices(path, indices, vertices.len())?;
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

    /// A mesh's vertices scaled and in m, each coordinate finite and in range.
    fn mesh_vertices(
        &mut self,
        path: &str,
        vertices: &[[f64; 3]],
        scale: [f64; 3],
    ) -> Option<Vec<[f64; 3]>> {
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
        Some(in_m)
    }

    /// A mesh's triangles: not too many, each index one of its `vertices`.
    fn mesh_indices(&mut self, path: &str, indices: &[[u32; 3]], vertices: usize) -> Option<()> {
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
                .find(|&&i| i as usize >= vertices)
                .map(|&i| (t, i))
        }) {
            self.push(
                format!("{path}.indices[{t}]"),
                format!("vertex index {bad} is out of range: the mesh has {vertices} vertices"),
            );
            return None;
        }
        Some(())
    }

    /// An instance's `inertial`, checked and in SI (`None` after an issue).
    pub(super) fn inertial(
        &mut self,
        path: &str,
        def: &InertialDef,
        shape: &Shape,
    ) -> Option<Inertial> {
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
}
