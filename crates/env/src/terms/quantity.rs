//! A terms task's coordinates and points checked against one env ([`Context`]): joint,
//! tendon, instance and site names into indices, groups of instances registered once, and
//! each coordinate (`Quantity`) into what the active terms read (`Q`).

use super::active::Q;
use super::resolve::{instance, Context};
use super::{bad, bounded, Point, Quantity};
use crate::error::Result;
use gymfleet_physics::{INERTIA_LEN, VELOCITY_LEN, WRENCH_LEN};

impl Context<'_> {
    pub(super) fn tendon(&self, path: &str, name: &str) -> Result<usize> {
        let names: Vec<&str> = self
            .assembly
            .tendons
            .iter()
            .map(|t| t.name.as_str())
            .collect();
        named(path, "tendon", &names, name)
    }

    pub(super) fn actuator(&self, path: &str, name: &str) -> Result<usize> {
        let names: Vec<&str> = self
            .assembly
            .actuators
            .iter()
            .map(|a| a.name.as_str())
            .collect();
        named(path, "actuator", &names, name)
    }
}

/// The index of `name` among `names` (a document's tendons or actuators), or an error
/// that lists the first of them.
fn named(path: &str, what: &str, names: &[&str], name: &str) -> Result<usize> {
    {
        if let Some(k) = names.iter().position(|t| *t == name) {
            return Ok(k);
        }
        let listed: Vec<String> = names.iter().take(16).map(|t| format!("{t:?}")).collect();
        let more = if names.len() > listed.len() {
            format!(" and {} more", names.len() - listed.len())
        } else {
            String::new()
        };
        let name: String = name.chars().take(64).collect();
        Err(bad(
            path,
            if names.is_empty() {
                format!("unknown {what} {name:?} (the document has no {what}s)")
            } else {
                format!(
                    "unknown {what} {name:?} ({what}s: {}{more})",
                    listed.join(", ")
                )
            },
        ))
    }
}

