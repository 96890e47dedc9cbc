//! `<equality>`: `<connect>` and `<weld>` between bodies become loop-closing joints of the
//! document (a ball joint at the anchor, a fixed joint), passive and unobserved: they keep a
//! kinematic loop closed and add no DOF to observations, as MuJoCo's qpos has none for them.
//! Both are hard constraints here (MuJoCo's are soft: `solref`/`solimp` are ignored, with a
//! warning). An inactive one (`active="false"`) is left out, with a warning: gymfleet does
//! not switch constraints on. `<joint>` and `<tendon>` equalities with a linear `polycoef`
//! become the document's couplings (hard too); flex and distance equalities are refused.

use super::*;

/// How far a weld's `relpose` may place body2 from where the model places it (m, rad)
/// before the weld is refused: it would pull the bodies together at the start.
const RELPOSE_TOLERANCE: f64 = 1e-6;

impl<'a, 'i> Converter<'a, 'i> {
    /// Reads `<equality>` (after `<worldbody>`, whose bodies it names).
    pub(super) fn equalities(&mut self, node: Node<'a, 'i>) -> Result<()> {
        if self.switched_off.equalities {
            self.warn(
                node,
                "left out: <option><flag> switches equality constraints off".into(),
            );
            return Ok(());
        }
        for child in elements(node) {
            let kind = child.tag_name().name();
            match kind {
                "connect" | "weld" | "joint" | "tendon" => {}
                "flex" | "distance" => {
                    return Err(self.unsupported(
                        child,
                        format!(
                        "<{kind}> equality constraints are not supported (connect, weld, joint and tendon are)"
                    ),
                    ))
                }
                other => {
                    return Err(self
                        .unsupported(child, format!("<{other}> in <equality> is not supported")))
                }
            }
            let class = child.attribute("class");
            if self.attr(child, class, "active") == Some("false") {
                self.warn(
                    child,
                    "an inactive equality is left out: gymfleet does not switch constraints on"
                        .into(),
                );
                continue;
            }
            for attr in ["site1", "site2"] {
                if child.attribute(attr).is_some() {
                    return Err(self.unsupported(
                        child,
                        format!("{attr}: an equality between sites is not supported yet (name body1 and body2)"),
                    ));
                }
            }
            if child.attribute("solref").is_some() || child.attribute("solimp").is_some() {
                self.warn(
                    child,
                    "solref/solimp ignored: the constraint is hard".into(),
                );
            }
            if kind == "joint" || kind == "tendon" {
                self.coupling(child, kind)?;
            } else {
                self.body_equality(child, kind)?;
            }
        }
        Ok(())
    }

    /// A `<connect>` or `<weld>` as a loop-closing joint (see the module documentation).
    fn body_equality(&mut self, child: Node<'a, 'i>, kind: &str) -> Result<()> {
        let class = child.attribute("class");
        let body1 = self.equality_body(child, "body1", true)?;
        let body2 = self.equality_body(child, "body2", false)?;
        let (first, frame1) = body1;
        let (second, frame2) = body2;
        if first == second {
            return Err(self.bad(child, "body2", "names the same body as body1".into()));
        }
        // What the world holds (its geoms, static bodies, mocap bodies) is never a
        // joint's child: a constraint to it is written from it.
        let (first, second) = if self.held_by_world(&second) {
            (second, first)
        } else {
            (first, second)
        };
        let wanted = child
            .attribute("name")
            .map_or_else(|| format!("{first}_{second}_{kind}"), str::to_string);
        let name = self.joint_name(&wanted);
        let joint = if kind == "connect" {
            // MuJoCo: the anchor is in body1's frame; the constraint holds in the
            // model's pose, where body2's point is the same world point.
            let anchor = self
                .exactly::<3>(child, class, "anchor")?
                .ok_or_else(|| self.bad(child, "anchor", "missing".into()))?;
            let at = frame1.translation + frame1.rotation * DVec3::from(anchor);
            JointDef {
                name: Some(name),
                anchor: Some(vec3(at * MM)),
                actuated: Some(false),
                observed: Some(false),
                ..JointDef::new(JointType::Ball, first, second)
            }
        } else {
            if let Some(t) = self.number(child, class, "torquescale")? {
                if t != 1.0 {
                    self.warn(child, "torquescale ignored: the weld is rigid".into());
                }
            }
            if let Some(p) = self.exactly::<7>(child, class, "relpose")? {
                let q = DQuat::from_xyzw(p[4], p[5], p[6], p[3]);
                if q.length() > 0.0 {
                    let wanted = frame1.then(&Frame {
                        translation: DVec3::new(p[0], p[1], p[2]),
                        rotation: q.normalize(),
                    });
                    let off = (wanted.translation - frame2.translation).length();
                    let turn = wanted.rotation.angle_between(frame2.rotation);
                    if off > RELPOSE_TOLERANCE || turn > RELPOSE_TOLERANCE {
                        return Err(self.bad(
                            child,
                            "relpose",
                            format!(
                                "places body2 {:.3} mm and {:.3}° from where the model places it; a weld must hold in the model's pose (leave relpose out)",
                                off * MM,
                                turn.to_degrees()
                            ),
                        ));
                    }
                }
            }
            JointDef {
                name: Some(name),
                actuated: Some(false),
                ..JointDef::new(JointType::Fixed, first, second)
            }
        };
        self.joints.push(joint);
        Ok(())
    }

