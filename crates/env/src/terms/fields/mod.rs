//! A term, a quantity and a point as written: flat JSON objects whose fields name one
//! kind among several (`{"joint": "hip"}`, `{"site": "tip", "axis": "x"}`). Serde reads
//! these and converts them (`try_from`) into the enums of `mod.rs`, where "exactly one
//! kind" holds by construction; they write back the same way (`into`), so the JSON and
//! a saved state's `postcard` bytes are what the flat structs gave.
//!
//! A conversion's error names the field it is about, below the value's own JSON path:
//! [`FieldError`] carries it to [`super::TermsTask::from_json`], which appends it to the
//! path `serde_path_to_error` tracked (`task.terms.terms[0].value` + `.component`).

mod quantity;

use std::fmt;

use serde::{Deserialize, Serialize};

pub(super) use quantity::QuantityFields;

use super::{
    one, out_of_bounds, ContactCost, Empty, Factor, Point, Quantity, Square, Term, TermKind,
    Tolerance,
};

/// Marks a [`FieldError`]'s message: `SUB field SUB reason`. No JSON text can produce it
/// in a serde message at the start (serde_json's own messages start with a word).
pub(super) const SUB: char = '\u{1f}';

/// A conversion's error: the field below the value's path (empty: the value itself) and
/// the reason.
#[derive(Debug)]
pub(super) struct FieldError {
    field: String,
    reason: String,
}

impl FieldError {
    pub(super) fn new(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            reason: reason.into(),
        }
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{SUB}{}{SUB}{}", self.field, self.reason)
    }
}

/// Splits a marked message into the field below the value's path and the reason;
/// `None` for serde's own messages.
pub(super) fn split(message: &str) -> Option<(&str, &str)> {
    message.strip_prefix(SUB)?.split_once(SUB)
}

/// A term as written: its name, weight and exactly one kind field.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TermFields {
    name: String,
    #[serde(default = "one")]
    weight: f64,
    #[serde(default)]
    velocity: Option<Quantity>,
    #[serde(default)]
    value: Option<Quantity>,
    #[serde(default)]
    ctrl_cost: Option<Empty>,
    #[serde(default)]
    healthy: Option<Empty>,
    #[serde(default)]
    distance: Option<[Point; 2]>,
    #[serde(default)]
    square: Option<Square>,
    #[serde(default)]
    contact_cost: Option<ContactCost>,
    #[serde(default)]
    tolerance: Option<Tolerance>,
    #[serde(default)]
    product: Option<Vec<Factor>>,
    #[serde(default)]
    sum: Option<Vec<Factor>>,
    #[serde(default)]
    norm: Option<Vec<Factor>>,
    #[serde(default)]
    observe: bool,
}

impl TryFrom<TermFields> for Term {
    type Error = FieldError;

    fn try_from(t: TermFields) -> Result<Self, FieldError> {
        let set = [
            t.velocity.is_some(),
            t.value.is_some(),
            t.ctrl_cost.is_some(),
            t.healthy.is_some(),
            t.distance.is_some(),
            t.square.is_some(),
            t.contact_cost.is_some(),
            t.tolerance.is_some(),
            t.product.is_some(),
            t.sum.is_some(),
            t.norm.is_some(),
        ];
        if set.iter().filter(|s| **s).count() != 1 {
            return Err(FieldError::new(
                "",
                "expected exactly one of velocity, value, ctrl_cost, healthy, distance, \
                 square, contact_cost, tolerance, product, sum or norm",
            ));
        }
        if t.observe && t.value.is_none() {
            return Err(FieldError::new(
                "observe",
                "only a value term can be observed (its coordinate is read from the state)",
            ));
        }
        let kind = if let Some(q) = t.velocity {
            TermKind::Velocity(q)
        } else if let Some(of) = t.value {
            TermKind::Value {
                of,
                observe: t.observe,
            }
        } else if t.ctrl_cost.is_some() {
            TermKind::CtrlCost
        } else if t.healthy.is_some() {
            TermKind::Healthy
        } else if let Some(d) = t.distance {
            TermKind::Distance(d)
        } else if let Some(s) = t.square {
            TermKind::Square(s)
        } else if let Some(c) = t.contact_cost {
            TermKind::ContactCost(c)
        } else if let Some(tol) = t.tolerance {
            TermKind::Tolerance(tol)
        } else if let Some(f) = t.product {
            TermKind::Product(f)
        } else if let Some(f) = t.sum {
            TermKind::Sum(f)
        } else {
            TermKind::Norm(t.norm.expect("one kind is set"))
        };
        Ok(Term {
            name: t.name,
            weight: t.weight,
            kind,
        })
    }
}

