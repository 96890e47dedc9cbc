//! Where some joints start when a task chooses among several placements
//! (`reset_noise.choice`): dm_control's manipulator puts its object in the hand (at the
//! grasp site), in the target (at the target's pose) or anywhere (a box, with a
//! velocity), 10 %, 10 % and 80 % of the time. An option is a uniform box of positions,
//! or a frame's world pose read after the other draws are placed: a slide takes a
//! coordinate of the frame's position, a hinge the frame's turn about a world axis.

use rand::rngs::Xoshiro256PlusPlus;
use rand::RngExt;
use serde::{Deserialize, Serialize};

use super::{bad, bounded, shown, MAX_TERMS};
use crate::error::Result;

/// One of several placements of some joints, chosen by weight each episode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Choice {
    /// The joints placed (one DOF each), in the order of each option's values.
    pub joints: Vec<String>,
    /// The options: each a box (`low`, `high`) or a frame (`frame`, `from`).
    pub options: Vec<ChoiceOption>,
}

/// One option of a [`Choice`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChoiceOption {
    /// Its share of the draws (default 1).
    #[serde(default = "super::one")]
    pub weight: f64,
    /// A box of positions (as observed, the env's units), one value per joint.
    #[serde(default)]
    pub low: Vec<f64>,
    /// The box's upper corner.
    #[serde(default)]
    pub high: Vec<f64>,
    /// Or a site or instance whose world pose the joints take, after the other draws
    /// (the arm's joints, the mocap bodies) are placed.
    #[serde(default)]
    pub frame: Option<String>,
    /// With `frame`, per joint: `"x"`, `"y"` or `"z"` (the frame's world position, for a
    /// prismatic joint) or `"angle_x"`, `"angle_y"` or `"angle_z"` (its turn about that
    /// world axis in (−π, π], for a revolute joint; read as a frame turned about that axis
    /// only).
    #[serde(default)]
    pub from: Vec<String>,
    /// With `frame`, added to each value (the env's units; default 0).
    #[serde(default)]
    pub offset: Vec<f64>,
    /// Velocities drawn uniform in `[velocity_low, velocity_high]`, one per joint.
    /// Without them the joints keep the velocities an earlier, rejected draw of the same
    /// reset gave (`reject_contacts`), else start at rest: dm_control's manipulator sets
    /// the ball's velocity only in its "anywhere" case and never clears it between its
    /// attempts.
    #[serde(default)]
    pub velocity_low: Vec<f64>,
    /// The velocities' upper bounds.
    #[serde(default)]
    pub velocity_high: Vec<f64>,
}

/// A frame coordinate of [`ChoiceOption::from`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Coord {
    /// A world position coordinate (x, y, z).
    Position(usize),
    /// The turn about world axis x, y or z.
    Angle(usize),
}

/// Where an option's positions come from.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Place {
    /// Uniform in `[low, high]`.
    Box { low: Vec<f64>, high: Vec<f64> },
    /// A frame's pose: its instance, point (mm in the instance's frame) and rotation (a
    /// site's), each joint's coordinate and offset.
    Frame {
        body: usize,
        point: [f64; 3],
        rotation: [f64; 3],
        from: Vec<Coord>,
        offset: Vec<f64>,
    },
}

/// A [`ChoiceOption`] resolved.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ActiveOption {
    /// The cumulative weight up to this option.
    until: f64,
    pub(crate) place: Place,
    /// Velocity bounds, one pair per joint (empty: at rest).
    velocity: Vec<[f64; 2]>,
}

/// A [`Choice`] resolved.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ActiveChoice {
    pub(crate) dofs: Vec<usize>,
    pub(crate) options: Vec<ActiveOption>,
}

/// An [`ActiveChoice`] with this episode's draw: the option, and the positions (a box's)
/// and velocities drawn for its joints (the env's units).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ChoiceDraw {
    pub(crate) choice: ActiveChoice,
    pub(crate) pick: usize,
    pub(crate) positions: Vec<f64>,
    pub(crate) velocities: Vec<f64>,
}

impl ChoiceDraw {
    pub(crate) fn new(choice: ActiveChoice) -> Self {
        let n = choice.dofs.len();
        ChoiceDraw {
            choice,
            pick: 0,
            positions: vec![0.0; n],
            velocities: vec![0.0; n],
        }
    }

    /// A new reset: its joints at rest until an option draws their velocities.
    pub(crate) fn start(&mut self) {
        self.velocities.fill(0.0);
    }

