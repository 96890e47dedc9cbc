//! The terms task: a reward made of weighted, named terms that any robot can carry
//! (PRODUCT.md §6.1 as extended by the Gymnasium suite): the velocity of a coordinate
//! over the env step (forward reward), a healthy reward with healthy ranges and
//! termination (`unhealthy`), the control cost on the action, distances between points
//! of instances, and plain coordinates to report (`x_position`). Each step reports every
//! term's unweighted value; the reward is `Σ weight · value`.
//!
//! Values are in the env's [`Units`] (SI: m, rad, m/s, rad/s; document: mm, deg): the
//! healthy ranges and the reset noise are given in them too. Points inside an instance
//! are document geometry, so they are written in mm in the instance's frame, as a reach
//! task's are.
//!
//! A task may also say how an episode starts: `reset_noise` draws every DOF's position
//! and velocity offset, uniform or normal, from the env's seeded stream.

use gymfleet_assembly::Assembly;
use gymfleet_physics::{JointDof, RobotWorld, Units};
use rand::rngs::Xoshiro256PlusPlus;
use rand::RngExt;
use serde::{Deserialize, Serialize};

use crate::env::Termination;
use crate::error::{EnvError, Result};

/// Most terms (and most healthy ranges) in one task.
pub const MAX_TERMS: usize = 64;
/// Longest term name, in characters.
const MAX_NAME: usize = 64;
/// Largest magnitude of a weight, a range bound or a noise scale.
const MAX_VALUE: f64 = 1e9;

/// A reward of weighted terms, optional healthy conditions and the reset's noise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TermsTask {
    /// The terms, in the order their values are reported.
    pub terms: Vec<Term>,
    /// When the robot is healthy: the `healthy` term's value, and the `unhealthy`
    /// termination.
    #[serde(default)]
    pub healthy: Option<Healthy>,
    /// How each episode's start is drawn. `None`: the env's `reset_noise`, if any.
    #[serde(default)]
    pub reset_noise: Option<ResetNoise>,
}

/// One named, weighted term: exactly one of its kinds is set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Term {
    /// The name its value is reported under (e.g. `reward_forward`, `x_position`).
    pub name: String,
    /// Its weight in the reward (default 1; 0: reported only).
    #[serde(default = "one")]
    pub weight: f64,
    /// The rate of change of a coordinate over the env step: (after − before) / dt.
    #[serde(default)]
    pub velocity: Option<Quantity>,
    /// A coordinate after the step.
    #[serde(default)]
    pub value: Option<Quantity>,
    /// The control cost: Σ a² over the step's action values.
    #[serde(default)]
    pub ctrl_cost: Option<Empty>,
    /// 1 when the robot is healthy after the step (see [`TermsTask::healthy`]), else 0.
    #[serde(default)]
    pub healthy: Option<Empty>,
    /// The distance between two points after the step.
    #[serde(default)]
    pub distance: Option<[Point; 2]>,
}

fn one() -> f64 {
    1.0
}

fn yes() -> bool {
    true
}

/// An empty JSON object: `{}`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Empty {}

/// A world axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// World x.
    X,
    /// World y.
    Y,
    /// World z.
    Z,
}

/// A scalar read from the state: a joint's position or velocity (`joint`,
/// `joint_velocity`), or one world coordinate (`axis`) of a point of an instance
/// (`instance`, `point`), of a site (`site`) or of the whole robot's centre of mass
/// (`center_of_mass`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantity {
    /// A joint's position (its first DOF), as observed.
    #[serde(default)]
    pub joint: Option<String>,
    /// A joint's velocity (its first DOF), as observed.
    #[serde(default)]
    pub joint_velocity: Option<String>,
    /// An instance whose point's coordinate is read (needs `axis`).
    #[serde(default)]
    pub instance: Option<String>,
    /// The instance's point, mm in its frame; `None`: its centre of mass.
    #[serde(default)]
    pub point: Option<[f64; 3]>,
    /// A site (the document's `assembly.sites`) whose coordinate is read (needs `axis`).
    #[serde(default)]
    pub site: Option<String>,
    /// The whole robot's centre of mass (needs `axis`).
    #[serde(default)]
    pub center_of_mass: bool,
    /// The world coordinate read from a point.
    #[serde(default)]
    pub axis: Option<Axis>,
}

