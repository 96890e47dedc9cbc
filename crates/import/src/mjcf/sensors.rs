//! `<sensor>`: MuJoCo's sensors become the document's `assembly.sensors`, in order, on the
//! sites, instances, joints, actuators and tendons the conversion made. A frame sensor's
//! `xbody` is its body's origin site, a `site` its site and a `geom` the geom's instance;
//! a subtree sensor's body is its body's instance. What gymfleet has no sensor for (a ball
//! joint's, an actuator's length, the clock, a `user` sensor, MuJoCo's inertial `body`
//! frame) is skipped with a warning, so its floats are missing from the readings.

use gymfleet_assembly::{SensorDef, SensorFrameDef, SensorType};

use super::*;

/// The sensor types converted, by element name.
fn sensor_type(tag: &str) -> Option<SensorType> {
    use SensorType::*;
    Some(match tag {
        "jointpos" => Jointpos,
        "jointvel" => Jointvel,
        "actuatorfrc" => Actuatorfrc,
        "tendonpos" => Tendonpos,
        "tendonvel" => Tendonvel,
        "framepos" => Framepos,
        "framequat" => Framequat,
        "framexaxis" => Framexaxis,
        "frameyaxis" => Frameyaxis,
        "framezaxis" => Framezaxis,
        "framelinvel" => Framelinvel,
        "frameangvel" => Frameangvel,
        "framelinacc" => Framelinacc,
        "frameangacc" => Frameangacc,
        "subtreecom" => Subtreecom,
        "subtreelinvel" => Subtreelinvel,
        "subtreeangmom" => Subtreeangmom,
        "gyro" => Gyro,
        "accelerometer" => Accelerometer,
        "velocimeter" => Velocimeter,
        "magnetometer" => Magnetometer,
        "touch" => Touch,
        "force" => Force,
        "torque" => Torque,
        "rangefinder" => Rangefinder,
        _ => return None,
    })
}

impl<'a, 'i> Converter<'a, 'i> {
    /// A `<site>`'s volume: its `type` (default sphere) and `size` (MuJoCo's default 0.005
    /// m for what is not given), which a touch sensor counts contacts in.
    pub(super) fn site_volume(
        &self,
        node: Node<'a, 'i>,
        class: Option<&str>,
    ) -> Result<gymfleet_assembly::SiteVolumeDef> {
        use gymfleet_assembly::SiteShape;
        let kind = match self.attr(node, class, "type").unwrap_or("sphere") {
            "sphere" => SiteShape::Sphere,
            "capsule" => SiteShape::Capsule,
            "cylinder" => SiteShape::Cylinder,
            "ellipsoid" => SiteShape::Ellipsoid,
            "box" => SiteShape::Box,
            other => {
                return Err(self.bad(
                    node,
                    "type",
                    format!("expected sphere, capsule, cylinder, ellipsoid or box, got {other:?}"),
                ))
            }
        };
        let given = self.numbers(node, class, "size")?.unwrap_or_default();
        let mut size = [0.005; 3];
        for (slot, v) in size.iter_mut().zip(&given) {
            if *v < 0.0 {
                return Err(self.bad(node, "size", format!("expected sizes ≥ 0, got {v}")));
            }
            *slot = *v;
        }
        Ok(gymfleet_assembly::SiteVolumeDef {
            kind,
            size: Vec3::from(size.map(|v| v * MM)),
        })
    }

    /// One `<sensor>` element's sensors, appended to [`Converter::sensors`]. An unnamed
    /// sensor is `sensor<index>`, its index among the model's sensors.
    pub(super) fn sensors(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for child in elements(node) {
            let tag = child.tag_name().name();
            let index = self.sensor_count;
            self.sensor_count += 1;
            let Some(kind) = sensor_type(tag) else {
                self.warn(
                    child,
                    format!("<{tag}> skipped: gymfleet has no such sensor yet (its values are missing from the readings)"),
                );
                continue;
            };
            let Some(mut def) = self.sensor_object(child, kind)? else {
                continue;
            };
            let wanted = child
                .attribute("name")
                .filter(|n| !n.is_empty())
                .map_or_else(|| format!("sensor{index}"), str::to_string);
            def.name = self.sensor_names_unique(&wanted);
            for (attr, slot) in [("cutoff", &mut def.cutoff), ("noise", &mut def.noise)] {
                if let Some(v) = self.number(child, None, attr)? {
                    if !(v.is_finite() && v >= 0.0) {
                        return Err(self.bad(
                            child,
                            attr,
                            format!("expected a number ≥ 0, got {v}"),
                        ));
                    }
                    *slot = (v > 0.0).then_some(v);
                }
            }
            self.sensors.push(def);
        }
        Ok(())
    }

