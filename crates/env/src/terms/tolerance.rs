//! Terms made of earlier terms: dm_control's `tolerance` (1 inside bounds, falling off
//! by a sigmoid over a margin; `dm_control/utils/rewards.py`) of a term's value, and sums
//! and products of affine maps of terms' values. With them a task writes the Control
//! Suite's rewards (walker: `standing · (5 · moving + 1) / 6`, products of tolerances
//! and uprights) from the quantities the other kinds read.

use serde::{Deserialize, Serialize};

use super::{bad, bounded, shown};
use crate::error::Result;

/// dm_control's `tolerance(x, bounds, margin, sigmoid, value_at_margin)` of an earlier
/// term's value `x`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerance {
    /// The earlier term (by name) whose value is `x`.
    pub of: String,
    /// The inclusive bounds where the value is 1; `null` for an open end (default
    /// `[0, 0]`).
    #[serde(default)]
    pub bounds: Option<[Option<f64>; 2]>,
    /// How far outside the bounds the sigmoid falls to `value_at_margin` (default 0:
    /// the value is 0 outside the bounds).
    #[serde(default)]
    pub margin: f64,
    /// The sigmoid's shape (default gaussian).
    #[serde(default)]
    pub sigmoid: Sigmoid,
    /// The value at `margin` from the bounds (default 0.1).
    #[serde(default = "default_value_at_margin")]
    pub value_at_margin: f64,
}

fn default_value_at_margin() -> f64 {
    0.1
}

/// dm_control's sigmoids (`rewards._sigmoids`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sigmoid {
    /// `exp(-(x·s)²/2)`.
    #[default]
    Gaussian,
    /// `1 / cosh(x·s)`.
    Hyperbolic,
    /// `1 / ((x·s)² + 1)`.
    LongTail,
    /// `1 / (|x|·s + 1)`.
    Reciprocal,
    /// `(1 + cos(π·x·s)) / 2` while `|x·s| < 1`, else 0.
    Cosine,
    /// `1 − x·s` while `|x·s| < 1`, else 0.
    Linear,
    /// `1 − (x·s)²` while `|x·s| < 1`, else 0.
    Quadratic,
    /// `1 − tanh(x·s)²`.
    TanhSquared,
}

impl Sigmoid {
    /// Whether `value_at_margin` may be 0 (the sigmoids that reach 0).
    fn reaches_zero(self) -> bool {
        matches!(self, Sigmoid::Cosine | Sigmoid::Linear | Sigmoid::Quadratic)
    }

    /// The sigmoid at `x` (≥ 0, in margins), 1 at 0 and `v` at 1, as dm_control computes
    /// it.
    fn at(self, x: f64, v: f64) -> f64 {
        let within = |scaled: f64, value: f64| if scaled.abs() < 1.0 { value } else { 0.0 };
        match self {
            Sigmoid::Gaussian => {
                let s = (-2.0 * v.ln()).sqrt();
                (-0.5 * (x * s).powi(2)).exp()
            }
            Sigmoid::Hyperbolic => 1.0 / (x * (1.0 / v).acosh()).cosh(),
            Sigmoid::LongTail => 1.0 / ((x * (1.0 / v - 1.0).sqrt()).powi(2) + 1.0),
            Sigmoid::Reciprocal => 1.0 / (x.abs() * (1.0 / v - 1.0) + 1.0),
            Sigmoid::Cosine => {
                let scaled = x * (2.0 * v - 1.0).acos() / std::f64::consts::PI;
                within(scaled, (1.0 + (std::f64::consts::PI * scaled).cos()) / 2.0)
            }
            Sigmoid::Linear => {
                let scaled = x * (1.0 - v);
                within(scaled, 1.0 - scaled)
            }
            Sigmoid::Quadratic => {
                let scaled = x * (1.0 - v).sqrt();
                within(scaled, 1.0 - scaled * scaled)
            }
            Sigmoid::TanhSquared => 1.0 - (x * (1.0 - v).sqrt().atanh()).tanh().powi(2),
        }
    }
}