/// A point: a site, or a point of an instance (`point`, mm in its frame; default its
/// centre of mass).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Point {
    /// The instance.
    #[serde(default)]
    pub instance: Option<String>,
    /// The point, mm in the instance's frame; `None`: its centre of mass.
    #[serde(default)]
    pub point: Option<[f64; 3]>,
    /// A site of the document (instead of `instance` and `point`).
    #[serde(default)]
    pub site: Option<String>,
}

/// The healthy conditions: every range holds strictly, and every observed position
/// (after the first `skip_positions`) and velocity lies strictly inside `state_range`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Healthy {
    /// Quantities and their open ranges.
    #[serde(default)]
    pub ranges: Vec<Range>,
    /// Bounds on the whole observed joint state.
    #[serde(default)]
    pub state_range: Option<StateRange>,
    /// End the episode (`unhealthy`) when a condition fails (default true).
    #[serde(default = "yes")]
    pub terminate: bool,
}

/// `min < of < max`; a missing bound is no bound.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    /// The quantity.
    pub of: Quantity,
    /// Lower bound (exclusive).
    #[serde(default)]
    pub min: Option<f64>,
    /// Upper bound (exclusive).
    #[serde(default)]
    pub max: Option<f64>,
}

/// Bounds on every observed position (but the first `skip_positions`) and velocity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateRange {
    /// Lower bound (exclusive).
    pub min: f64,
    /// Upper bound (exclusive).
    pub max: f64,
    /// Leading positions left out (Gymnasium's Hopper leaves out x and z: 2).
    #[serde(default)]
    pub skip_positions: usize,
}

/// How each DOF's start is drawn: an offset of its position and of its velocity, then
/// the positions some joints are set to (a goal, an object).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResetNoise {
    /// Position offsets (clamped into the joint's limits).
    #[serde(default)]
    pub position: Option<Noise>,
    /// Velocity offsets (from rest).
    #[serde(default)]
    pub velocity: Option<Noise>,
    /// Joints set to drawn positions (as observed), at rest, after the noise.
    #[serde(default)]
    pub set: Vec<SetJoints>,
}

/// Positions drawn for some joints: uniform in the box `[low, high]`, drawn again until
/// the vector's norm lies in `[min_norm, max_norm]` (Gymnasium's Reacher draws its goal in
/// a disk, Pusher its object away from the goal). After 1000 rejected draws the last one
/// is scaled radially into the range. The joints start at rest.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SetJoints {
    /// The joints (one DOF each), in the order of `low` and `high`.
    pub joints: Vec<String>,
    /// Lower corner of the box, one value per joint (the env's units).
    pub low: Vec<f64>,
    /// Upper corner.
    pub high: Vec<f64>,
    /// Smallest norm accepted (default 0).
    #[serde(default)]
    pub min_norm: Option<f64>,
    /// Largest norm accepted (default none).
    #[serde(default)]
    pub max_norm: Option<f64>,
}

/// A [`SetJoints`] resolved: DOF indices and bounds.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ActiveSet {
    pub(crate) dofs: Vec<usize>,
    low: Vec<f64>,
    high: Vec<f64>,
    min_norm: f64,
    max_norm: f64,
}

/// Draws before a set's last draw is scaled into its norm range.
const MAX_SET_DRAWS: usize = 1000;

impl ActiveSet {
    /// Draws the joints' positions (the env's units) into `out`.
    pub(crate) fn draw(&self, rng: &mut Xoshiro256PlusPlus, out: &mut [f64]) {
        for _ in 0..MAX_SET_DRAWS {
            for (k, o) in out.iter_mut().enumerate() {
                *o = if self.low[k] < self.high[k] {
                    rng.random_range(self.low[k]..=self.high[k])
                } else {
                    self.low[k]
                };
            }
            let norm = out.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm >= self.min_norm && norm <= self.max_norm {
                return;
            }
        }
        let norm = out.iter().map(|v| v * v).sum::<f64>().sqrt();
        let target = norm.clamp(self.min_norm, self.max_norm);
        if norm > 0.0 {
            out.iter_mut().for_each(|v| *v *= target / norm);
        }
    }
}

