//! `<actuator>`: each `<motor>` drives a joint; its `gear` is kept (actions are MuJoCo's
//! ctrl) and its ctrl and force ranges bound the joint's `max_effort`.

use super::*;

impl<'a, 'i> Converter<'a, 'i> {
    pub(super) fn actuators(&mut self, node: Node<'a, 'i>) -> Result<()> {
        for (order, motor) in elements(node).enumerate() {
            if motor.tag_name().name() != "motor" {
                return Err(self.unsupported(
                    motor,
                    "only <motor> actuators are supported (a torque or force at a joint)".into(),
                ));
            }
            let Some(joint) = self.attr(motor, None, "joint") else {
                return Err(self.unsupported(
                    motor,
                    "a motor must drive a joint (tendon, site and body transmissions are not supported)".into(),
                ));
            };
            let gear = self
                .numbers(motor, None, "gear")?
                .and_then(|g| g.first().copied())
                .unwrap_or(1.0);
            let bound = |range: Option<[f64; 2]>, limited: Option<bool>| match (range, limited) {
                (Some([lo, hi]), Some(true) | None) if lo < hi => Some(lo.abs().max(hi.abs())),
                _ => None,
            };
            let ctrl = bound(
                self.exactly::<2>(motor, None, "ctrlrange")?,
                self.flag(motor, None, "ctrllimited")?,
            )
            .map(|c| c * gear.abs());
            let force = bound(
                self.exactly::<2>(motor, None, "forcerange")?,
                self.flag(motor, None, "forcelimited")?,
            );
            let max_effort = match (ctrl, force) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            }
            .filter(|e| *e > 0.0);
            let line = self.line(motor);
            if self
                .motors
                .insert(
                    joint.to_string(),
                    Motor {
                        max_effort,
                        gear,
                        order,
                        line,
                    },
                )
                .is_some()
            {
                return Err(self.unsupported(motor, format!("joint {joint:?} has a second motor")));
            }
        }
        Ok(())
    }
}
