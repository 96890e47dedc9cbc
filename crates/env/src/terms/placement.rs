//! Where mocap bodies start each episode (`reset_noise.mocap`): a target the Control
//! Suite's tasks move before every episode (reacher's and fish's target, finger's goal,
//! swimmer's food), drawn from one of some weighted boxes, or on an arc about a centre.
//! The body keeps its orientation, or is turned by a drawn angle about an axis (`turn`:
//! manipulator's target), and stays where it is drawn until moved.

use rand::rngs::Xoshiro256PlusPlus;
use rand::RngExt;
use serde::{Deserialize, Serialize};

use super::{bad, bounded, shown};
use crate::error::Result;
use gymfleet_physics::Units;

/// A mocap body's start: exactly one of `boxes` or `polar`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MocapDraw {
    /// The mocap body (as `EnvSpec::mocap_bodies` names it).
    pub body: String,
    /// Boxes of world positions (the env's units): one is chosen by its weight, then a
    /// point uniform in it.
    #[serde(default)]
    pub boxes: Vec<WeightedBox>,
    /// A point on an arc: `center + radius · (sin angle, cos angle)` in `plane`, the third
    /// coordinate the centre's.
    #[serde(default)]
    pub polar: Option<Polar>,
    /// An orientation drawn too: turned from the world's frame by an angle uniform in
    /// `angle` about `axis`.
    #[serde(default)]
    pub turn: Option<Turn>,
}

/// A drawn orientation of a [`MocapDraw`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Turn {
    /// The axis (world; normalised).
    pub axis: [f64; 3],
    /// `[min, max]` of the angle, rad.
    pub angle: [f64; 2],
}

/// One box of a [`MocapDraw`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WeightedBox {
    /// Its share of the draws (default 1).
    #[serde(default = "super::one")]
    pub weight: f64,
    /// Lower corner, world (the env's units).
    pub low: [f64; 3],
    /// Upper corner.
    pub high: [f64; 3],
}

/// An arc of positions: `radius` and `angle` (rad) uniform in their ranges.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Polar {
    /// The plane: `"xy"` (u = x, v = y) or `"xz"`.
    pub plane: String,
    /// The arc's centre, world (the env's units).
    pub center: [f64; 3],
    /// `[min, max]` of the radius.
    pub radius: [f64; 2],
    /// `[min, max]` of the angle from v towards u, rad.
    pub angle: [f64; 2],
}

/// A [`WeightedBox`] resolved: (cumulative weight, low corner, high corner).
type Box3 = (f64, [f64; 3], [f64; 3]);

/// A [`Polar`] resolved: (u axis, v axis, centre, radius range, angle range).
type Arc = (usize, usize, [f64; 3], [f64; 2], [f64; 2]);

/// A [`MocapDraw`] resolved.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ActiveMocapDraw {
    /// The mocap body's index.
    pub(crate) mocap: usize,
    /// Boxes with their cumulative weights (the last is the total).
    boxes: Vec<Box3>,
    polar: Option<Arc>,
    /// A drawn orientation: the unit axis and the angle's range.
    turn: Option<([f64; 3], [f64; 2])>,
    /// Metres per env unit of length.
    to_m: f64,
}

/// A mocap body's drawn start: a world position (SI) and, with a turn, an orientation
/// (w, x, y, z).
pub(crate) type MocapStart = ([f64; 3], Option<[f64; 4]>);

impl ActiveMocapDraw {
    /// A world position, SI, and an orientation with a turn.
    pub(crate) fn draw(&self, rng: &mut Xoshiro256PlusPlus) -> MocapStart {
        let uniform = |rng: &mut Xoshiro256PlusPlus, lo: f64, hi: f64| {
            if lo < hi {
                rng.random_range(lo..=hi)
            } else {
                lo
            }
        };
        let p = match self.polar {
            Some((u, v, center, radius, angle)) => {
                let a = uniform(rng, angle[0], angle[1]);
                let r = uniform(rng, radius[0], radius[1]);
                let mut p = center;
                p[u] += r * a.sin();
                p[v] += r * a.cos();
                p
            }
            None => {
                let total = self.boxes.last().map_or(0.0, |b| b.0);
                let pick = uniform(rng, 0.0, total);
                let (_, low, high) = self
                    .boxes
                    .iter()
                    .find(|b| pick <= b.0)
                    .unwrap_or(&self.boxes[self.boxes.len() - 1]);
                std::array::from_fn(|k| uniform(rng, low[k], high[k]))
            }
        };
        let q = self.turn.map(|(axis, [lo, hi])| {
            let half = 0.5 * uniform(rng, lo, hi);
            let s = half.sin();
            [half.cos(), s * axis[0], s * axis[1], s * axis[2]]
        });
        (p.map(|c| c * self.to_m), q)
    }
}

