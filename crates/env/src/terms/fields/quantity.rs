//! A quantity as written: one kind field and its modifiers, converted into
//! [`Quantity`] and back (see the parent module).

use gymfleet_physics::{INERTIA_LEN, VELOCITY_LEN, WRENCH_LEN};
use serde::{Deserialize, Serialize};

use super::super::{Axis, Frame, Point, Quantity};
use super::{checked_point, FieldError};

/// A quantity as written: one kind field (`joint`, `site`, …) and the modifiers it takes
/// (`component`, `axis`, `point`, `frame_axis`, `relative_to`). The fields' meanings are
/// the [`Quantity`] variants'.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub(in crate::terms) struct QuantityFields {
    joint: Option<String>,
    joint_velocity: Option<String>,
    joint_limit_force: Option<String>,
    tendon_length: Option<String>,
    tendon_velocity: Option<String>,
    contact_wrench: Option<Vec<String>>,
    body_inertia: Option<Vec<String>>,
    body_velocity: Option<Vec<String>>,
    body_center: Option<Vec<String>>,
    actuator_force: Option<String>,
    actuator: Option<String>,
    actuator_activation: Option<String>,
    sensor: Option<String>,
    component: Option<usize>,
    instance: Option<String>,
    point: Option<[f64; 3]>,
    site: Option<String>,
    center_of_mass: bool,
    axis: Option<Axis>,
    frame_axis: Option<Axis>,
    action: Option<usize>,
    relative_to: Option<String>,
}

/// What `relative_to` is refused with where it does not apply.
const RELATIVE_TO: &str =
    "an offset from a site belongs to a site, or an instance (with an optional point)";

impl QuantityFields {
    /// Exactly one kind, and modifiers only where a kind takes them.
    fn shape(&self) -> Result<(), FieldError> {
        let set = [
            self.joint.is_some(),
            self.joint_velocity.is_some(),
            self.joint_limit_force.is_some(),
            self.tendon_length.is_some(),
            self.tendon_velocity.is_some(),
            self.actuator_force.is_some(),
            self.actuator.is_some(),
            self.actuator_activation.is_some(),
            self.sensor.is_some(),
            self.contact_wrench.is_some(),
            self.body_inertia.is_some(),
            self.body_velocity.is_some(),
            self.body_center.is_some(),
            self.instance.is_some(),
            self.site.is_some(),
            self.center_of_mass,
            self.action.is_some(),
        ];
        if set.iter().filter(|s| **s).count() != 1 {
            return Err(FieldError::new(
                "",
                "expected exactly one of joint, joint_velocity, joint_limit_force, \
                 tendon_length, tendon_velocity, actuator_force, actuator, actuator_activation, \
                 sensor (with a component when it reports several), contact_wrench, body_inertia, body_velocity (the last three with a component), body_center, instance, site or \
                 center_of_mass (the last four with an axis), or action",
            ));
        }
        if self.component.is_some()
            && self.contact_wrench.is_none()
            && self.body_inertia.is_none()
            && self.body_velocity.is_none()
            && self.sensor.is_none()
        {
            return Err(FieldError::new(
                "component",
                "a component belongs to a contact_wrench, body_inertia, body_velocity or sensor",
            ));
        }
        if self.frame_axis.is_some() && self.relative_to.is_some() {
            return Err(FieldError::new(
                "relative_to",
                "a frame axis is read in the world: it takes no relative_to",
            ));
        }
        let framed = self.instance.is_some() || self.site.is_some();
        if self.frame_axis.is_some() && !framed {
            return Err(FieldError::new(
                "frame_axis",
                "a frame axis belongs to an instance or a site",
            ));
        }
        if self.relative_to.is_some() && !framed {
            return Err(FieldError::new("relative_to", RELATIVE_TO));
        }
        Ok(())
    }

    /// A kind that takes no axis or point refuses either.
    fn no_geometry(&self, what: &str) -> Result<(), FieldError> {
        if self.axis.is_some() || self.point.is_some() {
            return Err(FieldError::new(
                "",
                format!(
                    "a {what} takes no axis or point (they are for instance, site and center_of_mass)"
                ),
            ));
        }
        Ok(())
    }