/// One distribution: exactly one of `uniform` (on `[-s, s]`) or `normal` (σ = s).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Noise {
    /// Half-width of a uniform draw.
    #[serde(default)]
    pub uniform: Option<f64>,
    /// Standard deviation of a normal draw.
    #[serde(default)]
    pub normal: Option<f64>,
}

/// A distribution as drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Dist {
    Uniform(f64),
    Normal(f64),
}

impl Dist {
    /// One draw from the env's stream.
    pub(crate) fn draw(self, rng: &mut Xoshiro256PlusPlus) -> f64 {
        match self {
            Dist::Uniform(s) => rng.random_range(-s..=s),
            Dist::Normal(s) => {
                // Box–Muller: u1 in (0, 1] keeps the logarithm finite.
                let u1: f64 = 1.0 - rng.random::<f64>();
                let u2: f64 = rng.random::<f64>();
                s * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
            }
        }
    }
}

impl TermsTask {
    /// Reads a terms task from JSON; errors name the JSON path (`task.terms[1].weight`).
    pub fn from_json(text: &str) -> Result<Self> {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let path = if path == "." {
                "task.terms".to_string()
            } else {
                format!("task.terms.{path}")
            };
            let reason: String = e.inner().to_string().chars().take(300).collect();
            bad(path, reason)
        })
    }
}

fn bad(path: impl Into<String>, reason: impl Into<String>) -> EnvError {
    EnvError::BadTask {
        path: path.into(),
        reason: reason.into(),
    }
}

/// A number as a message shows it: short whatever its size (`1e300`, not 301 digits).
fn shown(value: f64) -> String {
    if value.is_finite() && value.abs() < 1e9 {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

fn bounded(path: &str, value: f64, what: &str) -> Result<f64> {
    if value.is_finite() && value.abs() <= MAX_VALUE {
        Ok(value)
    } else {
        Err(bad(
            path,
            format!(
                "expected a finite {what} within ±{}, got {}",
                shown(MAX_VALUE),
                shown(value)
            ),
        ))
    }
}

/// A quantity resolved against the env.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Q {
    Position(usize),
    Velocity(usize),
    Point {
        body: usize,
        point: Option<[f64; 3]>,
        axis: usize,
    },
    CenterOfMass(usize),
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Velocity(Q),
    Value(Q),
    CtrlCost,
    Healthy,
    Distance([(usize, Option<[f64; 3]>); 2]),
}

#[derive(Debug, Clone, PartialEq)]
struct ActiveHealthy {
    ranges: Vec<(Q, f64, f64)>,
    state: Option<(f64, f64, usize)>,
    terminate: bool,
}

/// A terms task resolved against one env.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ActiveTerms {
    terms: Vec<(f64, Kind)>,
    healthy: Option<ActiveHealthy>,
    /// Each velocity term's coordinate at the end of the last step (or reset).
    previous: Vec<f64>,
    units: Units,
    dt: f64,
    pub(crate) position_noise: Option<Dist>,
    pub(crate) velocity_noise: Option<Dist>,
    pub(crate) sets: Vec<ActiveSet>,
}

/// What the resolver needs from the env.
pub(crate) struct Context<'a> {
    pub(crate) assembly: &'a Assembly,
    pub(crate) dofs: &'a [JointDof],
    pub(crate) units: Units,
    pub(crate) dt: f64,
}

