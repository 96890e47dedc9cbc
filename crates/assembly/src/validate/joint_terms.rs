//! One joint's terms, checked and in SI: axis, limits, initial position, gear and
//! reference, DOF quantities (damping, friction, armature), spring.

use crate::document::JointDef;
use crate::error::shown;
use crate::model::{JointType, SoftLimit};

use super::{limit_to_si, Validator};

impl Validator {
    pub(super) fn axis(&mut self, path: &str, def: &JointDef) -> [f64; 3] {
        let needs_axis = matches!(
            def.kind,
            JointType::Revolute | JointType::Prismatic | JointType::Cylindrical
        );
        let Some(axis) = def.axis else {
            if needs_axis {
                self.push(
                    format!("{path}.axis"),
                    format!(
                        "missing field `axis`: a {} joint needs an axis",
                        def.kind.as_str()
                    ),
                );
            }
            return [1.0, 0.0, 0.0];
        };
        // Scale by the largest component first, so that huge but finite components
        // do not overflow the norm.
        let a = axis.to_array();
        let scale = a.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let a = a.map(|c| c / scale);
        let norm = a.iter().map(|c| c * c).sum::<f64>().sqrt();
        if !(scale.is_finite() && scale > 1e-9 && norm.is_finite()) {
            self.push(
                format!("{path}.axis"),
                format!(
                    "expected a non-zero finite direction, got {{x: {}, y: {}, z: {}}}",
                    axis.x, axis.y, axis.z
                ),
            );
            return [1.0, 0.0, 0.0];
        }
        a.map(|c| c / norm)
    }

    /// The joint's `[min, max]` as written (deg or mm; an open side is infinite).
    pub(super) fn limits(&mut self, path: &str, def: &JointDef) -> Option<[f64; 2]> {
        if def.min.is_none() && def.max.is_none() {
            return None;
        }
        if !def.kind.supports_limits() {
            let field = if def.min.is_some() { "min" } else { "max" };
            self.push(
                format!("{path}.{field}"),
                format!(
                    "a {} joint has no limits; min/max apply to revolute and prismatic joints only",
                    def.kind.as_str()
                ),
            );
            return None;
        }
        let unit = match def.kind {
            JointType::Prismatic => "mm",
            _ => "deg",
        };
        let mut bound = |field: &str, value: Option<f64>, default: f64| match value {
            Some(v) if v.is_finite() => v,
            Some(v) => {
                self.push(
                    format!("{path}.{field}"),
                    format!("expected a finite limit in {unit}, got {v}"),
                );
                default
            }
            None => default,
        };
        let min = bound("min", def.min, f64::NEG_INFINITY);
        let max = bound("max", def.max, f64::INFINITY);
        if min > max {
            self.push(
                format!("{path}.min"),
                format!("expected min <= max, got min {min} > max {max} ({unit})"),
            );
        }
        Some([min, max])
    }

    /// A joint's `initial` position (deg or mm, 0 when unset), which must lie within its
    /// limits: where the joint starts, positions being measured from the document's pose.
    pub(super) fn initial(&mut self, path: &str, def: &JointDef, limits: Option<[f64; 2]>) -> f64 {
        let unit = if def.kind == JointType::Prismatic {
            "mm"
        } else {
            "deg"
        };
        let initial = match def.initial {
            None => 0.0,
            Some(_) if !def.kind.supports_limits() => {
                self.push(
                    format!("{path}.initial"),
                    format!(
                        "a {} joint has no initial position; initial applies to revolute and prismatic joints only",
                        def.kind.as_str()
                    ),
                );
                return 0.0;
            }
            Some(v) if !v.is_finite() => {
                self.push(
                    format!("{path}.initial"),
                    format!("expected a finite position in {unit}, got {v}"),
                );
                return 0.0;
            }
            Some(v) => v,
        };
        if let Some([min, max]) = limits.filter(|[min, max]| min <= max) {
            if !(min..=max).contains(&initial) {
                let field = if def.initial.is_some() {
                    "initial"
                } else if min > 0.0 {
                    "min"
                } else {
                    "max"
                };
                self.push(
                    format!("{path}.{field}"),
                    format!(
                        "the joint starts at {initial} {unit} (its `initial`; positions are measured from the document's pose), outside its limits [{min}, {max}]"
                    ),
                );
            }
        }
        initial
    }