/// One factor (or addend) of a `product` (`sum`) term: `scale · value + offset` of an
/// earlier term.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Factor {
    /// The earlier term, by name.
    pub term: String,
    /// Default 1.
    #[serde(default = "super::one")]
    pub scale: f64,
    /// Default 0.
    #[serde(default)]
    pub offset: f64,
}

/// A [`Tolerance`] resolved: the term read and the checked parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ActiveTolerance {
    pub(super) of: usize,
    lo: f64,
    hi: f64,
    margin: f64,
    sigmoid: Sigmoid,
    value_at_margin: f64,
}

impl ActiveTolerance {
    /// dm_control's `tolerance` of `x`.
    pub(super) fn of_value(&self, x: f64) -> f64 {
        if self.lo <= x && x <= self.hi {
            return 1.0;
        }
        if self.margin == 0.0 {
            return 0.0;
        }
        let d = if x < self.lo {
            self.lo - x
        } else {
            x - self.hi
        } / self.margin;
        self.sigmoid.at(d, self.value_at_margin)
    }
}

/// The index of earlier term `name` among `names` (the terms before this one).
pub(super) fn earlier(path: &str, names: &[&str], name: &str) -> Result<usize> {
    names.iter().position(|n| *n == name).ok_or_else(|| {
        let name: String = name.chars().take(64).collect();
        bad(
            path,
            format!(
                "{name:?} is not an earlier term (a term reads only the terms listed before it{})",
                if names.is_empty() {
                    String::new()
                } else {
                    let shown: Vec<String> =
                        names.iter().take(16).map(|n| format!("{n:?}")).collect();
                    format!(": {}", shown.join(", "))
                }
            ),
        )
    })
}

impl Tolerance {
    pub(super) fn resolve(&self, path: &str, names: &[&str]) -> Result<ActiveTolerance> {
        let of = earlier(&format!("{path}.of"), names, &self.of)?;
        let [lo, hi] = self.bounds.unwrap_or([Some(0.0), Some(0.0)]);
        let lo = match lo {
            Some(v) => bounded(&format!("{path}.bounds[0]"), v, "bound")?,
            None => f64::NEG_INFINITY,
        };
        let hi = match hi {
            Some(v) => bounded(&format!("{path}.bounds[1]"), v, "bound")?,
            None => f64::INFINITY,
        };
        if lo > hi {
            return Err(bad(
                format!("{path}.bounds"),
                format!(
                    "expected lower <= upper, got {} and {}",
                    shown(lo),
                    shown(hi)
                ),
            ));
        }
        let margin = bounded(&format!("{path}.margin"), self.margin, "margin")?;
        if margin < 0.0 {
            return Err(bad(
                format!("{path}.margin"),
                format!("expected a margin >= 0, got {}", shown(margin)),
            ));
        }
        let v = self.value_at_margin;
        let ok = if self.sigmoid.reaches_zero() {
            (0.0..1.0).contains(&v)
        } else {
            v > 0.0 && v < 1.0
        };
        if !ok {
            return Err(bad(
                format!("{path}.value_at_margin"),
                format!(
                    "expected {} (the {:?} sigmoid), got {}",
                    if self.sigmoid.reaches_zero() {
                        "0 <= value_at_margin < 1"
                    } else {
                        "0 < value_at_margin < 1"
                    },
                    self.sigmoid,
                    shown(v)
                ),
            ));
        }
        Ok(ActiveTolerance {
            of,
            lo,
            hi,
            margin,
            sigmoid: self.sigmoid,
            value_at_margin: v,
        })
    }
}