impl From<Term> for TermFields {
    fn from(t: Term) -> Self {
        let mut f = TermFields {
            name: t.name,
            weight: t.weight,
            ..TermFields::default()
        };
        match t.kind {
            TermKind::Velocity(q) => f.velocity = Some(q),
            TermKind::Value { of, observe } => {
                f.value = Some(of);
                f.observe = observe;
            }
            TermKind::CtrlCost => f.ctrl_cost = Some(Empty {}),
            TermKind::Healthy => f.healthy = Some(Empty {}),
            TermKind::Distance(d) => f.distance = Some(d),
            TermKind::Square(s) => f.square = Some(s),
            TermKind::ContactCost(c) => f.contact_cost = Some(c),
            TermKind::Tolerance(tol) => f.tolerance = Some(tol),
            TermKind::Product(v) => f.product = Some(v),
            TermKind::Sum(v) => f.sum = Some(v),
            TermKind::Norm(v) => f.norm = Some(v),
        }
        f
    }
}

/// A point's coordinates, each finite and within ±[`super::MAX_VALUE`] mm.
pub(super) fn checked_point(point: Option<[f64; 3]>) -> Result<Option<[f64; 3]>, FieldError> {
    if let Some(p) = point {
        for (k, c) in p.iter().enumerate() {
            if let Some(reason) = out_of_bounds(*c, "coordinate (mm)") {
                return Err(FieldError::new(format!("point[{k}]"), reason));
            }
        }
    }
    Ok(point)
}

/// A distance term's point as written: a site, or an instance with an optional point.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub(super) struct PointFields {
    instance: Option<String>,
    point: Option<[f64; 3]>,
    site: Option<String>,
}

impl TryFrom<PointFields> for Point {
    type Error = FieldError;

    fn try_from(p: PointFields) -> Result<Self, FieldError> {
        match (p.instance, p.site) {
            (Some(name), None) => Ok(Point::Instance {
                name,
                point: checked_point(p.point)?,
            }),
            (None, Some(name)) if p.point.is_none() => Ok(Point::Site(name)),
            _ => Err(FieldError::new(
                "",
                "expected a site, or an instance (with an optional point)",
            )),
        }
    }
}