impl Context<'_> {
    pub(super) fn joint(&self, path: &str, name: &str) -> Result<usize> {
        if let Some(k) = self.dofs.iter().position(|d| d.joint_name == name) {
            return Ok(k);
        }
        let mut names: Vec<String> = Vec::new();
        for d in self.dofs {
            let quoted = format!("{:?}", d.joint_name);
            if !names.contains(&quoted) {
                names.push(quoted);
            }
        }
        let shown = names.len().min(16);
        let more = if names.len() > shown {
            format!(" and {} more", names.len() - shown)
        } else {
            String::new()
        };
        let name: String = name.chars().take(64).collect();
        Err(bad(
            path,
            format!(
                "unknown joint {name:?} (joints with a DOF: {}{more})",
                names[..shown].join(", ")
            ),
        ))
    }

    pub(super) fn instance(&self, path: &str, name: &str) -> Result<usize> {
        instance(self.assembly, path, name)
    }

    /// A site's instance and point.
    pub(super) fn site(&self, path: &str, name: &str) -> Result<(usize, [f64; 3])> {
        match self.assembly.site_index(name) {
            Some(k) => {
                let site = &self.assembly.sites[k];
                Ok((site.instance, site.point))
            }
            None => {
                let names: Vec<&str> = self
                    .assembly
                    .sites
                    .iter()
                    .map(|s| s.name.as_str())
                    .collect();
                Err(bad(
                    path,
                    format!(
                        "unknown site {} (sites: {})",
                        gymfleet_assembly::quoted(name),
                        if names.is_empty() {
                            "none: the document has no assembly.sites".to_string()
                        } else {
                            gymfleet_assembly::quoted_list(&names)
                        }
                    ),
                ))
            }
        }
    }

    /// A distance term's point.
    pub(super) fn end(&self, path: &str, p: &Point) -> Result<(usize, Option<[f64; 3]>)> {
        match (&p.instance, &p.site) {
            (Some(name), None) => Ok((
                self.instance(&format!("{path}.instance"), name)?,
                self.point(&format!("{path}.point"), p.point)?,
            )),
            (None, Some(name)) if p.point.is_none() => {
                let (body, point) = self.site(&format!("{path}.site"), name)?;
                Ok((body, Some(point)))
            }
            _ => Err(bad(
                path,
                "expected a site, or an instance (with an optional point)",
            )),
        }
    }

    pub(super) fn point(&self, path: &str, point: Option<[f64; 3]>) -> Result<Option<[f64; 3]>> {
        if let Some(p) = point {
            for (k, c) in p.iter().enumerate() {
                bounded(&format!("{path}[{k}]"), *c, "coordinate (mm)")?;
            }
        }
        Ok(point)
    }

    pub(super) fn quantity(&self, path: &str, q: &Quantity) -> Result<Q> {
        let set = [
            q.joint.is_some(),
            q.joint_velocity.is_some(),
            q.joint_limit_force.is_some(),
            q.tendon_length.is_some(),
            q.tendon_velocity.is_some(),
            q.actuator_force.is_some(),
            q.actuator.is_some(),
            q.actuator_activation.is_some(),
            q.sensor.is_some(),
            q.contact_wrench.is_some(),
            q.body_inertia.is_some(),
            q.body_velocity.is_some(),
            q.body_center.is_some(),
            q.instance.is_some(),
            q.site.is_some(),
            q.center_of_mass,
            q.action.is_some(),
        ];
        if set.iter().filter(|s| **s).count() != 1 {
            return Err(bad(
                path,
                "expected exactly one of joint, joint_velocity, joint_limit_force, \
                 tendon_length, tendon_velocity, actuator_force, actuator, actuator_activation, \
                 sensor (with a component when it reports several), contact_wrench, body_inertia, body_velocity (the last three with a component), body_center, instance, site or \
                 center_of_mass (the last four with an axis), or action",
            ));
        }
        let axis = || {
            q.axis.map(|a| a as usize).ok_or_else(|| {
                bad(
                    format!("{path}.axis"),
                    "a point's coordinate needs an axis: \"x\", \"y\" or \"z\"",
                )
            })
        };
        if q.component.is_some()
            && q.contact_wrench.is_none()
            && q.body_inertia.is_none()
            && q.body_velocity.is_none()
            && q.sensor.is_none()
        {
            return Err(bad(
                format!("{path}.component"),
                "a component belongs to a contact_wrench, body_inertia, body_velocity or sensor",
            ));
        }
        let no_geometry = |what: &str| -> Result<()> {
            if q.axis.is_some() || q.point.is_some() {
                return Err(bad(
                    path,
                    format!("a {what} takes no axis or point (they are for instance, site and center_of_mass)"),
                ));
            }
            Ok(())
        };
        if q.frame_axis.is_some() && q.relative_to.is_some() {
            return Err(bad(
                format!("{path}.relative_to"),
                "a frame axis is read in the world: it takes no relative_to",
            ));
        }
        if q.frame_axis.is_some() && q.instance.is_none() && q.site.is_none() {
            return Err(bad(
                format!("{path}.frame_axis"),
                "a frame axis belongs to an instance or a site",
            ));
        }
        if let Some(k) = q.action {
            no_geometry("action value")?;
            if k >= self.action_dim {
                return Err(bad(
                    format!("{path}.action"),
                    format!(
                        "expected an action index below the action's length ({}), got {k}",
                        self.action_dim
                    ),
                ));
            }
            return Ok(Q::Action(k));
        }
        if let Some(name) = &q.joint {
            no_geometry("joint position")?;
            return Ok(Q::Position(self.joint(&format!("{path}.joint"), name)?));
        }
        if let Some(name) = &q.joint_velocity {
            no_geometry("joint velocity")?;
            return Ok(Q::Velocity(
                self.joint(&format!("{path}.joint_velocity"), name)?,
            ));
        }
        if let Some(name) = &q.joint_limit_force {
            no_geometry("joint limit force")?;
            return Ok(Q::LimitForce(
                self.joint(&format!("{path}.joint_limit_force"), name)?,
            ));
        }
        if let Some(name) = &q.tendon_length {
            no_geometry("tendon length")?;
            return Ok(Q::TendonLength(
                self.tendon(&format!("{path}.tendon_length"), name)?,
            ));
        }
        if let Some(name) = &q.tendon_velocity {
            no_geometry("tendon velocity")?;
            return Ok(Q::TendonVelocity(
                self.tendon(&format!("{path}.tendon_velocity"), name)?,
            ));
        }
        if let Some(name) = &q.actuator_force {
            no_geometry("actuator force")?;
            return Ok(Q::ActuatorForce(
                self.joint(&format!("{path}.actuator_force"), name)?,
            ));
        }
        if let Some(name) = &q.actuator {
            no_geometry("named actuator's force")?;
            return Ok(Q::Actuator(
                self.actuator(&format!("{path}.actuator"), name)?,
            ));
        }
        if let Some(name) = &q.actuator_activation {
            no_geometry("named actuator's activation")?;
            return Ok(Q::Activation(
                self.actuator(&format!("{path}.actuator_activation"), name)?,
            ));
        }
        if let Some(name) = &q.sensor {
            no_geometry("sensor")?;
            return self.sensor(path, name, q.component);
        }
        for (field, names, len, what) in [
            (
                "body_inertia",
                &q.body_inertia,
                INERTIA_LEN,
                "inertia (xx, yy, zz, xy, xz, yz), mass × offset (x, y, z), mass",
            ),
            (
                "body_velocity",
                &q.body_velocity,
                VELOCITY_LEN,
                "angular velocity (x, y, z), linear velocity (x, y, z)",
            ),
        ] {
            let Some(names) = names else { continue };
            no_geometry(field)?;
            let component = match q.component {
                Some(c) if c < len => c,
                other => {
                    return Err(bad(
                        format!("{path}.component"),
                        format!(
                            "expected a component 0 to {} ({what}), got {}",
                            len - 1,
                            other.map_or("none".to_string(), |c| c.to_string())
                        ),
                    ))
                }
            };
            let group = self.group(&format!("{path}.{field}"), names)?;
            return Ok(if field == "body_inertia" {
                Q::BodyInertia { group, component }
            } else {
                Q::BodyVelocity { group, component }
            });
        }
        if let Some(names) = &q.body_center {
            if q.point.is_some() {
                return Err(bad(
                    format!("{path}.point"),
                    "a body's centre of mass takes no point",
                ));
            }
            let axis = axis()?;
            let group = self.group(&format!("{path}.body_center"), names)?;
            return Ok(Q::BodyCenter { group, axis });
        }
        if let Some(names) = &q.contact_wrench {
            no_geometry("contact wrench")?;
            let component = match q.component {
                Some(c) if c < WRENCH_LEN => c,
                other => {
                    return Err(bad(
                        format!("{path}.component"),
                        format!(
                            "expected a component 0 to 5 (torque x, y, z, force x, y, z), got {}",
                            other.map_or("none".to_string(), |c| c.to_string())
                        ),
                    ))
                }
            };
            let group = self.group(&format!("{path}.contact_wrench"), names)?;
            return Ok(Q::ContactWrench { group, component });
        }
        if let (Some(local), Some(name)) = (q.frame_axis, q.instance.as_ref().or(q.site.as_ref())) {
            return self.frame_axis(path, q, local as usize, name, &axis);
        }
        if let Some(frame) = &q.relative_to {
            return self.relative(path, q, frame, &axis);
        }
        if let Some(name) = &q.instance {
            return Ok(Q::Point {
                body: self.instance(&format!("{path}.instance"), name)?,
                point: self.point(&format!("{path}.point"), q.point)?,
                axis: axis()?,
            });
        }
        if q.point.is_some() {
            return Err(bad(
                format!("{path}.point"),
                "a point belongs to an instance: a site and the robot's centre of mass take none",
            ));
        }
        if let Some(name) = &q.site {
            let (body, point) = self.site(&format!("{path}.site"), name)?;
            return Ok(Q::Point {
                body,
                point: Some(point),
                axis: axis()?,
            });
        }
        Ok(Q::CenterOfMass(axis()?))
    }

    /// A sensor's component, as its offset in the sensors' readings.
    fn sensor(&self, path: &str, name: &str, component: Option<usize>) -> Result<Q> {
        let sensors = &self.assembly.sensors;
        let names: Vec<&str> = sensors.iter().map(|s| s.name.as_str()).collect();
        let k = named(&format!("{path}.sensor"), "sensor", &names, name)?;
        let dim = sensors[k].kind.dim();
        let component = match component {
            Some(c) if c < dim => c,
            None if dim == 1 => 0,
            other => {
                return Err(bad(
                    format!("{path}.component"),
                    format!(
                        "sensor {name:?} ({}) reports {dim} values: expected a component 0 to {}, got {}",
                        sensors[k].kind.as_str(),
                        dim - 1,
                        other.map_or("none".to_string(), |c| c.to_string())
                    ),
                ))
            }
        };
        let offset: usize = sensors[..k].iter().map(|s| s.kind.dim()).sum();
        Ok(Q::Sensor(offset + component))
    }

    /// Registers a group of instances whose contact wrenches are summed; returns its index.
    pub(super) fn group(&self, path: &str, names: &[String]) -> Result<usize> {
        if names.len() > self.assembly.instances.len() {
            return Err(bad(
                path,
                format!(
                    "expected at most the number of instances ({}), got {}",
                    self.assembly.instances.len(),
                    names.len()
                ),
            ));
        }
        let mut group = Vec::with_capacity(names.len());
        for (k, name) in names.iter().enumerate() {
            let i = self.instance(&format!("{path}[{k}]"), name)?;
            if group.contains(&i) {
                return Err(bad(format!("{path}[{k}]"), "the instance is listed twice"));
            }
            group.push(i);
        }
        let mut groups = self.groups.borrow_mut();
        if let Some(g) = groups.iter().position(|g| *g == group) {
            return Ok(g);
        }
        groups.push(group);
        Ok(groups.len() - 1)
    }
}