    /// The axis a point's coordinate is read along.
    fn axis(&self) -> Result<Axis, FieldError> {
        self.axis.ok_or_else(|| {
            FieldError::new(
                "axis",
                "a point's coordinate needs an axis: \"x\", \"y\" or \"z\"",
            )
        })
    }

    /// The point of an instance, each coordinate finite and bounded (mm).
    fn point(&self) -> Result<Option<[f64; 3]>, FieldError> {
        checked_point(self.point)
    }

    /// A component below `len`, of a body's or a group's `what`.
    fn component(&self, len: usize, what: &str) -> Result<usize, FieldError> {
        match self.component {
            Some(c) if c < len => Ok(c),
            other => Err(FieldError::new(
                "component",
                format!(
                    "expected a component 0 to {} ({what}), got {}",
                    len - 1,
                    other.map_or("none".to_string(), |c| c.to_string())
                ),
            )),
        }
    }

    /// The kinds read from a group of instances.
    fn group(&mut self) -> Result<Option<Quantity>, FieldError> {
        if let Some(instances) = self.body_inertia.take() {
            self.no_geometry("body_inertia")?;
            let what = "inertia (xx, yy, zz, xy, xz, yz), mass × offset (x, y, z), mass";
            let component = self.component(INERTIA_LEN, what)?;
            return Ok(Some(Quantity::BodyInertia {
                instances,
                component,
            }));
        }
        if let Some(instances) = self.body_velocity.take() {
            self.no_geometry("body_velocity")?;
            let what = "angular velocity (x, y, z), linear velocity (x, y, z)";
            let component = self.component(VELOCITY_LEN, what)?;
            return Ok(Some(Quantity::BodyVelocity {
                instances,
                component,
            }));
        }
        if let Some(instances) = self.body_center.take() {
            if self.point.is_some() {
                return Err(FieldError::new(
                    "point",
                    "a body's centre of mass takes no point",
                ));
            }
            let axis = self.axis()?;
            return Ok(Some(Quantity::BodyCenter { instances, axis }));
        }
        if let Some(instances) = self.contact_wrench.take() {
            self.no_geometry("contact wrench")?;
            let what = "torque x, y, z, force x, y, z";
            let component = self.component(WRENCH_LEN, what)?;
            return Ok(Some(Quantity::ContactWrench {
                instances,
                component,
            }));
        }
        Ok(None)
    }

    /// The kinds read at a point or a frame: an instance's, a site's, the robot's centre
    /// of mass.
    fn located(mut self) -> Result<Quantity, FieldError> {
        if let Some(local) = self.frame_axis {
            if self.point.is_some() {
                return Err(FieldError::new(
                    "point",
                    "a frame axis is the frame's own: it takes no point",
                ));
            }
            let axis = self.axis()?;
            let frame = match (self.instance.take(), self.site.take()) {
                (Some(name), _) => Frame::Instance(name),
                (None, site) => Frame::Site(site.expect("shape: an instance or a site")),
            };
            return Ok(Quantity::FrameAxis { frame, local, axis });
        }
        if let Some(site) = self.relative_to.take() {
            let at = match (self.instance.take(), self.site.take()) {
                (Some(name), None) => Point::Instance {
                    name,
                    point: self.point()?,
                },
                (None, Some(name)) if self.point.is_none() => Point::Site(name),
                _ => return Err(FieldError::new("relative_to", RELATIVE_TO)),
            };
            let axis = self.axis()?;
            return Ok(Quantity::Relative { at, site, axis });
        }
        if let Some(name) = self.instance.take() {
            let point = self.point()?;
            let axis = self.axis()?;
            return Ok(Quantity::Point {
                at: Point::Instance { name, point },
                axis,
            });
        }
        if self.point.is_some() {
            return Err(FieldError::new(
                "point",
                "a point belongs to an instance: a site and the robot's centre of mass take none",
            ));
        }
        let axis = self.axis()?;
        Ok(match self.site.take() {
            Some(name) => Quantity::Point {
                at: Point::Site(name),
                axis,
            },
            None => Quantity::CenterOfMass(axis),
        })
    }
}