    /// A joint's `gear` (finite, non-zero, on an actuated revolute or prismatic joint;
    /// default 1) and `reference` (finite, within ±1e9 deg or mm, on a revolute or
    /// prismatic joint; default 0).
    pub(super) fn gear_and_reference(
        &mut self,
        path: &str,
        def: &JointDef,
        actuated: bool,
    ) -> (f64, f64) {
        let one_dof = matches!(def.kind, JointType::Revolute | JointType::Prismatic);
        let mut gear = 1.0;
        if let Some(g) = def.gear {
            if !(g.is_finite() && g != 0.0 && g.abs() <= 1e9) {
                self.push(
                    format!("{path}.gear"),
                    format!(
                        "expected a finite, non-zero gear within ±1e9, got {}",
                        shown(g)
                    ),
                );
            } else if !one_dof {
                self.push(
                    format!("{path}.gear"),
                    format!(
                        "a gear needs a revolute or prismatic joint, not a {} joint",
                        def.kind.as_str()
                    ),
                );
            } else if !actuated {
                self.push(
                    format!("{path}.gear"),
                    "a passive joint (\"actuated\": false) has no motor to gear; \
                     remove gear or the actuated flag"
                        .to_string(),
                );
            } else {
                gear = g;
            }
        }
        let mut reference = 0.0;
        if let Some(r) = def.reference {
            if !(r.is_finite() && r.abs() <= 1e9) {
                self.push(
                    format!("{path}.reference"),
                    format!(
                        "expected a finite position within ±1e9 (deg or mm), got {}",
                        shown(r)
                    ),
                );
            } else if !one_dof {
                self.push(
                    format!("{path}.reference"),
                    format!(
                        "a reference position needs a revolute or prismatic joint, not a {} joint",
                        def.kind.as_str()
                    ),
                );
            } else {
                reference = r;
            }
        }
        (gear, reference)
    }

