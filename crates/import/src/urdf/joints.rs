//! URDF joints: revolute, continuous, prismatic, fixed and floating, as assembly joints
//! (anchor and axis in world coordinates, limits in deg or mm).

use glam::DVec3;
use gymfleet_assembly::{JointDef, JointType};
use roxmltree::Node;

use crate::frame::{vec3, Frame};
use crate::xml::XmlReader;
use crate::Result;

use super::{child, Converter, MM};

impl<'a, 'i> Converter<'a, 'i> {
    /// A `<joint>` from the parent link's instance to the child's; `frame` is the joint's
    /// (the child link's) frame in the world.
    pub(super) fn joint(
        &mut self,
        node: Node<'a, 'i>,
        frame: &Frame,
        parent: &str,
        child_instance: &str,
    ) -> Result<()> {
        let name = self.required(node, "name")?.to_string();
        let kind = self.required(node, "type")?;
        if let Some(m) = child(node, "mimic") {
            return Err(self.unsupported(
                m,
                format!(
                    "joint {} mimics another: mimic joints are not supported (make it a separate, actuated joint, or fixed)",
                    crate::quote(&name)
                ),
            ));
        }
        let (joint_type, linear) = match kind {
            "revolute" | "continuous" => (JointType::Revolute, false),
            "prismatic" => (JointType::Prismatic, true),
            "fixed" => (JointType::Fixed, false),
            "floating" => {
                return Err(self.unsupported(
                    node,
                    "a floating joint must hang the robot's base from the world link".into(),
                ))
            }
            other => {
                return Err(self.bad(
                    node,
                    "type",
                    format!("{} joints are not supported", crate::quote(other)),
                ))
            }
        };
        let mut j = JointDef {
            name: Some(self.unique(&name)),
            anchor: Some(vec3(frame.translation * MM)),
            ..JointDef::new(joint_type, parent, child_instance)
        };
        if joint_type == JointType::Fixed {
            self.joints.push(j);
            return Ok(());
        }
        let axis_node = child(node, "axis");
        let axis = match axis_node {
            Some(a) => DVec3::from_array(self.numbers::<3>(a, "xyz")?.unwrap_or([1.0, 0.0, 0.0])),
            None => DVec3::X,
        };
        if axis.length() < 1e-12 {
            return Err(self.bad(
                axis_node.unwrap_or(node),
                "xyz",
                "the axis is the zero vector".into(),
            ));
        }
        j.axis = Some(vec3(frame.direction(axis.normalize())));
        self.limits(node, kind, (&name, linear), &mut j)?;
        if let Some(d) = child(node, "dynamics") {
            self.dynamics(d, &mut j)?;
        }
        for other in ["calibration", "safety_controller"] {
            if let Some(n) = child(node, other) {
                self.warn(n, "ignored (no effect on the dynamics)".into());
            }
        }
        self.joints.push(j);
        Ok(())
    }

    /// A moving joint's `<limit>`: its range (a continuous joint has none), effort bound
    /// and ignored velocity; a zero pose outside the range starts at its nearest end.
    fn limits(
        &mut self,
        node: Node<'a, 'i>,
        kind: &str,
        (name, linear): (&str, bool),
        j: &mut JointDef,
    ) -> Result<()> {
        let limit = child(node, "limit");
        match (kind, limit) {
            ("continuous", _) => {}
            (_, None) => {
                return Err(self.unsupported(
                    node,
                    format!("a {kind} joint needs <limit lower upper effort velocity> (use continuous for a joint without limits)"),
                ))
            }
            (_, Some(l)) => {
                let lower = self.number(l, "lower")?.unwrap_or(0.0);
                let upper = self.number(l, "upper")?.unwrap_or(0.0);
                if lower > upper {
                    return Err(self.bad(l, "lower", format!("lower {lower} is above upper {upper}")));
                }
                let unit = |v: f64| if linear { v * MM } else { v.to_degrees() };
                j.min = Some(unit(lower));
                j.max = Some(unit(upper));
                // The zero pose breaks these limits (Panda's joint 4, Kinova's joint 2):
                // start at the nearest limit, where MuJoCo's limit would push it.
                if lower > 0.0 || upper < 0.0 {
                    let start = 0.0f64.clamp(lower, upper);
                    j.initial = Some(unit(start));
                    self.warn(
                        l,
                        format!(
                            "joint {} starts at {} {}, its limit nearest to the zero pose that its limits exclude",
                            crate::quote(name),
                            (unit(start) * 1e6).round() / 1e6,
                            if linear { "mm" } else { "deg" }
                        ),
                    );
                }
            }
        }
        if let Some(l) = limit {
            match self.number(l, "effort")? {
                Some(e) if e > 0.0 => j.max_effort = Some(e),
                Some(e) if e < 0.0 => {
                    return Err(self.bad(l, "effort", format!("expected an effort ≥ 0, got {e}")))
                }
                _ => self.warn(
                    l,
                    "effort 0 or none: the joint's effort is not clamped".into(),
                ),
            }
            if l.attribute("velocity").is_some() {
                self.warn(
                    l,
                    "velocity ignored (gymfleet limits effort, not speed)".into(),
                );
            }
        }
        Ok(())
    }

    /// A joint's `<dynamics>`: damping and dry friction, neither negative.
    fn dynamics(&mut self, d: Node<'a, 'i>, j: &mut JointDef) -> Result<()> {
        if let Some(damping) = self.number(d, "damping")? {
            if damping < 0.0 {
                return Err(self.bad(d, "damping", format!("expected damping ≥ 0, got {damping}")));
            }
            if damping > 0.0 {
                j.damping = Some(damping);
            }
        }
        if let Some(f) = self.number(d, "friction")?.filter(|f| *f != 0.0) {
            if f < 0.0 {
                return Err(self.bad(d, "friction", format!("expected friction ≥ 0, got {f}")));
            }
            j.friction = Some(f);
        }
        Ok(())
    }
}