impl TryFrom<QuantityFields> for Quantity {
    type Error = FieldError;

    fn try_from(mut q: QuantityFields) -> Result<Self, FieldError> {
        q.shape()?;
        if let Some(k) = q.action {
            q.no_geometry("action value")?;
            return Ok(Quantity::Action(k));
        }
        type Named = fn(String) -> Quantity;
        let named: [(Option<String>, &str, Named); 8] = [
            (q.joint.take(), "joint position", Quantity::Joint),
            (
                q.joint_velocity.take(),
                "joint velocity",
                Quantity::JointVelocity,
            ),
            (
                q.joint_limit_force.take(),
                "joint limit force",
                Quantity::JointLimitForce,
            ),
            (
                q.tendon_length.take(),
                "tendon length",
                Quantity::TendonLength,
            ),
            (
                q.tendon_velocity.take(),
                "tendon velocity",
                Quantity::TendonVelocity,
            ),
            (
                q.actuator_force.take(),
                "actuator force",
                Quantity::ActuatorForce,
            ),
            (
                q.actuator.take(),
                "named actuator's force",
                Quantity::Actuator,
            ),
            (
                q.actuator_activation.take(),
                "named actuator's activation",
                Quantity::ActuatorActivation,
            ),
        ];
        for (name, what, make) in named {
            if let Some(name) = name {
                q.no_geometry(what)?;
                return Ok(make(name));
            }
        }
        if let Some(name) = q.sensor.take() {
            q.no_geometry("sensor")?;
            return Ok(Quantity::Sensor {
                name,
                component: q.component,
            });
        }
        match q.group()? {
            Some(quantity) => Ok(quantity),
            None => q.located(),
        }
    }
}

impl From<Quantity> for QuantityFields {
    fn from(q: Quantity) -> Self {
        let mut f = QuantityFields::default();
        let point_at = |f: &mut QuantityFields, at: Point| match at {
            Point::Instance { name, point } => {
                f.instance = Some(name);
                f.point = point;
            }
            Point::Site(name) => f.site = Some(name),
        };
        match q {
            Quantity::Joint(n) => f.joint = Some(n),
            Quantity::JointVelocity(n) => f.joint_velocity = Some(n),
            Quantity::JointLimitForce(n) => f.joint_limit_force = Some(n),
            Quantity::TendonLength(n) => f.tendon_length = Some(n),
            Quantity::TendonVelocity(n) => f.tendon_velocity = Some(n),
            Quantity::ActuatorForce(n) => f.actuator_force = Some(n),
            Quantity::Actuator(n) => f.actuator = Some(n),
            Quantity::ActuatorActivation(n) => f.actuator_activation = Some(n),
            Quantity::Sensor { name, component } => {
                f.sensor = Some(name);
                f.component = component;
            }
            Quantity::ContactWrench {
                instances,
                component,
            } => {
                f.contact_wrench = Some(instances);
                f.component = Some(component);
            }
            Quantity::BodyInertia {
                instances,
                component,
            } => {
                f.body_inertia = Some(instances);
                f.component = Some(component);
            }
            Quantity::BodyVelocity {
                instances,
                component,
            } => {
                f.body_velocity = Some(instances);
                f.component = Some(component);
            }
            Quantity::BodyCenter { instances, axis } => {
                f.body_center = Some(instances);
                f.axis = Some(axis);
            }
            Quantity::Point { at, axis } => {
                point_at(&mut f, at);
                f.axis = Some(axis);
            }
            Quantity::FrameAxis { frame, local, axis } => {
                match frame {
                    Frame::Instance(n) => f.instance = Some(n),
                    Frame::Site(n) => f.site = Some(n),
                }
                f.frame_axis = Some(local);
                f.axis = Some(axis);
            }
            Quantity::Relative { at, site, axis } => {
                point_at(&mut f, at);
                f.relative_to = Some(site);
                f.axis = Some(axis);
            }
            Quantity::CenterOfMass(axis) => {
                f.center_of_mass = true;
                f.axis = Some(axis);
            }
            Quantity::Action(k) => f.action = Some(k),
        }
        f
    }
}