impl Context<'_> {
    /// A site's instance, point and rotation.
    pub(super) fn site_frame(&self, path: &str, name: &str) -> Result<(usize, [f64; 3], [f64; 3])> {
        let (body, point) = self.site(path, name)?;
        let rotation =
            self.assembly.sites[self.assembly.site_index(name).expect("resolved")].rotation;
        Ok((body, point, rotation))
    }

    /// `frame_axis`: the world `axis` component of an instance's or site's own axis `local`.
    fn frame_axis(
        &self,
        path: &str,
        q: &Quantity,
        local: usize,
        name: &str,
        axis: &dyn Fn() -> Result<usize>,
    ) -> Result<Q> {
        if q.point.is_some() {
            return Err(bad(
                format!("{path}.point"),
                "a frame axis is the frame's own: it takes no point",
            ));
        }
        let (body, rotation) = match &q.instance {
            Some(name) => (self.instance(&format!("{path}.instance"), name)?, [0.0; 3]),
            None => {
                let (body, _, rotation) = self.site_frame(&format!("{path}.site"), name)?;
                (body, rotation)
            }
        };
        Ok(Q::FrameAxis {
            body,
            rotation,
            local,
            axis: axis()?,
        })
    }

    /// `relative_to`: a point's offset from a site, along the site's own axis.
    fn relative(
        &self,
        path: &str,
        q: &Quantity,
        frame: &str,
        axis: &dyn Fn() -> Result<usize>,
    ) -> Result<Q> {
        let (body, point) = match (&q.instance, &q.site) {
            (Some(name), None) => (
                self.instance(&format!("{path}.instance"), name)?,
                self.point(&format!("{path}.point"), q.point)?,
            ),
            (None, Some(name)) if q.point.is_none() => {
                let (body, point) = self.site(&format!("{path}.site"), name)?;
                (body, Some(point))
            }
            _ => return Err(bad(
                format!("{path}.relative_to"),
                "an offset from a site belongs to a site, or an instance (with an optional point)",
            )),
        };
        let (fbody, fpoint, rotation) = self.site_frame(&format!("{path}.relative_to"), frame)?;
        Ok(Q::Relative {
            body,
            point,
            frame: (fbody, fpoint, rotation),
            axis: axis()?,
        })
    }
}