    /// A joint's per-DOF quantity that must be finite and >= 0 (armature, friction), and that
    /// a fixed joint, with no DOF, cannot take above zero.
    pub(super) fn dof_quantity(
        &mut self,
        path: &str,
        def: &JointDef,
        (field, value): (&str, Option<f64>),
        expected: &str,
        on_fixed: &str,
    ) -> Option<f64> {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v >= 0.0)) {
            self.push(
                format!("{path}.{field}"),
                format!("expected {expected}, got {v}"),
            );
        }
        if def.kind == JointType::Fixed && value.is_some_and(|v| v > 0.0) {
            self.push(
                format!("{path}.{field}"),
                format!("a fixed joint has no DOF {on_fixed}"),
            );
        }
        value
    }

    /// A joint's passive spring: its stiffness (SI) and rest position (deg or mm).
    pub(super) fn spring(&mut self, path: &str, def: &JointDef) -> (f64, f64) {
        let unit = if def.kind == JointType::Prismatic {
            ("N/m", "mm")
        } else {
            ("N·m/rad", "deg")
        };
        let stiffness = match def.stiffness {
            None => 0.0,
            Some(_) if !def.kind.supports_limits() => {
                self.push(
                    format!("{path}.stiffness"),
                    format!(
                        "a {} joint takes no spring; stiffness applies to revolute and prismatic joints only",
                        def.kind.as_str()
                    ),
                );
                return (0.0, 0.0);
            }
            Some(k) if !(k.is_finite() && k >= 0.0) => {
                self.push(
                    format!("{path}.stiffness"),
                    format!("expected a stiffness >= 0 in {}, got {k}", unit.0),
                );
                return (0.0, 0.0);
            }
            Some(k) => k,
        };
        let rest = match def.spring_rest {
            None => 0.0,
            Some(_) if def.stiffness.is_none() && def.springdamper.is_none() => {
                self.push(
                    format!("{path}.spring_rest"),
                    "a spring rest position needs a `stiffness` or a `springdamper`".to_string(),
                );
                0.0
            }
            Some(r) if !r.is_finite() => {
                self.push(
                    format!("{path}.spring_rest"),
                    format!("expected a finite position in {}, got {r}", unit.1),
                );
                0.0
            }
            Some(r) => r,
        };
        (stiffness, rest)
    }

    /// A joint's `springdamper`, checked: both values positive, on a revolute or prismatic
    /// joint.
    /// A joint's compliant limits, SI: only on a revolute or prismatic joint with limits.
    pub(super) fn soft_limit(
        &mut self,
        path: &str,
        def: &JointDef,
        limits: Option<[f64; 2]>,
    ) -> Option<SoftLimit> {
        let soft = def.soft_limit.as_ref()?;
        let path = format!("{path}.soft_limit");
        if !matches!(def.kind, JointType::Revolute | JointType::Prismatic) || limits.is_none() {
            self.push(
                path,
                "only a revolute or prismatic joint with min and max has limits to soften"
                    .to_string(),
            );
            return None;
        }
        let unit = if def.kind == JointType::Revolute {
            "deg"
        } else {
            "mm"
        };
        let to_si = limit_to_si(def.kind);
        // MuJoCo's 0.001 (rad or m) in the document's unit.
        let default_width = 0.001 / to_si;
        let solref = self.solref(&path, soft.solref.unwrap_or([0.02, 1.0]));
        let [dmin, dmax, width, midpoint, power] = self.solimp(
            &path,
            soft.solimp.unwrap_or([0.9, 0.95, default_width, 0.5, 2.0]),
            unit,
        );
        let margin = soft.margin.unwrap_or(0.0);
        if !(margin.is_finite() && margin >= 0.0) {
            self.push(
                format!("{path}.margin"),
                format!("expected a distance in {unit} >= 0, got {margin}"),
            );
        }
        Some(SoftLimit {
            solref,
            solimp: [dmin, dmax, width * to_si, midpoint, power],
            margin: margin * to_si,
        })
    }

    /// A joint's `max_effort`: positive, and only on an actuated joint.
    pub(super) fn max_effort(&mut self, path: &str, def: &JointDef, actuated: bool) -> Option<f64> {
        let max_effort = def.max_effort.inspect(|&e| {
            if !(e.is_finite() && e > 0.0) {
                self.push(
                    format!("{path}.max_effort"),
                    format!("expected a positive effort in N·m or N, got {e}"),
                );
            }
        });
        if !actuated && max_effort.is_some() {
            self.push(
                format!("{path}.max_effort"),
                "a passive joint (\"actuated\": false) takes no effort to clamp; \
                 remove max_effort or the actuated flag"
                    .to_string(),
            );
        }
        max_effort
    }

    pub(super) fn springdamper(&mut self, path: &str, def: &JointDef) -> Option<[f64; 2]> {
        let [timeconst, dampratio] = def.springdamper?;
        if !def.kind.supports_limits() {
            self.push(
                format!("{path}.springdamper"),
                format!(
                    "a {} joint takes no spring; springdamper applies to revolute and prismatic joints only",
                    def.kind.as_str()
                ),
            );
            return None;
        }
        if !(timeconst.is_finite() && timeconst > 0.0 && dampratio.is_finite() && dampratio > 0.0) {
            self.push(
                format!("{path}.springdamper"),
                format!(
                    "expected [timeconst, dampratio], both > 0, got [{timeconst}, {dampratio}]"
                ),
            );
            return None;
        }
        Some([timeconst, dampratio])
    }
}