impl MocapDraw {
    pub(super) fn resolve(
        &self,
        path: &str,
        mocaps: &[String],
        units: Units,
    ) -> Result<ActiveMocapDraw> {
        let mocap = mocaps.iter().position(|m| *m == self.body).ok_or_else(|| {
            bad(
                format!("{path}.body"),
                format!(
                    "unknown mocap body {} (mocap bodies: {})",
                    gymfleet_assembly::quoted(&self.body),
                    if mocaps.is_empty() {
                        "none: the document has no mocap body".to_string()
                    } else {
                        gymfleet_assembly::quoted_list(mocaps)
                    }
                ),
            )
        })?;
        let to_m = 1.0 / units.length(1.0);
        let turn = match &self.turn {
            Some(t) => Some(turn(&format!("{path}.turn"), t)?),
            None => None,
        };
        match (&self.polar, self.boxes.is_empty()) {
            (Some(p), true) => Ok(ActiveMocapDraw {
                mocap,
                boxes: Vec::new(),
                polar: Some(arc(&format!("{path}.polar"), p)?),
                turn,
                to_m,
            }),
            (None, false) => Ok(ActiveMocapDraw {
                mocap,
                boxes: weighted(path, &self.boxes)?,
                polar: None,
                turn,
                to_m,
            }),
            _ => Err(bad(path, "expected exactly one of boxes or polar")),
        }
    }
}

/// Each coordinate of `v` finite and bounded (errors at `at[k]`).
fn coords(at: &str, v: &[f64]) -> Result<()> {
    for (k, c) in v.iter().enumerate() {
        bounded(&format!("{at}[{k}]"), *c, "coordinate")?;
    }
    Ok(())
}

/// A [`Turn`] checked: a finite, non-zero axis (normalised) and `min <= max`.
fn turn(at: &str, t: &Turn) -> Result<([f64; 3], [f64; 2])> {
    coords(&format!("{at}.axis"), &t.axis)?;
    coords(&format!("{at}.angle"), &t.angle)?;
    let norm = t.axis.iter().map(|c| c * c).sum::<f64>().sqrt();
    if norm < 1e-9 {
        return Err(bad(format!("{at}.axis"), "expected a non-zero axis"));
    }
    let [lo, hi] = t.angle;
    if lo > hi {
        return Err(bad(
            format!("{at}.angle"),
            format!("expected min <= max, got {} and {}", shown(lo), shown(hi)),
        ));
    }
    Ok((t.axis.map(|c| c / norm), t.angle))
}

/// A [`Polar`] checked (`at`: its path).
fn arc(at: &str, p: &Polar) -> Result<Arc> {
    let (u, v) = match p.plane.as_str() {
        "xy" => (0, 1),
        "xz" => (0, 2),
        other => {
            return Err(bad(
                format!("{at}.plane"),
                format!("expected \"xy\" or \"xz\", got {:?}", shown_str(other)),
            ))
        }
    };
    coords(&format!("{at}.center"), &p.center)?;
    coords(&format!("{at}.radius"), &p.radius)?;
    coords(&format!("{at}.angle"), &p.angle)?;
    for (field, [lo, hi]) in [("radius", p.radius), ("angle", p.angle)] {
        if lo > hi {
            return Err(bad(
                format!("{at}.{field}"),
                format!("expected min <= max, got {} and {}", shown(lo), shown(hi)),
            ));
        }
    }
    Ok((u, v, p.center, p.radius, p.angle))
}

/// [`WeightedBox`]es checked, with their cumulative weights.
fn weighted(path: &str, boxes: &[WeightedBox]) -> Result<Vec<Box3>> {
    let mut total = 0.0;
    let mut out = Vec::with_capacity(boxes.len());
    for (k, b) in boxes.iter().enumerate() {
        let at = format!("{path}.boxes[{k}]");
        let w = bounded(&format!("{at}.weight"), b.weight, "weight")?;
        if w <= 0.0 {
            return Err(bad(
                format!("{at}.weight"),
                format!("expected a weight > 0, got {}", shown(w)),
            ));
        }
        coords(&format!("{at}.low"), &b.low)?;
        coords(&format!("{at}.high"), &b.high)?;
        if (0..3).any(|i| b.low[i] > b.high[i]) {
            return Err(bad(
                format!("{at}.high"),
                "expected high >= low in every coordinate",
            ));
        }
        total += w;
        out.push((total, b.low, b.high));
    }
    Ok(out)
}

fn shown_str(s: &str) -> String {
    s.chars().take(16).collect()
}