    fn sensor_names_unique(&self, wanted: &str) -> String {
        let taken = |n: &str| self.sensors.iter().any(|s| s.name == n);
        if !taken(wanted) {
            return wanted.to_string();
        }
        (1..)
            .map(|k| format!("{wanted}_{k}"))
            .find(|n| !taken(n))
            .unwrap_or_default()
    }

    /// What the sensor reads, from its attributes; `None` (warned) when the conversion has
    /// nothing for it.
    fn sensor_object(&mut self, node: Node<'a, 'i>, kind: SensorType) -> Result<Option<SensorDef>> {
        let mut def = SensorDef {
            name: String::new(),
            kind,
            joint: None,
            actuator: None,
            tendon: None,
            site: None,
            instance: None,
            reference: None,
            cutoff: None,
            noise: None,
        };
        let need = |attr: &str| {
            node.attribute(attr)
                .map(str::to_string)
                .ok_or_else(|| self.bad(node, attr, "missing".into()))
        };
        use SensorType::*;
        match kind {
            Jointpos | Jointvel => {
                let joint = need("joint")?;
                let scalar = self.qpos_slots.iter().any(
                    |s| matches!(s, keyframes::QposSlot::Joint { name, .. } if *name == joint),
                );
                if !scalar {
                    return Err(self.bad(
                        node,
                        "joint",
                        format!("no hinge or slide joint is named {joint:?}"),
                    ));
                }
                def.joint = Some(joint);
            }
            Actuatorfrc => {
                let name = need("actuator")?;
                // Plain joint motors are their joints' own actions.
                let direct = self.direct_motor_joint(&name);
                def.actuator = Some(direct.unwrap_or(name));
            }
            Tendonpos | Tendonvel => def.tendon = Some(need("tendon")?),
            Subtreecom | Subtreelinvel | Subtreeangmom => {
                let body = need("body")?;
                match self.bodies.get(&body) {
                    Some((instance, _)) => def.instance = Some(instance.clone()),
                    None => {
                        return Err(self.bad(node, "body", format!("no body is named {body:?}")))
                    }
                }
            }
            Framepos | Framequat | Framexaxis | Frameyaxis | Framezaxis | Framelinvel
            | Frameangvel | Framelinacc | Frameangacc => {
                let object = self.sensor_frame(node, "objtype", "objname")?;
                let Some(object) = object else {
                    return Ok(None);
                };
                (def.site, def.instance) = (object.site, object.instance);
                if node.attribute("refname").is_some() {
                    let Some(r) = self.sensor_frame(node, "reftype", "refname")? else {
                        return Ok(None);
                    };
                    def.reference = Some(r);
                }
            }
            _ => {
                let site = need("site")?;
                match self.site_of.get(&site) {
                    Some(kept) => def.site = Some(kept.clone()),
                    None => {
                        return Err(self.bad(node, "site", format!("no site is named {site:?}")))
                    }
                }
            }
        }
        Ok(Some(def))
    }

    /// The joint a plain `<motor>` named `name` drives, when the motors are the joints' own
    /// actions (no `assembly.actuators`).
    fn direct_motor_joint(&self, name: &str) -> Option<String> {
        if !self.direct_motors() {
            return None;
        }
        self.actuator_list
            .iter()
            .find(|a| a.name == name)
            .and_then(|a| a.joint.clone())
    }

    /// A frame a frame sensor names with `type_attr` and `name_attr`.
    fn sensor_frame(
        &mut self,
        node: Node<'a, 'i>,
        type_attr: &str,
        name_attr: &str,
    ) -> Result<Option<SensorFrameDef>> {
        let Some(name) = node.attribute(name_attr).map(str::to_string) else {
            return Err(self.bad(node, name_attr, "missing".into()));
        };
        let kind = node.attribute(type_attr).unwrap_or("");
        let (site, instance) = match kind {
            "site" => (self.site_of.get(&name).cloned(), None),
            "xbody" => (self.body_sites.get(&name).cloned(), None),
            "geom" => (None, self.geom_instances.get(&name).cloned()),
            "body" | "camera" => {
                self.warn(
                    node,
                    format!("skipped: {type_attr}=\"{kind}\" (MuJoCo's inertial body frame, or a camera) is not converted yet; xbody reads the body's origin"),
                );
                return Ok(None);
            }
            other => {
                return Err(self.bad(
                    node,
                    type_attr,
                    format!("expected site, xbody, body, geom or camera, got {other:?}"),
                ))
            }
        };
        if site.is_none() && instance.is_none() {
            return Err(self.bad(node, name_attr, format!("no {kind} is named {name:?}")));
        }
        Ok(Some(SensorFrameDef { site, instance }))
    }
}