    /// Draws this episode's option and values from the stream.
    pub(crate) fn draw(&mut self, rng: &mut Xoshiro256PlusPlus) {
        self.pick = self
            .choice
            .draw(rng, &mut self.positions, &mut self.velocities);
    }

    /// The chosen option's frame, if it is one.
    pub(crate) fn frame(&self) -> Option<&Place> {
        let place = &self.choice.options[self.pick].place;
        matches!(place, Place::Frame { .. }).then_some(place)
    }
}

fn uniform(rng: &mut Xoshiro256PlusPlus, lo: f64, hi: f64) -> f64 {
    if lo < hi {
        rng.random_range(lo..=hi)
    } else {
        lo
    }
}

impl ActiveChoice {
    /// This episode's option, its box positions (when it is a box) into `positions` and
    /// its velocities into `velocities` (the env's units).
    pub(crate) fn draw(
        &self,
        rng: &mut Xoshiro256PlusPlus,
        positions: &mut [f64],
        velocities: &mut [f64],
    ) -> usize {
        let total = self.options.last().map_or(0.0, |o| o.until);
        let pick = uniform(rng, 0.0, total);
        let chosen = self
            .options
            .iter()
            .position(|o| pick <= o.until)
            .unwrap_or(self.options.len() - 1);
        let option = &self.options[chosen];
        if let Place::Box { low, high } = &option.place {
            for (k, p) in positions.iter_mut().enumerate() {
                *p = uniform(rng, low[k], high[k]);
            }
        }
        // An option without velocities keeps those of an earlier draw of this reset.
        for (v, &[lo, hi]) in velocities.iter_mut().zip(&option.velocity) {
            *v = uniform(rng, lo, hi);
        }
        chosen
    }
}

/// The turn about world axis `axis` (0, 1, 2) of a frame with rotation matrix `m`
/// (`m[row][column]`), turned about that axis only: the angle from a perpendicular unit
/// vector `e` to its image `m·e`, about the axis.
pub(crate) fn turn_about(m: &[[f64; 3]; 3], axis: usize) -> f64 {
    let (e, f) = match axis {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    };
    // m·e's components along e and along axis × e (= f).
    m[f][e].atan2(m[e][e])
}

/// What resolving a choice asks of the env (the terms' resolver answers it).
pub(super) trait ChoiceNames {
    /// The DOF of one-DOF joint `name`, not drawn by an earlier entry (`seen`, which it
    /// joins), or an error at `at`.
    fn one_dof(&self, at: &str, name: &str, seen: &mut Vec<usize>) -> Result<usize>;
    /// A site's (or an instance's) frame: its instance, point and rotation.
    fn frame(&self, at: &str, name: &str) -> Result<(usize, [f64; 3], [f64; 3])>;
    /// Whether DOF `dof` turns (a revolute joint's).
    fn angular(&self, dof: usize) -> bool;
}

impl Choice {
    pub(super) fn resolve(
        &self,
        path: &str,
        cx: &dyn ChoiceNames,
        seen: &mut Vec<usize>,
    ) -> Result<ActiveChoice> {
        let n = self.joints.len();
        if n == 0 || n > MAX_TERMS {
            return Err(bad(
                format!("{path}.joints"),
                format!("expected 1 to {MAX_TERMS} joints, got {n}"),
            ));
        }
        let mut dofs = Vec::with_capacity(n);
        for (k, name) in self.joints.iter().enumerate() {
            dofs.push(cx.one_dof(&format!("{path}.joints[{k}]"), name, seen)?);
        }
        if self.options.is_empty() {
            return Err(bad(
                format!("{path}.options"),
                "expected at least one option",
            ));
        }
        let mut total = 0.0;
        let mut options = Vec::with_capacity(self.options.len());
        for (i, option) in self.options.iter().enumerate() {
            let at = format!("{path}.options[{i}]");
            let w = bounded(&format!("{at}.weight"), option.weight, "weight")?;
            if w <= 0.0 {
                return Err(bad(
                    format!("{at}.weight"),
                    format!("expected a weight > 0, got {}", shown(w)),
                ));
            }
            total += w;
            options.push(ActiveOption {
                until: total,
                place: option.place(&at, cx, &dofs)?,
                velocity: pairs(
                    &at,
                    ("velocity_low", "velocity_high"),
                    &option.velocity_low,
                    &option.velocity_high,
                    n,
                    true,
                )?,
            });
        }
        Ok(ActiveChoice { dofs, options })
    }
}

