//! The tree: `<worldbody>` and each `<body>` (its instance, helper instances, welds, free
//! joints, `<inertial>`, and sites: every named body's origin and every `<site>`).

use super::*;

/// What a body hangs from.
#[derive(Debug, Clone, Copy)]
pub(super) enum BodyParent<'p> {
    /// The world: the body is a child of `<worldbody>`.
    World,
    /// A static body's instance (fixed where it is).
    Static(&'p str),
    /// A moving body's instance.
    Moving(&'p str),
}

impl<'a, 'i> Converter<'a, 'i> {
    /// Every `<worldbody>` (MuJoCo merges them). The world's geoms are static geometry:
    /// each an instance fixed where it is (`"fixed": true`), planes included, as many as the
    /// model has. A top-level body with a free joint is the floating base when something is
    /// jointed below it (a robot: the first such body), and otherwise a free body (an
    /// object), observed as its pose and velocity; a mocap body is kinematic, moved by the
    /// pose targets a client sets.
    pub(super) fn worldbody(&mut self, worlds: &[Node<'a, 'i>]) -> Result<()> {
        let children: Vec<Node<'a, 'i>> = worlds.iter().flat_map(|w| elements(*w)).collect();
        self.base_body = children
            .iter()
            .copied()
            .filter(|n| n.tag_name().name() == "body")
            .find(|body| self.free_joint_of(*body).is_some() && self.has_joint_below(*body))
            .map(|body| body.id());
        for geom in children
            .iter()
            .copied()
            .filter(|n| n.tag_name().name() == "geom")
        {
            if let Some(name) = self.geom(geom, &Frame::IDENTITY, None, "world", None, true)? {
                self.massless.insert(name.clone());
                self.set_fixed(&name);
                if self.world.is_none() {
                    self.world = Some(name.clone());
                    self.bodies.insert("world".into(), (name, Frame::IDENTITY));
                }
            }
        }
        let mut world_sites = Vec::new();
        for child in children {
            match child.tag_name().name() {
                "geom" => {}
                "body" => self.body(child, &Frame::IDENTITY, BodyParent::World, None)?,
                "site" => world_sites.push(child),
                "light" | "camera" => {
                    self.warn(child, "ignored (no effect on the dynamics)".into())
                }
                other => {
                    return Err(self.unsupported(
                        child,
                        format!("<{other}> in <worldbody> is not supported yet"),
                    ))
                }
            }
        }
        // The world's sites, after every body's: points of the world's instance.
        for site in world_sites {
            let (at, half_length) = self.site_frame(site, None)?;
            let world = self.world_instance();
            let name = site.attribute("name").unwrap_or("world_site");
            let mut volume = self.site_volume(site, None)?;
            if let Some(half) = half_length {
                volume.size.y = half * MM;
            }
            let kept = self.site(name, &world, &at, Some(volume));
            if let (Some(mjcf), Some(kept)) = (site.attribute("name"), kept) {
                self.site_of.insert(mjcf.to_string(), kept);
            }
        }
        Ok(())
    }

    /// The instance the world's own geoms and helpers stand for: the first world geom, or
    /// a helper fixed at the origin made on first use. What hangs from the world by a
    /// joint hangs from it.
    pub(super) fn world_instance(&mut self) -> String {
        if let Some(world) = &self.world {
            return world.clone();
        }
        let name = self.helper("world", &Frame::IDENTITY);
        self.set_fixed(&name);
        self.world = Some(name.clone());
        self.bodies
            .insert("world".into(), (name.clone(), Frame::IDENTITY));
        name
    }

    /// Marks instance `name` as fixed to the world where it is.
    pub(super) fn set_fixed(&mut self, name: &str) {
        if let Some(instance) = self.instances.iter_mut().find(|i| i.name == name) {
            instance.fixed = Some(true);
        }
    }

    /// `body`'s free joint, if it has one.
    fn free_joint_of(&self, body: Node<'a, 'i>) -> Option<Node<'a, 'i>> {
        let class = body.attribute("childclass");
        elements(body).find(|j| {
            matches!(j.tag_name().name(), "joint" | "freejoint") && self.is_free(*j, class)
        })
    }

    /// Whether a body below `body` has a joint: a robot rather than an object.
    fn has_joint_below(&self, body: Node<'a, 'i>) -> bool {
        body.descendants()
            .filter(|n| n.tag_name().name() == "body" && *n != body)
            .any(|b| elements(b).any(|j| matches!(j.tag_name().name(), "joint" | "freejoint")))
    }

    /// A top-level body's free joint: the body moves freely, as the floating base (the
    /// first with a joint below it) or as a free body. Its damping and armature act on no
    /// DOF gymfleet has: warned about.
    pub(super) fn free_joint(
        &mut self,
        joint: Node<'a, 'i>,
        class: Option<&str>,
        main: &str,
        is_base: bool,
    ) -> Result<()> {
        for (attr, what) in [
            ("damping", "damping"),
            ("armature", "armature"),
            ("stiffness", "stiffness"),
        ] {
            if self.number(joint, class, attr)?.is_some_and(|v| v != 0.0) {
                self.warn(
                    joint,
                    format!("{what} on a free joint ignored (its six DOFs take none)"),
                );
            }
        }
        if is_base {
            self.floating = Some(main.to_string());
        }
        Ok(())
    }

    /// A helper instance at a body's frame, turned as it is: what a free or mocap body's
    /// pose is read from and set on.
    pub(super) fn frame_helper(&mut self, wanted: &str, at: &Frame) -> String {
        let name = self.helper(wanted, at);
        if let Some(instance) = self.instances.iter_mut().find(|i| i.name == name) {
            instance.rotation = Some(Vec3::from(euler_xyz_degrees(at.rotation)));
        }
        self.frames.insert(name.clone(), *at);
        name
    }

    /// A helper instance: a small sphere of `HELPER_MASS` that collides with nothing.
    pub(super) fn helper(&mut self, wanted: &str, at: &Frame) -> String {
        self.helper_before(wanted, at, None)
    }

    /// [`Converter::helper`], listed before instance `before` (so that a body's own
    /// instance stays the last of its own, as users look for it).
    pub(super) fn helper_before(
        &mut self,
        wanted: &str,
        at: &Frame,
        before: Option<&str>,
    ) -> String {
        let name = self.unique(wanted);
        self.massless.insert(name.clone());
        self.parts.push(PartDef {
            name: name.clone(),
            primitive: Primitive::Sphere {
                radius: HELPER_RADIUS,
            },
            material: None,
        });
        let instance = InstanceDef {
            position: Some(vec3(at.translation * MM)),
            collision: Some(CollisionDef {
                group: Some(0),
                mask: Some(0),
            }),
            inertial: Some(InertialDef::mass(HELPER_MASS)),
            ..InstanceDef::new(&name, &name)
        };
        self.frames.insert(
            name.clone(),
            Frame {
                translation: at.translation,
                rotation: DQuat::IDENTITY,
            },
        );
        match before.and_then(|b| self.instances.iter().position(|i| i.name == b)) {
            Some(index) => self.instances.insert(index, instance),
            None => self.instances.push(instance),
        }
        name
    }

    /// A named frame `at` (world, m) on instance `instance`, in its frame: a site's, or a
    /// body's origin and axes (what MuJoCo's `xpos` and `xquat` report).
    pub(super) fn site(
        &mut self,
        wanted: &str,
        instance: &str,
        at: &Frame,
        volume: Option<gymfleet_assembly::SiteVolumeDef>,
    ) -> Option<String> {
        let frame = self.frames.get(instance)?;
        let back = frame.rotation.inverse();
        let local = back * (at.translation - frame.translation) * MM;
        let turn = back * at.rotation;
        let name = self.site_names.unique(wanted);
        self.sites.push(SiteDef {
            name: name.clone(),
            instance: instance.to_string(),
            point: vec3(local),
            rotation: (turn.angle_between(DQuat::IDENTITY) > 1e-12)
                .then(|| Vec3::from(euler_xyz_degrees(turn))),
            volume,
        });
        Some(name)
    }

    /// A site's frame in its body, and with `fromto` its half-length: MuJoCo puts such a
    /// site at the segment's middle, its z axis from the second point to the first (the way
    /// a rangefinder on it looks), and its `size[1]` at half the segment.
    pub(super) fn site_frame(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
    ) -> Result<(Frame, Option<f64>)> {
        let Some(f) = self.exactly::<6>(node, class, "fromto")? else {
            return Ok((self.local_frame(node, class)?, None));
        };
        let (a, b) = (DVec3::new(f[0], f[1], f[2]), DVec3::new(f[3], f[4], f[5]));
        let axis = a - b;
        if axis.length() < 1e-12 {
            return Err(self.bad(node, "fromto", "the two ends are the same point".into()));
        }
        let frame = Frame {
            translation: (a + b) / 2.0,
            rotation: z_onto(axis.normalize()),
        };
        Ok((frame, Some(axis.length() / 2.0)))
    }

    pub(super) fn joint_name(&mut self, wanted: &str) -> String {
        self.joint_names.unique(wanted)
    }

    pub(super) fn weld(&mut self, parent: String, child: String) {
        let name = self.joint_name(&format!("{child}_weld"));
        self.joints.push(JointDef {
            name: Some(name),
            ..JointDef::new(JointType::Fixed, parent, child)
        });
    }

    /// One body, its geoms, joints and children, hanging from `parent`.
    pub(super) fn body(
        &mut self,
        node: Node<'a, 'i>,
        parent_frame: &Frame,
        parent: BodyParent<'_>,
        class: Option<&str>,
    ) -> Result<()> {
        self.check_depth(node)?;
        let body_name = node.attribute("name").unwrap_or("body").to_string();
        let class_owned = node
            .attribute("childclass")
            .map(str::to_string)
            .or(class.map(str::to_string));
        let class = class_owned.as_deref();
        if let Some(v) = node.attribute("gravcomp").filter(|v| v.trim() != "0") {
            return Err(self.unsupported(node, format!("gravcomp=\"{v}\" is not supported yet")));
        }
        let top_level = matches!(parent, BodyParent::World);
        let mocap = self.mocap(node, top_level)?;
        let frame = parent_frame.then(&self.local_frame(node, None)?);
        let joints: Vec<Node<'a, 'i>> = elements(node)
            .filter(|n| matches!(n.tag_name().name(), "joint" | "freejoint"))
            .collect();
        // A jointless body below the world, and every jointless body below it, is static:
        // its instances are fixed where they are, as the world's geoms are.
        let is_static = joints.is_empty()
            && !mocap
            && matches!(parent, BodyParent::World | BodyParent::Static(_));
        let inertial = elements(node).find(|n| n.tag_name().name() == "inertial");
        let use_inertial = self.uses_inertial(node, inertial, is_static)?;

        // Geoms: the first is the body's instance, the others are welded to it (or, in a
        // static body, each fixed where it is).
        let first_instance = self.instances.len();
        let free = joints.iter().copied().find(|j| self.is_free(*j, class));
        let is_base = self.base_body == Some(node.id());
        let own_frame = (free.is_some() && !is_base) || mocap;
        let at = (body_name.as_str(), &frame);
        let main = self.body_geoms(node, class, at, own_frame, use_inertial, is_static)?;
        if let Some(i) = inertial.filter(|_| use_inertial) {
            self.inertial(i, &frame, &main)?;
        }
        self.body_origin(node, &body_name, &main, &frame);

        // Joints: parent → (helpers) → the body's instance.
        if let Some(free) = free {
            self.free_body(
                free,
                class,
                (main.as_str(), &frame),
                top_level,
                joints.len(),
                is_base,
            )?;
        }
        if mocap {
            self.mocap_body(joints.first().copied(), &main, &frame)?;
        }
        let held = (free.is_some(), mocap, is_static, joints.is_empty());
        let from = self.hang(parent, held, first_instance, &main);
        let joints = if free.is_some() { Vec::new() } else { joints };
        self.joint_chain(&joints, class, (&body_name, &main, &frame), from)?;

        if let Some(name) = node.attribute("name") {
            let own = self.instances[first_instance..]
                .iter()
                .map(|i| i.name.clone())
                .collect();
            self.body_instances.insert(name.to_string(), own);
        }
        let below = if is_static {
            BodyParent::Static(&main)
        } else {
            BodyParent::Moving(&main)
        };
        self.body_children(node, class, (&body_name, &main, &frame), below)
    }

    /// `<inertial>`: given mass properties on the body's instance, in its frame.
    pub(super) fn inertial(
        &mut self,
        node: Node<'a, 'i>,
        body: &Frame,
        instance: &str,
    ) -> Result<()> {
        let mass = self
            .number(node, None, "mass")?
            .ok_or_else(|| self.bad(node, "mass", "missing".into()))?;
        let local = self.local_frame(node, None)?;
        let world = body.then(&local);
        if mass < 0.0 {
            return Err(self.bad(node, "mass", format!("expected a mass >= 0, got {mass}")));
        }
        let principal = match (
            self.exactly::<3>(node, None, "diaginertia")?,
            self.exactly::<6>(node, None, "fullinertia")?,
        ) {
            (Some(d), None) => DMat3::from_diagonal(DVec3::from_array(d)),
            (None, Some([xx, yy, zz, xy, xz, yz])) => {
                DMat3::from_cols_array(&[xx, xy, xz, xy, yy, yz, xz, yz, zz])
            }
            _ => {
                return Err(self.bad(
                    node,
                    "diaginertia",
                    "expected one of diaginertia or fullinertia".into(),
                ))
            }
        };
        // MuJoCo takes a massless body, or one with no rotational inertia (a point mass),
        // where nothing moves it on its own (a camera frame welded to a link): here it
        // weighs at least a helper's 1 mg, and turns like a 1 mm ball of its mass.
        let (mass, principal) = if mass <= 0.0
            || gymfleet_assembly::inertia_problem(&principal.to_cols_array_2d()).is_some()
        {
            let mass = mass.max(HELPER_MASS);
            let floor = 0.4 * mass * POINT_RADIUS_M * POINT_RADIUS_M;
            let d = DVec3::new(principal.x_axis.x, principal.y_axis.y, principal.z_axis.z);
            (mass, DMat3::from_diagonal(d.max(DVec3::splat(floor))))
        } else {
            (mass, principal)
        };
        // Into the instance's frame: position and axes.
        let index = self
            .instances
            .iter()
            .position(|i| i.name == instance)
            .expect("the body's instance exists");
        self.instances[index].inertial = Some(inertial_def(
            mass,
            &world,
            principal,
            &self.frames[instance],
            MM,
        ));
        Ok(())
    }
}
