//! URDF joints: revolute, continuous, prismatic, fixed and floating, as assembly joints
//! (anchor and axis in world coordinates, limits in deg or mm).

use glam::DVec3;
use roxmltree::Node;
use serde_json::{json, Map, Value};

use crate::frame::Frame;
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
        let (json_kind, linear) = match kind {
            "revolute" | "continuous" => ("revolute", false),
            "prismatic" => ("prismatic", true),
            "fixed" => ("fixed", false),
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
        let mut j = Map::new();
        j.insert("type".into(), json!(json_kind));
        j.insert("name".into(), json!(self.unique(&name)));
        j.insert("parent".into(), json!(parent));
        j.insert("child".into(), json!(child_instance));
        let anchor = frame.translation * MM;
        j.insert(
            "anchor".into(),
            json!({"x": anchor.x, "y": anchor.y, "z": anchor.z}),
        );
        if json_kind == "fixed" {
            self.joints.push(Value::Object(j));
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
        let axis = frame.direction(axis.normalize());
        j.insert(
            "axis".into(),
            json!({"x": axis.x, "y": axis.y, "z": axis.z}),
        );
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
                j.insert("min".into(), json!(unit(lower)));
                j.insert("max".into(), json!(unit(upper)));
                // The zero pose breaks these limits (Panda's joint 4, Kinova's joint 2):
                // start at the nearest limit, where MuJoCo's limit would push it.
                if lower > 0.0 || upper < 0.0 {
                    let start = 0.0f64.clamp(lower, upper);
                    j.insert("initial".into(), json!(unit(start)));
                    self.warn(
                        l,
                        format!(
                            "joint {} starts at {} {}, its limit nearest to the zero pose that its limits exclude",
                            crate::quote(&name),
                            (unit(start) * 1e6).round() / 1e6,
                            if linear { "mm" } else { "deg" }
                        ),
                    );
                }
            }
        }
        if let Some(l) = limit {
            match self.number(l, "effort")? {
                Some(e) if e > 0.0 => {
                    j.insert("max_effort".into(), json!(e));
                }
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
        if let Some(d) = child(node, "dynamics") {
            if let Some(damping) = self.number(d, "damping")? {
                if damping < 0.0 {
                    return Err(self.bad(
                        d,
                        "damping",
                        format!("expected damping ≥ 0, got {damping}"),
                    ));
                }
                if damping > 0.0 {
                    j.insert("damping".into(), json!(damping));
                }
            }
            if let Some(f) = self.number(d, "friction")?.filter(|f| *f != 0.0) {
                if f < 0.0 {
                    return Err(self.bad(d, "friction", format!("expected friction ≥ 0, got {f}")));
                }
                if json_kind != "fixed" {
                    j.insert("friction".into(), json!(f));
                }
            }
        }
        for other in ["calibration", "safety_controller"] {
            if let Some(n) = child(node, other) {
                self.warn(n, "ignored (no effect on the dynamics)".into());
            }
        }
        self.joints.push(Value::Object(j));
        Ok(())
    }
}
