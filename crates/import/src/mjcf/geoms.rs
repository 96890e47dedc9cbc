//! One `<geom>` as an instance with its own part: the primitive (or `fromto`), its frame,
//! its mass (volume × density, or `mass`), friction and collision bits.

use super::*;

/// A geom's primitive, the corner or base it starts at in the geom's frame (m), and for a
/// heightfield its x and y half-extents and the depth of its base (m).
type GeomShape = (Primitive, DVec3, Option<([f64; 2], f64)>);

/// MuJoCo's default sliding friction coefficient.
const MUJOCO_FRICTION: f64 = 1.0;

impl<'a, 'i> Converter<'a, 'i> {
    /// One geom as an instance; `None` for a plane that collides with nothing (dropped).
    /// `given_mass`: the body's mass comes from `<inertial>`; the geom then weighs this.
    /// `static_body`: the geom's body is the world or fixed to it (planes belong there).
    pub(super) fn geom(
        &mut self,
        node: Node<'a, 'i>,
        body: &Frame,
        class: Option<&str>,
        body_name: &str,
        given_mass: Option<f64>,
        static_body: bool,
    ) -> Result<Option<String>> {
        let kind = self.attr(node, class, "type").unwrap_or("sphere");
        let contype = self.int(node, class, "contype", 1)?;
        let conaffinity = self.int(node, class, "conaffinity", 1)?;
        let size = self.numbers(node, class, "size")?.unwrap_or_default();
        let fromto = self.exactly::<6>(node, class, "fromto")?;
        let (local, half_length) = self.geom_frame(node, class, kind, fromto)?;
        let world = body.then(&local);
        if kind != "mesh" && self.attr(node, class, "mesh").is_some() {
            return Err(self.unsupported(
                node,
                format!("a {kind} fitted to a mesh is not supported yet"),
            ));
        }
        // A geom with no mass and no collisions only shows (MuJoCo's visual meshes).
        if contype == 0 && conaffinity == 0 && self.number(node, class, "mass")? == Some(0.0) {
            self.warn(
                node,
                "a massless geom that collides with nothing: dropped".into(),
            );
            return Ok(None);
        }
        let Some((primitive, corner, terrain_base)) = self.geom_shape(
            node,
            class,
            kind,
            &size,
            half_length,
            static_body,
            (contype, conaffinity),
        )?
        else {
            return Ok(None);
        };
        // Our primitives start at a corner (box) or their base (cylinder, capsule).
        let origin_m = world.point(-corner);
        let origin = origin_m * MM;
        let rotation = euler_xyz_degrees(world.rotation);
        let name = self.geom_name(node, body_name);
        self.geom_contact_model(node, class)?;
        // MuJoCo's default sliding friction is 1 (gymfleet's own is 0.5).
        let friction = self
            .numbers(node, class, "friction")?
            .and_then(|f| f.first().copied())
            .or(Some(MUJOCO_FRICTION));
        let mut material = MaterialDef {
            friction,
            soft_contact: Some(self.soft_contact(node, class)?),
            ..MaterialDef::default()
        };
        let mut instance = InstanceDef {
            position: Some(vec3(origin)),
            rotation: Some(Vec3::from(rotation)),
            collision: ((contype, conaffinity) != (1, 1)).then_some(CollisionDef {
                group: Some(contype),
                mask: Some(conaffinity),
            }),
            ..InstanceDef::new(&name, &name)
        };
        self.geom_mass(node, class, &name, given_mass, &mut instance, &mut material)?;
        let frame = Frame {
            translation: origin_m,
            rotation: world.rotation,
        };
        self.record_geom(&name, primitive, instance, material, frame);
        if let Some((half, base)) = terrain_base {
            self.hfield_base(&name, &world, half, base);
        }
        Ok(Some(name))
    }

    /// What the contact model does with a geom's `fluidshape` (refused; `condim` is read
    /// with the compliant contact, `soft_contact`).
    fn geom_contact_model(&mut self, node: Node<'a, 'i>, class: Option<&str>) -> Result<()> {
        if let Some(shape) = self
            .attr(node, class, "fluidshape")
            .filter(|v| *v != "none")
        {
            return Err(self.unsupported(
                node,
                format!("fluidshape=\"{shape}\" (MuJoCo's ellipsoid fluid model) is not supported yet; the inertia-box model of <option density viscosity> is"),
            ));
        }
        Ok(())
    }

