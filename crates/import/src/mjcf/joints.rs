//! One `<joint>` (hinge, slide, ball) between two instances: anchor, axis, range and
//! `ref`, damping, armature, friction, springs, and the motor that drives it.

use super::*;

impl<'a, 'i> Converter<'a, 'i> {
    /// MuJoCo's `springdamper`: two positive values size the joint's stiffness and damping
    /// (both zero: none).
    fn springdamper(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        our: &str,
    ) -> Result<Option<[f64; 2]>> {
        Ok(match self.exactly::<2>(node, class, "springdamper")? {
            None | Some([0.0, 0.0]) => None,
            Some([tc, dr]) if tc > 0.0 && dr > 0.0 && our != "ball" => Some([tc, dr]),
            Some(_) if our == "ball" => {
                return Err(self.unsupported(
                    node,
                    "springdamper on a ball joint (a rotational spring) is not supported yet"
                        .into(),
                ))
            }
            Some(v) => {
                return Err(self.bad(
                    node,
                    "springdamper",
                    format!(
                        "expected a time constant and a damping ratio, both > 0, got {} {}",
                        v[0], v[1]
                    ),
                ))
            }
        })
    }

    pub(super) fn joint(
        &mut self,
        node: Node<'a, 'i>,
        body: &Frame,
        class: Option<&str>,
        body_name: &str,
        parent: &str,
        child: &str,
    ) -> Result<()> {
        let (our, joint_type) = self.joint_kind(node, class)?;
        let springdamper = self.springdamper(node, class, our)?;
        let friction = self
            .number(node, class, "frictionloss")?
            .filter(|f| *f != 0.0);
        if let Some(f) = friction.filter(|f| *f < 0.0) {
            return Err(self.bad(
                node,
                "frictionloss",
                format!("expected a friction >= 0, got {f}"),
            ));
        }
        let stiffness = self.number(node, class, "stiffness")?.filter(|k| *k != 0.0);
        if stiffness.is_some() && our == "ball" {
            return Err(self.unsupported(
                node,
                "stiffness on a ball joint (a rotational spring) is not supported yet".into(),
            ));
        }
        // MuJoCo's joint value is `ref` at the model's pose; gymfleet measures limits from
        // that pose, so a range (given in MuJoCo's values) shifts by −ref, and reports
        // positions with the `reference` added back.
        let reference = self.number(node, class, "ref")?.unwrap_or(0.0);
        let pos = DVec3::from_array(self.exactly::<3>(node, class, "pos")?.unwrap_or([0.0; 3]));
        let axis = DVec3::from_array(
            self.exactly::<3>(node, class, "axis")?
                .unwrap_or([0.0, 0.0, 1.0]),
        );
        if our != "ball" && axis.length() < 1e-12 {
            return Err(self.bad(node, "axis", "the axis is the zero vector".into()));
        }
        let anchor = body.point(pos) * MM;
        let name = node
            .attribute("name")
            .map_or_else(|| format!("{body_name}_joint"), str::to_string);
        let name = self.joint_name(&name);
        let mut j = JointDef {
            name: Some(name.clone()),
            anchor: Some(vec3(anchor)),
            axis: (our != "ball").then(|| vec3(body.direction(axis.normalize()))),
            ..JointDef::new(joint_type, parent, child)
        };
        self.joint_range(node, class, our, reference, &mut j)?;
        j.damping = self.number(node, class, "damping")?.filter(|d| *d != 0.0);
        j.springdamper = springdamper;
        j.armature = self.number(node, class, "armature")?.filter(|a| *a != 0.0);
        j.friction = friction;
        self.joint_spring(
            node,
            class,
            our,
            (stiffness.or(springdamper.map(|_| 0.0)), reference),
            &mut j,
        )?;
        self.joint_motor(node, our, &name, &mut j);
        self.qpos_slots.push(if our == "ball" {
            keyframes::QposSlot::Ball { name: name.clone() }
        } else {
            keyframes::QposSlot::Joint {
                name: name.clone(),
                prismatic: our == "prismatic",
            }
        });
        self.moving_joints.push(name);
        self.joints.push(j);
        Ok(())
    }

    /// A joint's type, as gymfleet names it: a free joint is its body's only joint, in a
    /// top-level body (`bodies.rs`), never one of several.
    fn joint_kind(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
    ) -> Result<(&'static str, JointType)> {
        let kind = if node.tag_name().name() == "freejoint" {
            "free"
        } else {
            self.attr(node, class, "type").unwrap_or("hinge")
        };
        match kind {
            "hinge" => Ok(("revolute", JointType::Revolute)),
            "slide" => Ok(("prismatic", JointType::Prismatic)),
            "ball" => Ok(("ball", JointType::Ball)),
            "free" => Err(self.unsupported(
                node,
                "a free joint must be its body's only joint, in a top-level body".into(),
            )),
            other => Err(self.bad(node, "type", format!("unknown joint type {other:?}"))),
        }
    }