/// A `sum` or `product` term's factors resolved: (term, scale, offset).
pub(super) fn factors(
    path: &str,
    factors: &[Factor],
    names: &[&str],
) -> Result<Vec<(usize, f64, f64)>> {
    if factors.is_empty() || factors.len() > super::MAX_TERMS {
        return Err(bad(
            path,
            format!(
                "expected 1 to {} factors, got {}",
                super::MAX_TERMS,
                factors.len()
            ),
        ));
    }
    factors
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let at = format!("{path}[{k}]");
            Ok((
                earlier(&format!("{at}.term"), names, &f.term)?,
                bounded(&format!("{at}.scale"), f.scale, "scale")?,
                bounded(&format!("{at}.offset"), f.offset, "offset")?,
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tol(bounds: [Option<f64>; 2], margin: f64, sigmoid: Sigmoid, v: f64) -> ActiveTolerance {
        Tolerance {
            of: "x".into(),
            bounds: Some(bounds),
            margin,
            sigmoid,
            value_at_margin: v,
        }
        .resolve("t", &["x"])
        .unwrap()
    }

    #[test]
    fn every_sigmoid_is_one_in_bounds_and_its_value_at_the_margin() {
        for sigmoid in [
            Sigmoid::Gaussian,
            Sigmoid::Hyperbolic,
            Sigmoid::LongTail,
            Sigmoid::Reciprocal,
            Sigmoid::Cosine,
            Sigmoid::Linear,
            Sigmoid::Quadratic,
            Sigmoid::TanhSquared,
        ] {
            let t = tol([Some(1.0), Some(2.0)], 0.5, sigmoid, 0.3);
            assert_eq!(t.of_value(1.5), 1.0);
            assert_eq!(t.of_value(1.0), 1.0);
            for x in [0.5, 2.5] {
                assert!(
                    (t.of_value(x) - 0.3).abs() < 1e-12,
                    "{sigmoid:?}: {}",
                    t.of_value(x)
                );
            }
            assert!(
                t.of_value(2.2) > 0.3 && t.of_value(2.2) < 1.0,
                "{sigmoid:?}"
            );
        }
    }

    #[test]
    fn values_as_dm_control_gives_them() {
        // rewards.tolerance(x, bounds, margin, sigmoid, value_at_margin), from dm_control 1.0.50.
        let cases = [
            (
                tol([Some(1.2), None], 0.6, Sigmoid::Gaussian, 0.1),
                0.9,
                0.5623413251903491,
            ),
            (
                tol([Some(10.0), None], 10.0, Sigmoid::Linear, 0.0),
                3.0,
                0.3,
            ),
            (
                tol([Some(0.0), Some(0.0)], 1.0, Sigmoid::Quadratic, 0.0),
                0.5,
                0.75,
            ),
            (
                tol([Some(1.0), Some(1.0)], 2.0, Sigmoid::LongTail, 0.1),
                0.0,
                0.3076923076923077,
            ),
            (
                tol([None, Some(-15.0)], 0.0, Sigmoid::Gaussian, 0.1),
                -14.0,
                0.0,
            ),
        ];
        for (t, x, want) in cases {
            assert!(
                (t.of_value(x) - want).abs() < 1e-12,
                "{t:?} at {x}: {}",
                t.of_value(x)
            );
        }
    }

    #[test]
    fn bad_parameters_are_refused_with_their_path() {
        let t = |bounds, margin, sigmoid, v| {
            Tolerance {
                of: "x".into(),
                bounds: Some(bounds),
                margin,
                sigmoid,
                value_at_margin: v,
            }
            .resolve("task.terms.terms[1].tolerance", &["x"])
            .unwrap_err()
            .to_string()
        };
        assert!(t([Some(2.0), Some(1.0)], 0.0, Sigmoid::Gaussian, 0.1)
            .contains("tolerance.bounds: expected lower <= upper, got 2 and 1"));
        assert!(t([None, None], -1.0, Sigmoid::Gaussian, 0.1)
            .contains("tolerance.margin: expected a margin >= 0, got -1"));
        assert!(t([None, None], 1.0, Sigmoid::Gaussian, 0.0).contains(
            "value_at_margin: expected 0 < value_at_margin < 1 (the Gaussian sigmoid), got 0"
        ));
        let unknown = Tolerance {
            of: "y".into(),
            bounds: None,
            margin: 0.0,
            sigmoid: Sigmoid::Linear,
            value_at_margin: 0.0,
        }
        .resolve("p", &["x"])
        .unwrap_err()
        .to_string();
        assert!(
            unknown.contains("p.of: \"y\" is not an earlier term"),
            "{unknown}"
        );
    }
}
