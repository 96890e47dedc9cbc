//! URDF links: a link's collisions as instances (the first is the link's, the others welded
//! to it), its `<inertial>` and PyBullet `<contact>`, and massless links as helpers.

use glam::{DMat3, DVec3};
use gymfleet_assembly::{
    CollisionDef, InertialDef, InstanceDef, JointDef, JointType, MaterialDef, MeshDef, PartDef,
    Primitive, Vec3,
};
use roxmltree::Node;

use crate::frame::{euler_xyz_degrees, inertial_def, vec3, Frame};
use crate::xml::{elements, XmlReader};
use crate::Result;

use super::{child, Converter, HELPER_MASS, HELPER_RADIUS, MM, PLACEHOLDER_MASS};

impl<'a, 'i> Converter<'a, 'i> {
    /// A link's instances; returns the link's own (its first collision's, or a helper).
    pub(super) fn link(&mut self, link: Node<'a, 'i>, frame: &Frame) -> Result<String> {
        let link_name = link.attribute("name").unwrap_or("link").to_string();
        let inertial = child(link, "inertial");
        let mass = match inertial {
            Some(i) => Some(self.link_mass(i)?),
            None => None,
        };
        self.link_children(link)?;
        let massless = mass == Some(0.0);
        if massless {
            self.warn(link, "a link of mass 0 (a frame) weighs 1 mg".into());
        }
        let mut main: Option<String> = None;
        let first_instance = self.instances.len();
        for collision in elements(link).filter(|n| n.tag_name().name() == "collision") {
            // With given mass properties (or none at all) the shapes weigh 1 mg each and
            // the link's instance carries the mass.
            let weight = (mass.is_some()).then_some(HELPER_MASS);
            let name = self.collision(collision, frame, &link_name, weight, main.is_none())?;
            match &main {
                None => main = Some(name),
                Some(m) => self.weld(m, &name),
            }
        }
        // The link's shapes are instances `first_instance..shapes_end`.
        let shapes_end = self.instances.len();
        let main = match main {
            Some(m) => m,
            None => {
                if mass.is_none() {
                    self.warn(
                        link,
                        "a link without <collision> or <inertial> weighs 1 mg".into(),
                    );
                }
                self.helper(&link_name, frame)
            }
        };
        if let Some(contact) = child(link, "contact") {
            self.contact(contact, &link_name, first_instance..shapes_end)?;
        }
        match (inertial, mass) {
            (Some(i), Some(m)) if m > 0.0 => self.inertial(i, m, frame, &main)?,
            (None, _) if shapes_end > first_instance => self.warn(
                link,
                "no <inertial>: the mass comes from the shapes at 1000 kg/m³".into(),
            ),
            _ => {}
        }
        Ok(main)
    }

    /// An `<inertial>`'s `<mass value>`: given, and not negative.
    fn link_mass(&mut self, inertial: Node<'a, 'i>) -> Result<f64> {
        let mass_node = child(inertial, "mass")
            .ok_or_else(|| self.unsupported(inertial, "no <mass value=…>".into()))?;
        let m = self
            .number(mass_node, "value")?
            .ok_or_else(|| self.bad(mass_node, "value", "missing".into()))?;
        if m < 0.0 {
            return Err(self.bad(
                mass_node,
                "value",
                format!("expected a mass ≥ 0 kg, got {m}"),
            ));
        }
        Ok(m)
    }

    /// A `<link>`'s children: `<visual>` and `<self_filter>` ignored with a warning, any
    /// other than `<inertial>`, `<collision>` and `<contact>` refused.
    fn link_children(&mut self, link: Node<'a, 'i>) -> Result<()> {
        for node in elements(link) {
            match node.tag_name().name() {
                "visual" => self.warn(
                    node,
                    "ignored (only <collision> shapes are simulated)".into(),
                ),
                "self_filter" => self.warn(
                    node,
                    "ignored (a ROS sensor-filtering setting, no effect on the dynamics)".into(),
                ),
                "inertial" | "collision" | "contact" => {}
                other => {
                    return Err(
                        self.unsupported(node, format!("<{other}> in <link> is not supported"))
                    )
                }
            }
        }
        Ok(())
    }