impl From<Point> for PointFields {
    fn from(p: Point) -> Self {
        match p {
            Point::Instance { name, point } => PointFields {
                instance: Some(name),
                point,
                site: None,
            },
            Point::Site(name) => PointFields {
                instance: None,
                point: None,
                site: Some(name),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::TermsTask;
    use super::*;
    use serde_json::{json, Value};

    /// One of each kind, as written.
    fn written() -> Vec<Value> {
        vec![
            json!({"joint": "hip"}),
            json!({"joint_velocity": "hip"}),
            json!({"joint_limit_force": "hip"}),
            json!({"tendon_length": "t"}),
            json!({"tendon_velocity": "t"}),
            json!({"actuator_force": "hip"}),
            json!({"actuator": "a"}),
            json!({"actuator_activation": "a"}),
            json!({"sensor": "gyro", "component": 2}),
            json!({"sensor": "touch"}),
            json!({"contact_wrench": ["foot"], "component": 5}),
            json!({"body_inertia": ["torso"], "component": 9}),
            json!({"body_velocity": ["torso"], "component": 0}),
            json!({"body_center": ["torso"], "axis": "y"}),
            json!({"instance": "torso", "point": [1.0, 2.0, 3.0], "axis": "z"}),
            json!({"instance": "torso", "axis": "x"}),
            json!({"site": "tip", "axis": "x"}),
            json!({"instance": "torso", "frame_axis": "z", "axis": "z"}),
            json!({"site": "tip", "frame_axis": "x", "axis": "y"}),
            json!({"instance": "torso", "point": [0.0, 1.0, 0.0], "relative_to": "eye", "axis": "x"}),
            json!({"site": "tip", "relative_to": "eye", "axis": "y"}),
            json!({"center_of_mass": true, "axis": "z"}),
            json!({"action": 3}),
        ]
    }

    /// Written back without the fields a kind leaves at their defaults.
    fn written_back(q: &Quantity) -> Value {
        let Value::Object(map) = serde_json::to_value(q).expect("writes") else {
            panic!("an object")
        };
        let set = map
            .into_iter()
            .filter(|(_, v)| !v.is_null() && *v != json!(false))
            .collect();
        Value::Object(set)
    }

    #[test]
    fn every_kind_reads_and_writes_back_as_written() {
        for w in written() {
            let q: Quantity = serde_json::from_value(w.clone()).expect("a quantity");
            assert_eq!(written_back(&q), w);
            // A saved state's bytes are the flat struct's: postcard reads them back as it.
            let bytes = postcard::to_allocvec(&q).expect("encodes");
            let flat: QuantityFields = postcard::from_bytes(&bytes).expect("the flat form");
            assert_eq!(Quantity::try_from(flat).expect("converts"), q);
        }
        let task = json!({"terms": [
            {"name": "f", "velocity": {"joint": "x"}},
            {"name": "v", "weight": 0.5, "value": {"site": "tip", "axis": "z"}, "observe": true},
            {"name": "c", "weight": -0.1, "ctrl_cost": {}},
            {"name": "d", "distance": [{"site": "tip"}, {"instance": "goal", "point": [1.0, 0.0, 0.0]}]},
            {"name": "s", "sum": [{"term": "f"}]},
        ]});
        let parsed = TermsTask::from_json(&task.to_string()).expect("a task");
        let again = TermsTask::from_json(&serde_json::to_string(&parsed).expect("writes"))
            .expect("reads back");
        assert_eq!(again, parsed);
        assert!(parsed.terms[1].observed() && !parsed.terms[0].observed());
        let bytes = postcard::to_allocvec(&parsed).expect("encodes");
        assert_eq!(
            postcard::from_bytes::<TermsTask>(&bytes).expect("decodes"),
            parsed
        );
    }

    #[test]
    fn a_shape_error_names_its_field_below_the_value() {
        let refused = |q: Value| {
            let task = json!({"terms": [{"name": "a", "value": q}]});
            TermsTask::from_json(&task.to_string())
                .expect_err("refused")
                .to_string()
        };
        for (q, expected) in [
            (
                json!({"joint": "hip", "relative_to": "eye"}),
                "task.terms.terms[0].value.relative_to: an offset from a site belongs to a site, or an instance (with an optional point)",
            ),
            (
                json!({"instance": "torso", "point": [0.0, 1e300, 0.0], "axis": "x"}),
                "task.terms.terms[0].value.point[1]: expected a finite coordinate (mm) within ±1e9, got 1e300",
            ),
            (
                json!({"site": "tip"}),
                "task.terms.terms[0].value.axis: a point's coordinate needs an axis: \"x\", \"y\" or \"z\"",
            ),
            (
                json!({"joint": "hip", "wobble": 1}),
                "task.terms.terms[0].value.wobble: unknown field `wobble`",
            ),
        ] {
            let message = refused(q);
            assert!(message.starts_with(expected), "{message}\nexpected: {expected}");
            assert!(!message.contains(SUB), "{message:?}");
        }
        let task = json!({"terms": [{"name": "d", "distance": [{"site": "tip", "point": [0.0, 0.0, 0.0]}, {"site": "tip"}]}]});
        assert_eq!(
            TermsTask::from_json(&task.to_string())
                .expect_err("refused")
                .to_string(),
            "task.terms.terms[0].distance[0]: expected a site, or an instance (with an optional point)"
        );
    }
}
