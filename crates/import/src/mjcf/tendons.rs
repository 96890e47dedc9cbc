//! `<tendon><fixed>` (a linear combination of joint positions) and `<tendon><spatial>`
//! through sites become entries of the document's `assembly.tendons`, with their
//! stiffness, damping, spring length and range (a hard limit here, soft in MuJoCo; a
//! spatial tendon's is a rope). Friction loss, wrapping around geoms and pulleys are
//! refused with their line.

use super::*;

/// A tendon as read, its joints and sites by their MJCF names (resolved in `finish`).
#[derive(Debug)]
pub(super) struct TendonRead {
    pub(super) name: String,
    /// A fixed tendon's (joint name, coefficient, the `<joint>`'s line).
    joints: Vec<(String, f64, u32)>,
    /// A spatial tendon's (site name, the `<site>`'s line).
    sites: Vec<(String, u32)>,
    stiffness: f64,
    damping: f64,
    spring_length: Option<f64>,
    range: Option<[f64; 2]>,
}

impl TendonRead {
    /// Whether it is a fixed tendon (a combination of joints), not a spatial one.
    pub(super) fn is_fixed(&self) -> bool {
        self.sites.is_empty()
    }
}

impl<'a, 'i> Converter<'a, 'i> {
    pub(super) fn tendons(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for child in elements(node) {
            match child.tag_name().name() {
                "fixed" => self.tendon(child, false)?,
                "spatial" => self.tendon(child, true)?,
                other => {
                    return Err(
                        self.unsupported(child, format!("<{other}> in <tendon> is not supported"))
                    )
                }
            }
        }
        Ok(())
    }

    fn tendon(&mut self, node: Node<'a, 'i>, spatial: bool) -> Result<()> {
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
        let (joints, sites) = if spatial {
            (Vec::new(), self.spatial_path(node)?)
        } else {
            (self.fixed_joints(node)?, Vec::new())
        };
        let name = node
            .attribute("name")
            .map_or_else(|| format!("tendon{}", self.tendons.len()), str::to_string);
        self.tendons.push(TendonRead {
            name,
            joints,
            sites,
            stiffness,
            damping,
            spring_length,
            range,
        });
        Ok(())
    }

    /// A fixed tendon's `<joint>`s: (name, coefficient, line).
    fn fixed_joints(&self, node: Node<'a, 'i>) -> Result<Vec<(String, f64, u32)>> {
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
        Ok(joints)
    }

    /// A spatial tendon's `<site>`s: (name, line). Wrapping around a geom and pulleys are
    /// refused.
    fn spatial_path(&self, node: Node<'a, 'i>) -> Result<Vec<(String, u32)>> {
        let mut sites = Vec::new();
        for member in elements(node) {
            match member.tag_name().name() {
                "site" => {
                    let site = member
                        .attribute("site")
                        .ok_or_else(|| self.bad(member, "site", "missing".into()))?;
                    sites.push((site.to_string(), self.line(member)));
                }
                "geom" => {
                    let how = if member.attribute("sidesite").is_some() {
                        "wrapping around a geom (with its sidesite)"
                    } else {
                        "wrapping around a geom"
                    };
                    return Err(self.unsupported(
                        member,
                        format!("{how} is not supported yet: a spatial tendon goes straight through its sites"),
                    ));
                }
                other => {
                    return Err(self.unsupported(
                        member,
                        format!("<{other}> in a spatial tendon is not supported (only <site>)"),
                    ))
                }
            }
        }
        if sites.len() < 2 {
            return Err(self.bad(
                node,
                "site",
                format!(
                    "a spatial tendon needs at least two <site>s, got {}",
                    sites.len()
                ),
            ));
        }
        Ok(sites)
    }

    /// The tendons as the document's `assembly.tendons`, their joints checked to be hinge
    /// or slide joints of the model and their sites to be sites of it.
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
            let mut sites = Vec::with_capacity(t.sites.len());
            for (site, line) in &t.sites {
                let Some(name) = self.site_of.get(site) else {
                    return Err(ImportError::BadAttribute {
                        element: "site".into(),
                        attribute: "site".into(),
                        line: *line,
                        reason: format!("no site is named {site:?}"),
                    });
                };
                sites.push(name.clone());
            }
            out.push(TendonDef {
                name: t.name.clone(),
                joints,
                sites,
                stiffness: (t.stiffness > 0.0).then_some(t.stiffness),
                damping: (t.damping > 0.0).then_some(t.damping),
                spring_length: t.spring_length,
                range: t.range,
            });
        }
        Ok(out)
    }
}
