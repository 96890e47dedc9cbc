//! A terms task's coordinates and points checked against one env ([`Context`]): joint,
//! tendon, instance and site names into indices, groups of instances registered once, and
//! each coordinate (`Quantity`) into what the active terms read (`Q`).

use super::active::Q;
use super::resolve::{instance, Context};
use super::{bad, Axis, Frame, Point, Quantity};
use crate::error::Result;

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

    /// A point: its instance, and its point in the instance's frame (a site's, or the
    /// instance's; `None`: the instance's centre of mass).
    pub(super) fn end(&self, path: &str, p: &Point) -> Result<(usize, Option<[f64; 3]>)> {
        match p {
            Point::Instance { name, point } => {
                Ok((self.instance(&format!("{path}.instance"), name)?, *point))
            }
            Point::Site(name) => {
                let (body, point) = self.site(&format!("{path}.site"), name)?;
                Ok((body, Some(point)))
            }
        }
    }

    /// What the active terms read for a quantity: its names looked up, its action index
    /// and sensor component checked (the rest of its shape holds by construction).
    pub(super) fn quantity(&self, path: &str, q: &Quantity) -> Result<Q> {
        let at = |field: &str| format!("{path}.{field}");
        Ok(match q {
            Quantity::Joint(name) => Q::Position(self.joint(&at("joint"), name)?),
            Quantity::JointVelocity(name) => Q::Velocity(self.joint(&at("joint_velocity"), name)?),
            Quantity::JointLimitForce(name) => {
                Q::LimitForce(self.joint(&at("joint_limit_force"), name)?)
            }
            Quantity::TendonLength(name) => {
                Q::TendonLength(self.tendon(&at("tendon_length"), name)?)
            }
            Quantity::TendonVelocity(name) => {
                Q::TendonVelocity(self.tendon(&at("tendon_velocity"), name)?)
            }
            Quantity::ActuatorForce(name) => {
                Q::ActuatorForce(self.joint(&at("actuator_force"), name)?)
            }
            Quantity::Actuator(name) => Q::Actuator(self.actuator(&at("actuator"), name)?),
            Quantity::ActuatorActivation(name) => {
                Q::Activation(self.actuator(&at("actuator_activation"), name)?)
            }
            Quantity::Sensor { name, component } => self.sensor(path, name, *component)?,
            Quantity::ContactWrench {
                instances,
                component,
            } => Q::ContactWrench {
                group: self.group(&at("contact_wrench"), instances)?,
                component: *component,
            },
            Quantity::BodyInertia {
                instances,
                component,
            } => Q::BodyInertia {
                group: self.group(&at("body_inertia"), instances)?,
                component: *component,
            },
            Quantity::BodyVelocity {
                instances,
                component,
            } => Q::BodyVelocity {
                group: self.group(&at("body_velocity"), instances)?,
                component: *component,
            },
            Quantity::BodyCenter { instances, axis } => Q::BodyCenter {
                group: self.group(&at("body_center"), instances)?,
                axis: *axis as usize,
            },
            Quantity::Point { at: p, axis } => {
                let (body, point) = self.end(path, p)?;
                Q::Point {
                    body,
                    point,
                    axis: *axis as usize,
                }
            }
            Quantity::FrameAxis { frame, local, axis } => {
                self.frame_axis(path, frame, *local, *axis)?
            }
            Quantity::Relative { at: p, site, axis } => self.relative(path, p, site, *axis)?,
            Quantity::CenterOfMass(axis) => Q::CenterOfMass(*axis as usize),
            Quantity::Action(k) => {
                if *k >= self.action_dim {
                    return Err(bad(
                        at("action"),
                        format!(
                            "expected an action index below the action's length ({}), got {k}",
                            self.action_dim
                        ),
                    ));
                }
                Q::Action(*k)
            }
        })
    }

    /// `relative_to`: a point's offset from a site, along the site's own axis.
    fn relative(&self, path: &str, p: &Point, site: &str, axis: Axis) -> Result<Q> {
        let (body, point) = self.end(path, p)?;
        Ok(Q::Relative {
            body,
            point,
            frame: self.site_frame(&format!("{path}.relative_to"), site)?,
            axis: axis as usize,
        })
    }

    /// `frame_axis`: the world `axis` component of an instance's or a site's own axis.
    fn frame_axis(&self, path: &str, frame: &Frame, local: Axis, axis: Axis) -> Result<Q> {
        let (body, rotation) = match frame {
            Frame::Instance(name) => (self.instance(&format!("{path}.instance"), name)?, [0.0; 3]),
            Frame::Site(name) => {
                let (body, _, rotation) = self.site_frame(&format!("{path}.site"), name)?;
                (body, rotation)
            }
        };
        Ok(Q::FrameAxis {
            body,
            rotation,
            local: local as usize,
            axis: axis as usize,
        })
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
}