impl Context<'_> {
    fn joint(&self, path: &str, name: &str) -> Result<usize> {
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

    fn instance(&self, path: &str, name: &str) -> Result<usize> {
        crate::task::instance(self.assembly, path, name)
    }

    /// A site's instance and point.
    fn site(&self, path: &str, name: &str) -> Result<(usize, [f64; 3])> {
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
    fn end(&self, path: &str, p: &Point) -> Result<(usize, Option<[f64; 3]>)> {
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

    fn point(&self, path: &str, point: Option<[f64; 3]>) -> Result<Option<[f64; 3]>> {
        if let Some(p) = point {
            for (k, c) in p.iter().enumerate() {
                bounded(&format!("{path}[{k}]"), *c, "coordinate (mm)")?;
            }
        }
        Ok(point)
    }

    fn quantity(&self, path: &str, q: &Quantity) -> Result<Q> {
        let set = [
            q.joint.is_some(),
            q.joint_velocity.is_some(),
            q.instance.is_some(),
            q.site.is_some(),
            q.center_of_mass,
        ];
        if set.iter().filter(|s| **s).count() != 1 {
            return Err(bad(
                path,
                "expected exactly one of joint, joint_velocity, instance, site or \
                 center_of_mass (the last three with an axis)",
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
        let no_geometry = |what: &str| -> Result<()> {
            if q.axis.is_some() || q.point.is_some() {
                return Err(bad(
                    path,
                    format!("a {what} takes no axis or point (they are for instance, site and center_of_mass)"),
                ));
            }
            Ok(())
        };
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

    fn set(&self, path: &str, set: &SetJoints, seen: &mut Vec<usize>) -> Result<ActiveSet> {
        let n = set.joints.len();
        if n == 0 || n > MAX_TERMS {
            return Err(bad(
                format!("{path}.joints"),
                format!("expected 1 to {MAX_TERMS} joints, got {n}"),
            ));
        }
        if set.low.len() != n || set.high.len() != n {
            return Err(bad(
                path,
                format!(
                    "expected one low and one high per joint ({n}), got {} and {}",
                    set.low.len(),
                    set.high.len()
                ),
            ));
        }
        let mut dofs = Vec::with_capacity(n);
        for (k, name) in set.joints.iter().enumerate() {
            let at = format!("{path}.joints[{k}]");
            let dof = self.joint(&at, name)?;
            if self.dofs.iter().filter(|d| d.joint_name == *name).count() != 1 {
                return Err(bad(
                    at,
                    "expected a joint with one DOF (revolute or prismatic)",
                ));
            }
            if seen.contains(&dof) {
                return Err(bad(at, "the joint is set by an earlier entry too"));
            }
            seen.push(dof);
            dofs.push(dof);
            let lo = bounded(&format!("{path}.low[{k}]"), set.low[k], "position")?;
            let hi = bounded(&format!("{path}.high[{k}]"), set.high[k], "position")?;
            if lo > hi {
                return Err(bad(
                    format!("{path}.high[{k}]"),
                    format!("expected high >= low = {}, got {}", shown(lo), shown(hi)),
                ));
            }
        }
        let min_norm = bounded(
            &format!("{path}.min_norm"),
            set.min_norm.unwrap_or(0.0),
            "norm",
        )?;
        let max_norm = match set.max_norm {
            Some(m) => bounded(&format!("{path}.max_norm"), m, "norm")?,
            None => f64::INFINITY,
        };
        if min_norm < 0.0 || max_norm < min_norm {
            return Err(bad(
                format!("{path}.max_norm"),
                format!(
                    "expected 0 <= min_norm <= max_norm, got {} and {}",
                    shown(min_norm),
                    shown(max_norm)
                ),
            ));
        }
        Ok(ActiveSet {
            dofs,
            low: set.low.clone(),
            high: set.high.clone(),
            min_norm,
            max_norm,
        })
    }

    fn noise(&self, path: &str, noise: Option<Noise>) -> Result<Option<Dist>> {
        let Some(n) = noise else { return Ok(None) };
        let dist =
            match (n.uniform, n.normal) {
                (Some(s), None) => Dist::Uniform(s),
                (None, Some(s)) => Dist::Normal(s),
                _ => return Err(bad(
                    path,
                    "expected exactly one of uniform (half-width) or normal (standard deviation)",
                )),
            };
        let (Dist::Uniform(s) | Dist::Normal(s)) = dist;
        if !(0.0..=MAX_VALUE).contains(&s) {
            return Err(bad(
                path,
                format!(
                    "expected a scale 0 <= s <= {} (the env's units), got {}",
                    shown(MAX_VALUE),
                    shown(s)
                ),
            ));
        }
        Ok((s > 0.0).then_some(dist))
    }
}

impl TermsTask {
    pub(crate) fn resolve(&self, cx: &Context<'_>) -> Result<ActiveTerms> {
        if self.terms.len() > MAX_TERMS {
            return Err(bad(
                "task.terms.terms",
                format!(
                    "expected at most {MAX_TERMS} terms, got {}",
                    self.terms.len()
                ),
            ));
        }
        let mut terms = Vec::with_capacity(self.terms.len());
        let mut names: Vec<&str> = Vec::new();
        for (i, t) in self.terms.iter().enumerate() {
            let path = format!("task.terms.terms[{i}]");
            if t.name.is_empty()
                || t.name.chars().count() > MAX_NAME
                || t.name.chars().any(char::is_control)
            {
                return Err(bad(
                    format!("{path}.name"),
                    format!("expected a name of 1 to {MAX_NAME} printable characters"),
                ));
            }
            if names.contains(&t.name.as_str()) {
                let name: String = t.name.chars().take(MAX_NAME).collect();
                return Err(bad(
                    format!("{path}.name"),
                    format!("{name:?} names an earlier term too; names must be unique"),
                ));
            }
            names.push(&t.name);
            let weight = bounded(&format!("{path}.weight"), t.weight, "weight")?;
            let set = [
                t.velocity.is_some(),
                t.value.is_some(),
                t.ctrl_cost.is_some(),
                t.healthy.is_some(),
                t.distance.is_some(),
            ];
            if set.iter().filter(|s| **s).count() != 1 {
                return Err(bad(
                    path,
                    "expected exactly one of velocity, value, ctrl_cost, healthy or distance",
                ));
            }
            let kind = if let Some(q) = &t.velocity {
                Kind::Velocity(cx.quantity(&format!("{path}.velocity"), q)?)
            } else if let Some(q) = &t.value {
                Kind::Value(cx.quantity(&format!("{path}.value"), q)?)
            } else if t.ctrl_cost.is_some() {
                Kind::CtrlCost
            } else if t.healthy.is_some() {
                if self.healthy.is_none() {
                    return Err(bad(
                        format!("{path}.healthy"),
                        "a healthy term needs the task's healthy conditions (task.terms.healthy)",
                    ));
                }
                Kind::Healthy
            } else {
                let [a, b] = t.distance.as_ref().expect("one kind is set");
                Kind::Distance([
                    cx.end(&format!("{path}.distance[0]"), a)?,
                    cx.end(&format!("{path}.distance[1]"), b)?,
                ])
            };
            terms.push((weight, kind));
        }
        let healthy = match &self.healthy {
            None => None,
            Some(h) => {
                if h.ranges.len() > MAX_TERMS {
                    return Err(bad(
                        "task.terms.healthy.ranges",
                        format!(
                            "expected at most {MAX_TERMS} ranges, got {}",
                            h.ranges.len()
                        ),
                    ));
                }
                let mut ranges = Vec::with_capacity(h.ranges.len());
                for (i, r) in h.ranges.iter().enumerate() {
                    let path = format!("task.terms.healthy.ranges[{i}]");
                    let q = cx.quantity(&format!("{path}.of"), &r.of)?;
                    let lo = match r.min {
                        Some(v) => bounded(&format!("{path}.min"), v, "bound")?,
                        None => f64::NEG_INFINITY,
                    };
                    let hi = match r.max {
                        Some(v) => bounded(&format!("{path}.max"), v, "bound")?,
                        None => f64::INFINITY,
                    };
                    if lo >= hi {
                        return Err(bad(
                            format!("{path}.max"),
                            format!("expected max > min = {}, got {}", shown(lo), shown(hi)),
                        ));
                    }
                    ranges.push((q, lo, hi));
                }
                let state = match &h.state_range {
                    None => None,
                    Some(s) => {
                        let path = "task.terms.healthy.state_range";
                        let lo = bounded(&format!("{path}.min"), s.min, "bound")?;
                        let hi = bounded(&format!("{path}.max"), s.max, "bound")?;
                        if lo >= hi {
                            return Err(bad(
                                format!("{path}.max"),
                                format!("expected max > min = {}, got {}", shown(lo), shown(hi)),
                            ));
                        }
                        if s.skip_positions > cx.dofs.len() {
                            return Err(bad(
                                format!("{path}.skip_positions"),
                                format!(
                                    "expected at most the number of DOFs ({}), got {}",
                                    cx.dofs.len(),
                                    s.skip_positions
                                ),
                            ));
                        }
                        Some((lo, hi, s.skip_positions))
                    }
                };
                Some(ActiveHealthy {
                    ranges,
                    state,
                    terminate: h.terminate,
                })
            }
        };
        let noise = self.reset_noise.clone().unwrap_or_default();
        let mut sets = Vec::with_capacity(noise.set.len());
        let mut seen: Vec<usize> = Vec::new();
        for (i, set) in noise.set.iter().enumerate() {
            sets.push(cx.set(&format!("task.terms.reset_noise.set[{i}]"), set, &mut seen)?);
        }
        Ok(ActiveTerms {
            sets,
            previous: vec![0.0; terms.len()],
            terms,
            healthy,
            units: cx.units,
            dt: cx.dt,
            position_noise: cx.noise("task.terms.reset_noise.position", noise.position)?,
            velocity_noise: cx.noise("task.terms.reset_noise.velocity", noise.velocity)?,
        })
    }
}

impl ActiveTerms {
    fn read(&self, q: Q, world: &RobotWorld, positions: &[f32], velocities: &[f32]) -> f64 {
        match q {
            Q::Position(k) => f64::from(positions[k]),
            Q::Velocity(k) => f64::from(velocities[k]),
            Q::Point { body, point, axis } => match point {
                Some(p) => world.point_position(self.units, body, p)[axis],
                None => world.center_of_mass(self.units, body)[axis],
            },
            Q::CenterOfMass(axis) => world.robot_center_of_mass(self.units)[axis],
        }
    }

    fn point(&self, world: &RobotWorld, (body, point): (usize, Option<[f64; 3]>)) -> [f64; 3] {
        match point {
            Some(p) => world.point_position(self.units, body, p),
            None => world.center_of_mass(self.units, body),
        }
    }

    /// A new episode (or a state put back): the velocity terms' coordinates now.
    pub(crate) fn start(&mut self, world: &RobotWorld, positions: &[f32], velocities: &[f32]) {
        for k in 0..self.terms.len() {
            if let Kind::Velocity(q) = self.terms[k].1 {
                self.previous[k] = self.read(q, world, positions, velocities);
            }
        }
    }

    fn is_healthy(&self, world: &RobotWorld, positions: &[f32], velocities: &[f32]) -> bool {
        let Some(h) = &self.healthy else { return true };
        let ranges = h.ranges.iter().all(|&(q, lo, hi)| {
            let v = self.read(q, world, positions, velocities);
            lo < v && v < hi
        });
        let state = h.state.is_none_or(|(lo, hi, skip)| {
            positions[skip..]
                .iter()
                .chain(velocities)
                .all(|&v| lo < f64::from(v) && f64::from(v) < hi)
        });
        ranges && state
    }

    /// After a step: writes every term's value into `values`, and returns the reward
    /// (Σ weight · value) and the `unhealthy` termination if the task calls for it.
    pub(crate) fn evaluate(
        &mut self,
        world: &RobotWorld,
        positions: &[f32],
        velocities: &[f32],
        action: &[f32],
        values: &mut [f32],
    ) -> (f64, Option<Termination>) {
        let healthy = self.is_healthy(world, positions, velocities);
        let mut reward = 0.0;
        for (k, slot) in values.iter_mut().enumerate().take(self.terms.len()) {
            let (weight, kind) = &self.terms[k];
            let value = match kind {
                Kind::Velocity(q) => {
                    let now = self.read(*q, world, positions, velocities);
                    let rate = (now - self.previous[k]) / self.dt;
                    self.previous[k] = now;
                    rate
                }
                Kind::Value(q) => self.read(*q, world, positions, velocities),
                Kind::CtrlCost => action.iter().map(|&a| f64::from(a) * f64::from(a)).sum(),
                Kind::Healthy => f64::from(u8::from(healthy)),
                Kind::Distance([a, b]) => {
                    let (a, b) = (self.point(world, *a), self.point(world, *b));
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
                }
            };
            *slot = value as f32;
            reward += weight * value;
        }
        let terminate = self.healthy.as_ref().is_some_and(|h| h.terminate);
        (
            reward,
            (terminate && !healthy).then_some(Termination::Unhealthy),
        )
    }
}
