//! The parts of an MJCF `<body>` that `bodies.rs`'s `Converter::body` reads one by one:
//! its depth, `mocap` and mass source, its geoms, its free or mocap root, the joint chain
//! from its parent, its origin, sites and children.

use super::bodies::BodyParent;
use super::*;

impl<'a, 'i> Converter<'a, 'i> {
    /// The instance a body's first joint hangs from (none for a free, mocap or static
    /// top-level body: the empty name). A static body's instances (from `first`) are
    /// fixed where they are; a jointless moving body is welded to its parent.
    pub(super) fn hang(
        &mut self,
        parent: BodyParent<'_>,
        (free, mocap, is_static, jointless): (bool, bool, bool, bool),
        first: usize,
        main: &str,
    ) -> String {
        let parent_instance = match parent {
            BodyParent::World if !free && !mocap && !is_static => Some(self.world_instance()),
            BodyParent::World => None,
            BodyParent::Static(p) | BodyParent::Moving(p) => Some(p.to_string()),
        };
        if is_static {
            for instance in &mut self.instances[first..] {
                instance.fixed = Some(true);
            }
        } else if jointless && !mocap {
            if let Some(p) = &parent_instance {
                self.weld(p.clone(), main.to_string());
            }
        }
        parent_instance.unwrap_or_default()
    }

    /// Bounded before recursing further: a hostile tree of nested bodies would otherwise
    /// overflow the converting thread's stack.
    pub(super) fn check_depth(&self, node: Node<'a, 'i>) -> Result<()> {
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
        Ok(())
    }