    /// A joint's range (MuJoCo's values, shifted by −`reference`) with its soft limit;
    /// a pose the range excludes starts at its nearest end.
    fn joint_range(
        &mut self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        our: &str,
        reference: f64,
        j: &mut JointDef,
    ) -> Result<()> {
        let name = j.name.clone().unwrap_or_default();
        let range = self.exactly::<2>(node, class, "range")?;
        let limited = self.flag(node, class, "limited")?;
        // `<flag limit="disable">`: no limit acts.
        let (range, limited) = if self.switched_off.limits {
            (None, None)
        } else {
            (range, limited)
        };
        if let (Some([lo, hi]), Some(true) | None) = (range, limited) {
            if our == "ball" {
                return Err(self.unsupported(
                    node,
                    "a ball joint's range (a cone) is not supported yet".into(),
                ));
            }
            if lo < hi {
                let (lo, hi) = (lo - reference, hi - reference);
                let (lo, hi) = if our == "revolute" {
                    (self.angle(lo).to_degrees(), self.angle(hi).to_degrees())
                } else {
                    (lo * MM, hi * MM)
                };
                j.min = Some(lo);
                j.max = Some(hi);
                j.soft_limit = Some(self.soft_limit(node, class, our == "revolute")?);
                // The model's pose (qpos = ref) breaks the range: start at the nearest
                // limit, where MuJoCo's limit constraint would push it.
                if lo > 0.0 || hi < 0.0 {
                    let start = 0.0f64.clamp(lo, hi);
                    j.initial = Some(start);
                    self.warn(
                        node,
                        format!(
                            "joint {name:?} starts at {} {}, the end of its range nearest to the model's pose, which the range excludes",
                            (start * 1e6).round() / 1e6,
                            if our == "revolute" { "deg" } else { "mm" }
                        ),
                    );
                }
            } else if limited == Some(true) {
                return Err(self.bad(
                    node,
                    "range",
                    format!("a limited joint needs min < max, got {lo} {hi}"),
                ));
            }
        } else if limited == Some(true) {
            return Err(self.bad(node, "range", "limited=\"true\" without a range".into()));
        }
        Ok(())
    }

    /// A joint's spring (`stiffness`, pulling to `springref`) and its `ref`, as gymfleet
    /// measures positions: from the model's pose.
    fn joint_spring(
        &mut self,
        node: Node<'a, 'i>,
        class: Option<&str>,
        our: &str,
        (stiffness, reference): (Option<f64>, f64),
        j: &mut JointDef,
    ) -> Result<()> {
        if let Some(k) = stiffness {
            if k < 0.0 {
                return Err(self.bad(
                    node,
                    "stiffness",
                    format!("expected a stiffness >= 0, got {k}"),
                ));
            }
            j.stiffness = (k != 0.0).then_some(k);
            // MuJoCo's spring pulls qpos to `springref`; positions here are qpos − ref.
            let rest = self.number(node, class, "springref")?.unwrap_or(0.0) - reference;
            if rest != 0.0 {
                let rest = if our == "revolute" {
                    self.angle(rest).to_degrees()
                } else {
                    rest * MM
                };
                j.spring_rest = Some(rest);
            }
        }
        if reference != 0.0 {
            // Observed positions are MuJoCo's qpos: the document's pose reports `ref`.
            let reference = if our == "revolute" {
                self.angle(reference).to_degrees()
            } else {
                reference * MM
            };
            j.reference = Some(reference);
        }
        Ok(())
    }

    /// A joint's motor: its effort bound and gear, or no actuation.
    fn joint_motor(&mut self, node: Node<'a, 'i>, our: &str, name: &str, j: &mut JointDef) {
        match self.motors.get(name).copied() {
            Some(motor) => {
                j.max_effort = motor.max_effort;
                if motor.gear != 1.0 {
                    if our == "revolute" || our == "prismatic" {
                        // Actions are MuJoCo's ctrl: the effort is gear × ctrl.
                        j.gear = Some(motor.gear);
                    } else {
                        self.warn(
                            node,
                            format!(
                                "gear {} is folded into max_effort: a {our} joint's actions are torques (N·m)",
                                motor.gear
                            ),
                        );
                    }
                }
            }
            None => j.actuated = Some(false),
        }
    }
}