impl ChoiceOption {
    fn place(&self, at: &str, cx: &dyn ChoiceNames, dofs: &[usize]) -> Result<Place> {
        let n = dofs.len();
        let Some(frame) = &self.frame else {
            if !self.from.is_empty() || !self.offset.is_empty() {
                return Err(bad(at, "from and offset belong to a frame option"));
            }
            let bounds = pairs(at, ("low", "high"), &self.low, &self.high, n, false)?;
            return Ok(Place::Box {
                low: bounds.iter().map(|b| b[0]).collect(),
                high: bounds.iter().map(|b| b[1]).collect(),
            });
        };
        if !self.low.is_empty() || !self.high.is_empty() {
            return Err(bad(
                at,
                "expected exactly one of a box (low, high) or a frame",
            ));
        }
        let (body, point, rotation) = cx.frame(&format!("{at}.frame"), frame)?;
        if self.from.len() != n {
            return Err(bad(
                format!("{at}.from"),
                format!(
                    "expected one coordinate per joint ({n}), got {}",
                    self.from.len()
                ),
            ));
        }
        let mut from = Vec::with_capacity(n);
        for (k, c) in self.from.iter().enumerate() {
            let coord = match c.as_str() {
                "x" | "y" | "z" => Coord::Position(axis(c)),
                "angle_x" | "angle_y" | "angle_z" => Coord::Angle(axis(&c[6..])),
                other => {
                    return Err(bad(
                        format!("{at}.from[{k}]"),
                        format!(
                            "expected x, y, z, angle_x, angle_y or angle_z, got {:?}",
                            other.chars().take(16).collect::<String>()
                        ),
                    ))
                }
            };
            let angular = cx.angular(dofs[k]);
            if angular != matches!(coord, Coord::Angle(_)) {
                return Err(bad(
                    format!("{at}.from[{k}]"),
                    if angular {
                        "a revolute joint takes a turn (angle_x, angle_y or angle_z)"
                    } else {
                        "a prismatic joint takes a position (x, y or z)"
                    },
                ));
            }
            from.push(coord);
        }
        let offset = if self.offset.is_empty() {
            vec![0.0; n]
        } else if self.offset.len() == n {
            for (k, &o) in self.offset.iter().enumerate() {
                bounded(&format!("{at}.offset[{k}]"), o, "offset")?;
            }
            self.offset.clone()
        } else {
            return Err(bad(
                format!("{at}.offset"),
                format!(
                    "expected one value per joint ({n}), got {}",
                    self.offset.len()
                ),
            ));
        };
        Ok(Place::Frame {
            body,
            point,
            rotation,
            from,
            offset,
        })
    }
}

fn axis(c: &str) -> usize {
    match c {
        "x" => 0,
        "y" => 1,
        _ => 2,
    }
}

/// `low` and `high` checked: one finite value per joint each, `low <= high`; both empty
/// is no bounds when `optional`.
fn pairs(
    at: &str,
    (a, b): (&str, &str),
    low: &[f64],
    high: &[f64],
    n: usize,
    optional: bool,
) -> Result<Vec<[f64; 2]>> {
    if optional && low.is_empty() && high.is_empty() {
        return Ok(Vec::new());
    }
    for (field, values) in [(a, low), (b, high)] {
        if values.len() != n {
            return Err(bad(
                format!("{at}.{field}"),
                format!("expected one value per joint ({n}), got {}", values.len()),
            ));
        }
    }
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let lo = bounded(&format!("{at}.{a}[{k}]"), low[k], "value")?;
        let hi = bounded(&format!("{at}.{b}[{k}]"), high[k], "value")?;
        if lo > hi {
            return Err(bad(
                format!("{at}.{b}[{k}]"),
                format!("expected {b} >= {a} = {}, got {}", shown(lo), shown(hi)),
            ));
        }
        out.push([lo, hi]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::turn_about;

    fn about_y(a: f64) -> [[f64; 3]; 3] {
        [
            [a.cos(), 0.0, a.sin()],
            [0.0, 1.0, 0.0],
            [-a.sin(), 0.0, a.cos()],
        ]
    }

    #[test]
    fn the_turn_about_an_axis_is_the_frames_angle() {
        for a in [-3.0, -1.0, 0.0, 0.5, 2.5, 3.1] {
            assert!((turn_about(&about_y(a), 1) - a).abs() < 1e-12, "{a}");
            let (c, s) = (a.cos(), a.sin());
            let z = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
            assert!((turn_about(&z, 2) - a).abs() < 1e-12, "{a}");
            let x = [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]];
            assert!((turn_about(&x, 0) - a).abs() < 1e-12, "{a}");
        }
    }
}