    /// Records a geom as a part, an instance of it at `frame`, and its material: every
    /// geom's contacts are compliant, as MuJoCo's are.
    fn record_geom(
        &mut self,
        name: &str,
        primitive: Primitive,
        mut instance: InstanceDef,
        material: MaterialDef,
        frame: Frame,
    ) {
        instance.material = Some(name.to_string());
        self.frames.insert(name.to_string(), frame);
        self.parts.push(PartDef {
            name: name.to_string(),
            primitive,
            material: None,
        });
        self.materials.insert(name.to_string(), material);
        self.instances.push(instance);
    }

    /// A geom's frame in its body and, with `fromto`, its half-length; `fromto` gives the
    /// centre and the z axis.
    fn geom_frame(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        kind: &str,
        fromto: Option<[f64; 6]>,
    ) -> Result<(Frame, Option<f64>)> {
        Ok(match fromto {
            Some(f) if matches!(kind, "capsule" | "cylinder") => {
                let (a, b) = (DVec3::new(f[0], f[1], f[2]), DVec3::new(f[3], f[4], f[5]));
                let axis = b - a;
                if axis.length() < 1e-12 {
                    return Err(self.bad(node, "fromto", "the two ends are the same point".into()));
                }
                (
                    Frame {
                        translation: (a + b) / 2.0,
                        rotation: z_onto(axis.normalize()),
                    },
                    Some(axis.length() / 2.0),
                )
            }
            Some(_) => {
                return Err(
                    self.unsupported(node, format!("fromto on a {kind} is not supported yet"))
                )
            }
            None => (self.local_frame(node, class)?, None),
        })
    }

    /// A geom's primitive by its shape, the corner or base our primitive starts at (in the
    /// geom's frame, m) and, for a heightfield, its base; `None` for a plane that collides
    /// with nothing (dropped).
    #[allow(clippy::too_many_arguments)]
    fn geom_shape(
        &mut self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        kind: &str,
        size: &[f64],
        half_length: Option<f64>,
        static_body: bool,
        (contype, conaffinity): (u32, u32),
    ) -> Result<Option<GeomShape>> {
        // A heightfield's base: its x and y half-extents and its depth, m.
        let mut terrain_base = None;
        let (primitive, corner) = match kind {
            "plane" => {
                if contype == 0 && conaffinity == 0 {
                    self.warn(node, "a plane that collides with nothing: dropped".into());
                    return Ok(None);
                }
                if !static_body {
                    return Err(self.unsupported(
                        node,
                        "a plane (a half-space) belongs to the world or to a body without joints"
                            .into(),
                    ));
                }
                (Primitive::Plane, DVec3::ZERO)
            }
            "sphere" | "ellipsoid" | "capsule" | "cylinder" | "box" => {
                self.solid(node, kind, size, half_length)?
            }
            "mesh" => (self.mesh_primitive(node, class)?, DVec3::ZERO),
            "hfield" => {
                if !static_body {
                    return Err(self.unsupported(
                        node,
                        "a heightfield (terrain) belongs to the world or to a body without joints"
                            .into(),
                    ));
                }
                let (primitive, base) = self.hfield_primitive(node, class)?;
                if let Primitive::Heightfield(ref h) = primitive {
                    terrain_base = Some(([h.size.x / MM, h.size.y / MM], base));
                }
                (primitive, DVec3::ZERO)
            }
            "sdf" => {
                return Err(self.unsupported(node, format!("{kind} geoms are not converted yet")))
            }
            other => {
                return Err(self.unsupported(node, format!("{other} geoms are not supported yet")))
            }
        };
        Ok(Some((primitive, corner, terrain_base)))
    }