    /// A body's child bodies (hanging from `below`) and sites; its geoms, joints and
    /// inertial are read already.
    pub(super) fn body_children(
        &mut self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        (body_name, main, frame): (&str, &str, &Frame),
        below: BodyParent<'_>,
    ) -> Result<()> {
        for child in elements(node) {
            match child.tag_name().name() {
                "geom" | "joint" | "freejoint" | "inertial" => {}
                "body" => self.body(child, frame, below, class)?,
                "site" => self.body_site(child, class, (body_name, main), frame)?,
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

    /// A body's joints, parent → (helpers) → the body's instance `main`: each joint but
    /// the last moves a helper of its own.
    pub(super) fn joint_chain(
        &mut self,
        joints: &[Node<'a, 'i>],
        class: Option<&str>,
        (body_name, main, frame): (&str, &str, &Frame),
        mut from: String,
    ) -> Result<()> {
        for (k, joint) in joints.iter().enumerate() {
            let to = if k + 1 == joints.len() {
                main.to_string()
            } else {
                self.helper_before(&format!("{body_name}_dof{}", k + 1), frame, Some(main))
            };
            self.joint(*joint, frame, class, body_name, &from, &to)?;
            from = to;
        }
        Ok(())
    }

    /// The body's origin, by the body's name (what MuJoCo's body xpos reports); an
    /// unnamed body's as `body` (made unique), so that every body has one, in body order.
    pub(super) fn body_origin(
        &mut self,
        node: Node<'a, 'i>,
        body_name: &str,
        main: &str,
        frame: &Frame,
    ) {
        let origin = self.site(body_name, main, frame, None);
        if let (Some(name), Some(origin)) = (node.attribute("name"), origin) {
            self.body_sites.insert(name.to_string(), origin);
        }
        if let Some(name) = node.attribute("name") {
            self.bodies
                .insert(name.to_string(), (main.to_string(), *frame));
        }
    }

    /// A body's `mocap`: a mocap body is a child of `<worldbody>` (`top_level`).
    pub(super) fn mocap(&self, node: Node<'a, 'i>, top_level: bool) -> Result<bool> {
        match node.attribute("mocap") {
            None | Some("false") => Ok(false),
            Some("true") if top_level => Ok(true),
            Some("true") => Err(self.bad(
                node,
                "mocap",
                "a mocap body is a child of <worldbody> (MuJoCo's rule)".into(),
            )),
            Some(other) => Err(self.bad(
                node,
                "mocap",
                format!("expected true or false, got {other:?}"),
            )),
        }
    }

    /// Whether a body's mass comes from its `<inertial>` rather than its geoms (the
    /// compiler's `inertiafromgeom`).
    pub(super) fn uses_inertial(
        &mut self,
        node: Node<'a, 'i>,
        inertial: Option<Node<'a, 'i>>,
        is_static: bool,
    ) -> Result<bool> {
        Ok(match (self.inertia_from_geom, inertial) {
            (InertiaFromGeom::True, Some(i)) => {
                self.warn(
                    i,
                    "ignored: compiler inertiafromgeom=\"true\" takes masses from the geoms".into(),
                );
                false
            }
            (InertiaFromGeom::False, None) if !is_static => {
                return Err(self.unsupported(
                    node,
                    "inertiafromgeom=\"false\" and no <inertial>: the body has no mass".into(),
                ))
            }
            (_, i) => i.is_some(),
        })
    }

    /// A body's geoms, the first its instance and the others welded to it (or, in a
    /// static body, each fixed where it is); returns the body's instance. A free body (an
    /// object) or a mocap body is observed and moved by its own frame (`own_frame`), as
    /// MuJoCo's qpos and mocap_pos give it: its instance is a helper there, named after
    /// the body, and its geoms are welded to it.
    pub(super) fn body_geoms(
        &mut self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        (body_name, frame): (&str, &Frame),
        own_frame: bool,
        use_inertial: bool,
        is_static: bool,
    ) -> Result<String> {
        let mut main: Option<String> = own_frame.then(|| self.frame_helper(body_name, frame));
        for geom in elements(node).filter(|n| n.tag_name().name() == "geom") {
            let given = use_inertial.then_some(HELPER_MASS);
            let Some(name) = self.geom(geom, frame, class, body_name, given, is_static)? else {
                continue;
            };
            match &main {
                None => main = Some(name),
                Some(_) if is_static => {}
                Some(m) => self.weld(m.clone(), name),
            }
        }
        Ok(match main {
            Some(m) => m,
            None => {
                if !use_inertial {
                    self.warn(
                        node,
                        "a body without geoms or <inertial> gets a 1 mg helper mass".into(),
                    );
                }
                self.helper(body_name, frame)
            }
        })
    }

    /// A top-level body's free joint (its only joint) on its instance `main`, and the
    /// qpos slot it fills.
    pub(super) fn free_body(
        &mut self,
        free: Node<'a, 'i>,
        class: Option<&str>,
        (main, frame): (&str, &Frame),
        top_level: bool,
        joints: usize,
        is_base: bool,
    ) -> Result<()> {
        if !top_level {
            return Err(self.unsupported(
                free,
                "a free joint belongs to a top-level body (a child of <worldbody>)".into(),
            ));
        }
        if joints > 1 {
            return Err(self.unsupported(free, "a free joint must be its body's only joint".into()));
        }
        self.free_joint(free, class, main, is_base)?;
        let instance = self.frames.get(main).copied().unwrap_or(*frame);
        self.qpos_slots.push(keyframes::QposSlot::Free {
            base: is_base,
            instance: main.to_string(),
            body: *frame,
            frame: instance,
        });
        Ok(())
    }

    /// A mocap body (it has no joints: `joint` is its first, if any) on its instance.
    pub(super) fn mocap_body(
        &mut self,
        joint: Option<Node<'a, 'i>>,
        main: &str,
        frame: &Frame,
    ) -> Result<()> {
        if let Some(joint) = joint {
            return Err(self.bad(
                joint,
                "type",
                "a mocap body has no joints: its pose targets move it".into(),
            ));
        }
        if let Some(instance) = self.instances.iter_mut().find(|i| i.name == main) {
            instance.mocap = Some(true);
        }
        self.mocap_bodies.push((main.to_string(), *frame));
        Ok(())
    }

    /// A site, kept as a named point of the body's instance `main`.
    pub(super) fn body_site(
        &mut self,
        child: Node<'a, 'i>,
        class: Option<&str>,
        (body_name, main): (&str, &str),
        frame: &Frame,
    ) -> Result<()> {
        let (local, half_length) = self.site_frame(child, class)?;
        let at = frame.then(&local);
        let name = child
            .attribute("name")
            .map_or_else(|| format!("{body_name}_site"), str::to_string);
        let mut volume = self.site_volume(child, class)?;
        if let Some(half) = half_length {
            volume.size.y = half * MM;
        }
        let kept = self.site(&name, main, &at, Some(volume));
        if let (Some(mjcf), Some(kept)) = (child.attribute("name"), kept) {
            self.site_of.insert(mjcf.to_string(), kept);
        }
        Ok(())
    }
}
