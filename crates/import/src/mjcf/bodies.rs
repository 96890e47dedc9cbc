//! The tree: `<worldbody>` and each `<body>` (its instance, helper instances, welds, free
//! joints, `<inertial>`, and sites: every named body's origin and every `<site>`).

use super::*;

impl<'a, 'i> Converter<'a, 'i> {
    pub(super) fn worldbody(&mut self, world: Node<'a, 'i>) -> Result<()> {
        // A top-level body with a free joint makes the model's first instance that body's, a
        // floating base (MuJoCo allows free joints in top-level bodies only); the world's
        // geoms are then grounds only if they are planes.
        let floating = elements(world)
            .filter(|n| n.tag_name().name() == "body")
            .any(|body| {
                let class = body.attribute("childclass");
                elements(body).any(|j| {
                    matches!(j.tag_name().name(), "joint" | "freejoint") && self.is_free(j, class)
                })
            });
        let mut world_instance: Option<String> = None;
        // The world's geoms first: the first of them is the grounded instance. A colliding
        // plane (a ground) must be it, so planes go first; one at most.
        let mut geoms: Vec<Node<'a, 'i>> = elements(world)
            .filter(|n| n.tag_name().name() == "geom")
            .collect();
        geoms.sort_by_key(|g| self.attr(*g, None, "type") != Some("plane"));
        for geom in geoms {
            if let Some(name) = self.geom(geom, &Frame::IDENTITY, None, "world", None)? {
                self.massless.insert(name.clone());
                match &world_instance {
                    None if floating && self.attr(geom, None, "type") != Some("plane") => {
                        return Err(self.unsupported(
                            geom,
                            "in a model with a free joint, the world's geoms other than a plane need a ground plane to be fixed to"
                                .into(),
                        ))
                    }
                    None => world_instance = Some(name),
                    Some(ground) => self.weld(ground.clone(), name),
                }
            }
        }
        let ground = match world_instance {
            Some(g) => Some(g),
            None if floating => None,
            None => Some(self.helper("world", &Frame::IDENTITY)),
        };
        if let Some(g) = &ground {
            self.bodies
                .insert("world".into(), (g.clone(), Frame::IDENTITY));
        }
        for child in elements(world) {
            match child.tag_name().name() {
                "geom" => {}
                "body" => self.body(child, &Frame::IDENTITY, ground.as_deref(), None)?,
                "light" | "camera" | "site" => {
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
        Ok(())
    }

    /// A top-level body's free joint: the body moves freely (the first such body is the
    /// floating base). Its damping and armature act on no DOF gymfleet has: warned about.
    pub(super) fn free_joint(
        &mut self,
        joint: Node<'a, 'i>,
        class: Option<&str>,
        main: &str,
    ) -> Result<()> {
        for (attr, what) in [
            ("damping", "damping"),
            ("armature", "armature"),
            ("stiffness", "stiffness"),
        ] {
            if self.number(joint, class, attr)?.is_some_and(|v| v != 0.0) {
                self.warn(
                    joint,
                    format!("{what} on a free joint ignored (the base's six DOFs take none)"),
                );
            }
        }
        match &self.floating {
            None => self.floating = Some(main.to_string()),
            Some(base) => {
                let base = base.clone();
                self.warn(
                    joint,
                    format!(
                        "a second free body moves freely, but only the first ({base:?}) is observed as the floating base; name {main:?} in end_effector_ids to observe its pose"
                    ),
                );
            }
        }
        Ok(())
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

    /// A named point at `at` (world, m) on instance `instance`, in its frame.
    pub(super) fn site(&mut self, wanted: &str, instance: &str, at: DVec3) {
        let Some(frame) = self.frames.get(instance) else {
            return;
        };
        let local = frame.rotation.inverse() * (at - frame.translation) * MM;
        let name = self.site_names.unique(wanted);
        self.sites.push(SiteDef {
            name,
            instance: instance.to_string(),
            point: vec3(local),
        });
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

    /// One body, its geoms, joints and children. `parent` is the instance it hangs from;
    /// `None` for a top-level body of a model with a free joint and no ground plane.
    pub(super) fn body(
        &mut self,
        node: Node<'a, 'i>,
        parent_frame: &Frame,
        parent: Option<&str>,
        class: Option<&str>,
    ) -> Result<()> {
        // Bounded before recursing further: a hostile tree of nested bodies would
        // otherwise overflow the converting thread's stack.
        let nested = node
            .ancestors()
            .filter(|n| n.has_tag_name("body"))
            .take(MAX_BODY_DEPTH + 1)
            .count();
        if nested > MAX_BODY_DEPTH {
            return Err(self.unsupported(
                node,
                format!("bodies nested more than {MAX_BODY_DEPTH} deep are not supported"),
            ));
        }
        let body_name = node.attribute("name").unwrap_or("body").to_string();
        let class_owned = node
            .attribute("childclass")
            .map(str::to_string)
            .or(class.map(str::to_string));
        let class = class_owned.as_deref();
        for (attr, ok) in [("mocap", "false"), ("gravcomp", "0")] {
            if let Some(v) = node.attribute(attr) {
                if v != ok {
                    return Err(
                        self.unsupported(node, format!("{attr}=\"{v}\" is not supported yet"))
                    );
                }
            }
        }
        let frame = parent_frame.then(&self.local_frame(node, None)?);
        let inertial = elements(node).find(|n| n.tag_name().name() == "inertial");
        let use_inertial = match (self.inertia_from_geom, inertial) {
            (InertiaFromGeom::True, Some(i)) => {
                self.warn(
                    i,
                    "ignored: compiler inertiafromgeom=\"true\" takes masses from the geoms".into(),
                );
                false
            }
            (InertiaFromGeom::False, None) => {
                return Err(self.unsupported(
                    node,
                    "inertiafromgeom=\"false\" and no <inertial>: the body has no mass".into(),
                ))
            }
            (_, i) => i.is_some(),
        };

        // Geoms: the first is the body's instance, the others are welded to it.
        let mut main: Option<String> = None;
        for geom in elements(node).filter(|n| n.tag_name().name() == "geom") {
            let given = if use_inertial {
                Some(HELPER_MASS)
            } else {
                None
            };
            let Some(name) = self.geom(geom, &frame, class, &body_name, given)? else {
                continue;
            };
            match &main {
                None => main = Some(name),
                Some(m) => self.weld(m.clone(), name),
            }
        }
        let main = match main {
            Some(m) => m,
            None => {
                if !use_inertial {
                    self.warn(
                        node,
                        "a body without geoms or <inertial> gets a 1 mg helper mass".into(),
                    );
                }
                self.helper(&body_name, &frame)
            }
        };
        if let Some(i) = inertial.filter(|_| use_inertial) {
            self.inertial(i, &frame, &main)?;
        }
        // The body's origin, by the body's name (what MuJoCo's body xpos reports).
        if let Some(name) = node.attribute("name") {
            self.site(name, &main, frame.translation);
            self.bodies.insert(name.to_string(), (main.clone(), frame));
        }

        // Joints: parent → (helpers) → the body's instance.
        let joints: Vec<Node<'a, 'i>> = elements(node)
            .filter(|n| matches!(n.tag_name().name(), "joint" | "freejoint"))
            .collect();
        let top_level = node
            .parent_element()
            .is_some_and(|p| p.tag_name().name() == "worldbody");
        let free = joints.iter().copied().find(|j| self.is_free(*j, class));
        if let Some(free) = free {
            if !top_level {
                return Err(self.unsupported(
                    free,
                    "a free joint belongs to a top-level body (a child of <worldbody>)".into(),
                ));
            }
            if joints.len() > 1 {
                return Err(
                    self.unsupported(free, "a free joint must be its body's only joint".into())
                );
            }
            self.free_joint(free, class, &main)?;
        }
        let parent = match (parent, free) {
            (_, Some(_)) => "",
            (Some(p), None) => p,
            (None, None) => {
                return Err(self.unsupported(
                    node,
                    "in a model with a free joint, a body fixed or jointed to the world needs a ground plane in <worldbody>"
                        .into(),
                ))
            }
        };
        if joints.is_empty() {
            self.weld(parent.to_string(), main.clone());
        }
        let joints = if free.is_some() { Vec::new() } else { joints };
        let mut from = parent.to_string();
        for (k, joint) in joints.iter().enumerate() {
            let to = if k + 1 == joints.len() {
                main.clone()
            } else {
                self.helper_before(&format!("{body_name}_dof{}", k + 1), &frame, Some(&main))
            };
            self.joint(*joint, &frame, class, &body_name, &from, &to)?;
            from = to;
        }

        for child in elements(node) {
            match child.tag_name().name() {
                "geom" | "joint" | "freejoint" | "inertial" => {}
                "body" => self.body(child, &frame, Some(&main), class)?,
                "site" => {
                    // A site is kept as a named point of the body's instance.
                    let at = frame.then(&self.local_frame(child, class)?).translation;
                    let name = child
                        .attribute("name")
                        .map_or_else(|| format!("{body_name}_site"), str::to_string);
                    self.site(&name, &main, at);
                }
                "camera" | "light" => {
                    self.warn(child, "ignored (no effect on the dynamics)".into())
                }
                other => {
                    return Err(self
                        .unsupported(child, format!("<{other}> in <body> is not supported yet")))
                }
            }
        }
        Ok(())
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