    /// A `<joint>` or `<tendon>` equality as a coupling: `joint1` (`tendon1`) held at
    /// `polycoef[0] + polycoef[1] ·` `joint2`'s (`tendon2`'s) displacement from qpos0.
    /// MuJoCo's polycoef has five terms; only the first two may be non-zero here.
    fn coupling(&mut self, node: Node<'a, 'i>, kind: &str) -> Result<()> {
        let class = node.attribute("class");
        let (first, second) = (format!("{kind}1"), format!("{kind}2"));
        let known = |name: &str| match kind {
            "joint" => self.moving_joints.iter().any(|j| j == name),
            _ => self.tendons.iter().any(|t| t.name == name && t.is_fixed()),
        };
        let what = if kind == "joint" {
            "hinge or slide joint"
        } else {
            "fixed tendon"
        };
        let named = |attribute: &str, required: bool| -> Result<Option<String>> {
            match node.attribute(attribute) {
                None if required => Err(self.bad(node, attribute, "missing".into())),
                None => Ok(None),
                Some(name) if known(name) => Ok(Some(name.to_string())),
                Some(name) => {
                    Err(self.bad(node, attribute, format!("no {what} is named {name:?}")))
                }
            }
        };
        let held = named(&first, true)?;
        let followed = named(&second, false)?;
        let poly = self
            .numbers(node, class, "polycoef")?
            .unwrap_or_else(|| vec![0.0, 1.0]);
        if poly.len() > 5 {
            return Err(self.bad(
                node,
                "polycoef",
                format!("expected at most 5 numbers, got {}", poly.len()),
            ));
        }
        if poly.iter().skip(2).any(|&c| c != 0.0) {
            return Err(self.unsupported(
                node,
                "polycoef: a nonlinear coupling (a term past the second) is not supported yet"
                    .into(),
            ));
        }
        let name = node.attribute("name").map_or_else(
            || format!("{kind}_coupling{}", self.couplings.len()),
            str::to_string,
        );
        let mut def = CouplingDef {
            name,
            joint1: None,
            joint2: None,
            tendon1: None,
            tendon2: None,
            polycoef: Some(poly.iter().take(2).copied().collect()),
        };
        if kind == "joint" {
            (def.joint1, def.joint2) = (held, followed);
        } else {
            (def.tendon1, def.tendon2) = (held, followed);
        }
        self.couplings.push(def);
        Ok(())
    }

    /// Whether the world holds instance `name` where it is: fixed, or a mocap body.
    fn held_by_world(&self, name: &str) -> bool {
        self.instances
            .iter()
            .any(|i| i.name == name && (i.fixed == Some(true) || i.mocap == Some(true)))
    }

    /// The instance and world frame of the body an equality names in `attribute` (the
    /// world's when `body2` is left out).
    fn equality_body(
        &self,
        node: Node<'a, 'i>,
        attribute: &str,
        required: bool,
    ) -> Result<(String, Frame)> {
        let name = match node.attribute(attribute) {
            Some(name) => name,
            None if required => return Err(self.bad(node, attribute, "missing".into())),
            None => "world",
        };
        self.bodies
            .get(name)
            .cloned()
            .ok_or_else(|| self.bad(node, attribute, format!("no body is named {name:?}")))
    }
}
