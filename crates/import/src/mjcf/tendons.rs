//! `<tendon><fixed>`: a fixed tendon (a linear combination of joint positions) becomes an
//! entry of the document's `assembly.tendons`, with its stiffness, damping and spring
//! length and range (a hard limit here, soft in MuJoCo). Friction loss and spatial tendons
//! are refused with their line.

use super::*;

/// A fixed tendon as read, its joints by their MJCF names (resolved in `finish`).
#[derive(Debug)]
pub(super) struct FixedTendon {
    pub(super) name: String,
    /// (joint name, coefficient, the `<joint>`'s line).
    joints: Vec<(String, f64, u32)>,
    stiffness: f64,
    damping: f64,
    spring_length: Option<f64>,
    range: Option<[f64; 2]>,
}

impl<'a, 'i> Converter<'a, 'i> {
    pub(super) fn tendons(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for child in elements(node) {
            match child.tag_name().name() {
                "fixed" => self.fixed_tendon(child)?,
                "spatial" => {
                    return Err(self.unsupported(
                        child,
                        "spatial tendons are not supported yet (fixed tendons are)".into(),
                    ))
                }
                other => {
                    return Err(
                        self.unsupported(child, format!("<{other}> in <tendon> is not supported"))
                    )
                }
            }
        }
        Ok(())
    }

    fn fixed_tendon(&mut self, node: Node<'a, 'i>) -> Result<()> {
        let class = node.attribute("class");
        let limited = self.attr(node, class, "limited").unwrap_or("auto");
        let range = self.exactly::<2>(node, class, "range")?;
        // `<flag limit="disable">`: no limit acts.
        let (limited, range) = if self.switched_off.limits {
            ("false", None)
        } else {
            (limited, range)
        };
        let range = match (limited, range) {
            ("true", None) => {
                return Err(self.bad(
                    node,
                    "range",
                    "missing: a limited tendon needs a range".into(),
                ))
            }
            ("true" | "auto", Some([lo, hi])) => {
                if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
                    return Err(self.bad(
                        node,
                        "range",
                        format!("expected min < max, got {lo} {hi}"),
                    ));
                }
                Some([lo, hi])
            }
            _ => None,
        };
        if self
            .number(node, class, "frictionloss")?
            .is_some_and(|f| f != 0.0)
        {
            return Err(
                self.unsupported(node, "a tendon's frictionloss is not supported yet".into())
            );
        }
        let stiffness = self.number(node, class, "stiffness")?.unwrap_or(0.0);
        let damping = self.number(node, class, "damping")?.unwrap_or(0.0);
        for (name, value) in [("stiffness", stiffness), ("damping", damping)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(self.bad(node, name, format!("expected a number ≥ 0, got {value}")));
            }
        }
        // MuJoCo: −1 (the default) is the length at qpos0; two values are a dead band.
        let spring_length = match self.numbers(node, class, "springlength")?.as_deref() {
            None | Some([-1.0]) | Some([-1.0, -1.0]) => None,
            Some([l]) => Some(*l),
            Some([lo, hi]) if lo == hi => Some(*lo),
            Some(_) => {
                return Err(self.unsupported(
                    node,
                    "a springlength dead band (two different values) is not supported yet".into(),
                ))
            }
        };
        let mut joints = Vec::new();
        for member in elements(node) {
            if member.tag_name().name() != "joint" {
                return Err(self.unsupported(
                    member,
                    format!(
                        "<{}> in a fixed tendon is not supported (only <joint>)",
                        member.tag_name().name()
                    ),
                ));
            }
            let joint = member
                .attribute("joint")
                .ok_or_else(|| self.bad(member, "joint", "missing".into()))?;
            let coef = self
                .number(member, None, "coef")?
                .ok_or_else(|| self.bad(member, "coef", "missing".into()))?;
            joints.push((joint.to_string(), coef, self.line(member)));
        }
        if joints.is_empty() {
            return Err(self.bad(
                node,
                "joint",
                "a fixed tendon needs at least one <joint>".into(),
            ));
        }
        let name = node
            .attribute("name")
            .map_or_else(|| format!("tendon{}", self.tendons.len()), str::to_string);
        self.tendons.push(FixedTendon {
            name,
            joints,
            stiffness,
            damping,
            spring_length,
            range,
        });
        Ok(())
    }

    /// The tendons as the document's `assembly.tendons`, their joints checked to be hinge
    /// or slide joints of the model.
    pub(super) fn tendon_defs(&self) -> Result<Vec<TendonDef>> {
        let known: HashSet<&String> = self.moving_joints.iter().collect();
        let mut out = Vec::with_capacity(self.tendons.len());
        for t in &self.tendons {
            let mut joints = Vec::with_capacity(t.joints.len());
            for (joint, coef, line) in &t.joints {
                if !known.contains(joint) {
                    return Err(ImportError::BadAttribute {
                        element: "joint".into(),
                        attribute: "joint".into(),
                        line: *line,
                        reason: format!("no hinge or slide joint is named {joint:?}"),
                    });
                }
                joints.push(TendonJointDef {
                    joint: joint.clone(),
                    coef: *coef,
                });
            }
            out.push(TendonDef {
                name: t.name.clone(),
                joints,
                stiffness: (t.stiffness > 0.0).then_some(t.stiffness),
                damping: (t.damping > 0.0).then_some(t.damping),
                spring_length: t.spring_length,
                range: t.range,
            });
        }
        Ok(out)
    }
}