    /// PyBullet's `<contact>` extension: `lateral_friction` and `restitution` become the
    /// material of the link's shapes (the instances `shapes`); its solver tuning
    /// (stiffness, damping, rolling and spinning friction) is ignored with a warning.
    pub(super) fn contact(
        &mut self,
        node: Node<'a, 'i>,
        link_name: &str,
        shapes: std::ops::Range<usize>,
    ) -> Result<()> {
        let mut material = MaterialDef::default();
        for item in elements(node) {
            let key = match item.tag_name().name() {
                "lateral_friction" => &mut material.friction,
                "restitution" => &mut material.restitution,
                other => {
                    self.warn(
                        item,
                        format!("<{other}> ignored (gymfleet's contact model)"),
                    );
                    continue;
                }
            };
            let value = self
                .number(item, "value")?
                .ok_or_else(|| self.bad(item, "value", "missing".into()))?;
            *key = Some(value);
        }
        if material.friction.is_none() && material.restitution.is_none() {
            return Ok(());
        }
        let name = format!("{link_name}_contact");
        for instance in &mut self.instances[shapes] {
            instance.material = Some(name.clone());
        }
        self.materials.insert(name, material);
        Ok(())
    }

    /// A link's `<inertial>` on its instance: mass, centre of mass and inertia.
    pub(super) fn inertial(
        &mut self,
        node: Node<'a, 'i>,
        mass: f64,
        link: &Frame,
        instance: &str,
    ) -> Result<()> {
        let at = link.then(&self.origin(node)?);
        let inertia = child(node, "inertia")
            .ok_or_else(|| self.unsupported(node, "no <inertia ixx=… …>".into()))?;
        let mut entry = |name: &str| -> Result<f64> {
            self.number(inertia, name)?
                .ok_or_else(|| self.bad(inertia, name, "missing".into()))
        };
        let [xx, yy, zz, xy, xz, yz] = ["ixx", "iyy", "izz", "ixy", "ixz", "iyz"].map(&mut entry);
        let (xx, yy, zz, xy, xz, yz) = (xx?, yy?, zz?, xy?, xz?, yz?);
        if xx == 0.0 && yy == 0.0 && zz == 0.0 {
            return Err(self.unsupported(
                inertia,
                format!(
                    "a link of {mass} kg with zero inertia: every principal moment must be > 0"
                ),
            ));
        }
        if let Some(problem) =
            gymfleet_assembly::inertia_problem(&[[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        {
            // Placeholder inertias on near-massless frame links (1e-6 everywhere, off
            // diagonals included: Unitree's B1, IIT's HyQ) are not the link's physics: it
            // keeps its mass, with its shape's inertia for that mass.
            if mass <= PLACEHOLDER_MASS {
                self.warn(
                    inertia,
                    format!(
                        "the inertia of a link of {mass} kg is {problem}; a link this light keeps its mass with its shape's inertia"
                    ),
                );
                let index = self.index_of(instance);
                self.instances[index].inertial = Some(InertialDef::mass(mass));
                return Ok(());
            }
            return Err(self.unsupported(
                inertia,
                format!("the inertia of a link of {mass} kg is {problem}"),
            ));
        }
        let tensor = DMat3::from_cols_array(&[xx, xy, xz, xy, yy, yz, xz, yz, zz]);
        let index = self.index_of(instance);
        self.instances[index].inertial =
            Some(inertial_def(mass, &at, tensor, &self.frames[instance], MM));
        Ok(())
    }

    /// A helper instance: a small sphere of `HELPER_MASS` that collides with nothing.
    pub(super) fn helper(&mut self, wanted: &str, at: &Frame) -> String {
        let name = self.unique(wanted);
        self.parts.push(PartDef {
            name: name.clone(),
            primitive: Primitive::Sphere {
                radius: HELPER_RADIUS,
            },
            material: None,
        });
        self.instances.push(InstanceDef {
            position: Some(vec3(at.translation * MM)),
            rotation: Some(euler_xyz_degrees(at.rotation).into()),
            collision: Some(CollisionDef {
                group: Some(0),
                mask: Some(0),
            }),
            inertial: Some(InertialDef::mass(HELPER_MASS)),
            ..InstanceDef::new(&name, &name)
        });
        self.frames.insert(name.clone(), *at);
        name
    }

    pub(super) fn weld(&mut self, parent: &str, child: &str) {
        let name = self.unique(&format!("{child}_weld"));
        self.joints.push(JointDef {
            name: Some(name),
            ..JointDef::new(JointType::Fixed, parent, child)
        });
    }

    /// A collision's `<geometry>` element as a primitive, with the point of it the URDF
    /// origin is at (our primitives start at a corner or their base).
    fn shape(&self, shape: Node<'a, 'i>) -> Result<(Primitive, DVec3)> {
        let positive = |c: &Self, name: &str| -> Result<f64> {
            match c.number(shape, name)? {
                Some(v) if v > 0.0 => Ok(v),
                Some(v) => Err(c.bad(shape, name, format!("expected a positive length, got {v}"))),
                None => Err(c.bad(shape, name, "missing".into())),
            }
        };
        // Our primitives start at a corner (box) or their base (cylinder, capsule).
        Ok(match shape.tag_name().name() {
            "box" => {
                let s = self
                    .numbers::<3>(shape, "size")?
                    .ok_or_else(|| self.bad(shape, "size", "missing".into()))?;
                if let Some(v) = s.iter().find(|v| **v <= 0.0) {
                    return Err(self.bad(
                        shape,
                        "size",
                        format!("expected positive lengths, got {v}"),
                    ));
                }
                (
                    Primitive::Cube {
                        size: vec3(DVec3::from_array(s) * MM),
                    },
                    DVec3::from_array(s) / 2.0,
                )
            }
            "cylinder" => {
                let (r, l) = (positive(self, "radius")?, positive(self, "length")?);
                (
                    Primitive::Cylinder {
                        radius: r * MM,
                        height: l * MM,
                    },
                    DVec3::new(0.0, 0.0, l / 2.0),
                )
            }
            "capsule" => {
                let (r, l) = (positive(self, "radius")?, positive(self, "length")?);
                (
                    Primitive::Capsule {
                        radius: r * MM,
                        height: (l + 2.0 * r) * MM,
                    },
                    DVec3::new(0.0, 0.0, l / 2.0 + r),
                )
            }
            "sphere" => (
                Primitive::Sphere {
                    radius: positive(self, "radius")? * MM,
                },
                DVec3::ZERO,
            ),
            "mesh" => {
                let file = self.required(shape, "filename")?;
                let s = self.numbers::<3>(shape, "scale")?.unwrap_or([1.0; 3]);
                if let Some(v) = s.iter().find(|v| **v == 0.0) {
                    return Err(self.bad(
                        shape,
                        "scale",
                        format!("expected non-zero factors, got {v}"),
                    ));
                }
                (
                    Primitive::Mesh(MeshDef {
                        file: Some(file.to_string()),
                        convex: Some(gymfleet_assembly::ConvexMode::Hull),
                        scale: Some(vec3(DVec3::from_array(s) * MM)),
                        ..MeshDef::default()
                    }),
                    DVec3::ZERO,
                )
            }
            other => {
                return Err(self.unsupported(shape, format!("<{other}> geometry is not supported")))
            }
        })
    }

    /// One `<collision>` as an instance, placed in the world.
    pub(super) fn collision(
        &mut self,
        node: Node<'a, 'i>,
        link: &Frame,
        link_name: &str,
        weight: Option<f64>,
        first: bool,
    ) -> Result<String> {
        let at = link.then(&self.origin(node)?);
        let geometry = child(node, "geometry")
            .ok_or_else(|| self.unsupported(node, "no <geometry>".into()))?;
        let shape = elements(geometry)
            .next()
            .ok_or_else(|| self.unsupported(geometry, "empty <geometry>".into()))?;
        let (primitive, corner) = self.shape(shape)?;
        let origin_m = at.point(-corner);
        let origin = origin_m * MM;
        let rotation = euler_xyz_degrees(at.rotation);
        let wanted = match (first, node.attribute("name")) {
            (true, _) => link_name.to_string(),
            (false, Some(n)) => n.to_string(),
            (false, None) => format!("{link_name}_collision"),
        };
        let name = self.unique(&wanted);
        self.parts.push(PartDef {
            name: name.clone(),
            primitive,
            material: None,
        });
        self.instances.push(InstanceDef {
            position: Some(vec3(origin)),
            rotation: Some(Vec3::from(rotation)),
            inertial: weight.map(InertialDef::mass),
            ..InstanceDef::new(&name, &name)
        });
        self.frames.insert(
            name.clone(),
            Frame {
                translation: origin_m,
                rotation: at.rotation,
            },
        );
        Ok(name)
    }
}