    /// A solid's primitive (sphere, ellipsoid, capsule, cylinder, box) from `size` (or,
    /// for a capsule or cylinder, `fromto`'s half-length), and the corner or base our
    /// primitive starts at in the geom's frame (m).
    fn solid(
        &self,
        node: Node<'a, 'i>,
        kind: &str,
        size: &[f64],
        half_length: Option<f64>,
    ) -> Result<(Primitive, DVec3)> {
        let size_at = |k: usize, what: &str| self.size_at(node, kind, size, k, what);
        Ok(match kind {
            "sphere" => {
                let r = size_at(0, "radius")?;
                (Primitive::Sphere { radius: r * MM }, DVec3::ZERO)
            }
            "ellipsoid" => {
                let r = DVec3::new(
                    size_at(0, "x semi-axis")?,
                    size_at(1, "y semi-axis")?,
                    size_at(2, "z semi-axis")?,
                );
                (
                    Primitive::Ellipsoid {
                        radii: vec3(r * MM),
                    },
                    DVec3::ZERO,
                )
            }
            "capsule" | "cylinder" => {
                let r = size_at(0, "radius")?;
                let half = match half_length {
                    Some(h) => h,
                    None => size_at(1, "half-length")?,
                };
                if kind == "capsule" {
                    (
                        Primitive::Capsule {
                            radius: r * MM,
                            height: 2.0 * (half + r) * MM,
                        },
                        DVec3::new(0.0, 0.0, half + r),
                    )
                } else {
                    (
                        Primitive::Cylinder {
                            radius: r * MM,
                            height: 2.0 * half * MM,
                        },
                        DVec3::new(0.0, 0.0, half),
                    )
                }
            }
            "box" => {
                let h = DVec3::new(
                    size_at(0, "x half-size")?,
                    size_at(1, "y half-size")?,
                    size_at(2, "z half-size")?,
                );
                (
                    Primitive::Cube {
                        size: vec3(2.0 * h * MM),
                    },
                    h,
                )
            }
            // The caller sends only the solids above.
            other => {
                return Err(self.unsupported(node, format!("{other} geoms are not supported yet")))
            }
        })
    }

    /// `size[k]`, which must be positive: `what` names it in the error.
    fn size_at(
        &self,
        node: Node<'a, 'i>,
        kind: &str,
        size: &[f64],
        k: usize,
        what: &str,
    ) -> Result<f64> {
        size.get(k).copied().filter(|v| *v > 0.0).ok_or_else(|| {
            let article = if kind.starts_with(['a', 'e', 'i', 'o', 'u']) {
                "an"
            } else {
                "a"
            };
            self.bad(
                node,
                "size",
                format!("{article} {kind} needs a positive {what} (size[{k}])"),
            )
        })
    }

    /// The geom's instance name: its own, made unique, or its body's; the world's geoms are
    /// recorded as the world's.
    fn geom_name(&mut self, node: Node<'a, 'i>, body_name: &str) -> String {
        let name = match node.attribute("name") {
            Some(n) => {
                let name = self.unique(n);
                self.geom_instances.insert(n.to_string(), name.clone());
                name
            }
            None => self.unique(&format!("{body_name}_geom")),
        };
        if body_name == "world" {
            self.body_instances
                .entry("world".to_string())
                .or_default()
                .push(name.clone());
        }
        name
    }

    /// The geom's mass: its body's `<inertial>` share, `mass`, or `density` (into its
    /// material); a geom outside `inertiagrouprange`, or of `mass="0"`, weighs a helper's.
    fn geom_mass(
        &mut self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        name: &str,
        given_mass: Option<f64>,
        instance: &mut InstanceDef,
        material: &mut MaterialDef,
    ) -> Result<()> {
        // `compiler inertiagrouprange`: a geom outside it weighs nothing (here, 1 mg).
        let group = self
            .attr(node, class, "group")
            .and_then(|g| g.trim().parse::<i64>().ok())
            .unwrap_or(0);
        let (lo, hi) = self.inertia_groups;
        let weightless = !(lo..=hi).contains(&group);
        if weightless {
            self.massless.insert(name.to_string());
        }
        let given_mass = given_mass.or(weightless.then_some(HELPER_MASS));
        match (
            given_mass,
            self.number(node, class, "mass")?,
            self.number(node, class, "density")?,
        ) {
            (Some(m), _, _) => instance.inertial = Some(InertialDef::mass(m)),
            (None, Some(m), _) => {
                if m < 0.0 {
                    return Err(self.bad(node, "mass", format!("expected a mass >= 0, got {m}")));
                }
                // MuJoCo's `mass="0"`: the geom adds nothing to its body's mass, which
                // comes from the body's other geoms (or its <inertial>). Here it weighs a
                // helper's 1 mg, as every instance must weigh something.
                if m == 0.0 {
                    self.massless.insert(name.to_string());
                }
                instance.inertial = Some(InertialDef::mass(if m == 0.0 { HELPER_MASS } else { m }));
            }
            (None, None, Some(d)) if d != DEFAULT_DENSITY => material.density = Some(d),
            _ => {}
        }
        Ok(())
    }
}
