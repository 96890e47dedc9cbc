//! The terms task: a reward made of weighted, named terms that any robot can carry
//! (docs/design.md §6.1 as extended by the Gymnasium suite): the velocity of a coordinate
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
//! and velocity offset, uniform or normal, from the env's seeded stream, then sets some
//! joints to drawn positions (a goal, an object). Points may be the document's sites.
//!
//! `mod.rs` holds the task as written (serde, JSON); `resolve.rs` checks it against one
//! env; `active.rs` evaluates it after every step and draws the reset.

mod active;
mod choice;
mod fields;
mod placement;
mod quantity;
mod resolve;
mod tolerance;

pub(crate) use gymfleet_assembly::shown;
use serde::{Deserialize, Serialize};

use crate::error::{EnvError, Result};

pub(crate) use active::{rotation_matrix, ActiveSet, ActiveTerms, Dist};
pub(crate) use choice::{turn_about, ChoiceDraw, Coord, Place};
pub use choice::{Choice, ChoiceOption};
pub(crate) use placement::{ActiveMocapDraw, MocapStart};
pub use placement::{MocapDraw, Polar, Turn, WeightedBox};
pub(crate) use resolve::{instance, Context};
pub use tolerance::{Factor, Sigmoid, Tolerance};

/// Most terms (and most healthy ranges) in one task.
pub const MAX_TERMS: usize = 512;
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

/// One named, weighted term. Written as a flat object: its name, weight and one kind
/// field (`{"name": "forward", "velocity": {"joint": "rootx"}}`; `fields/`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "fields::TermFields", into = "fields::TermFields")]
pub struct Term {
    /// The name its value is reported under (e.g. `reward_forward`, `x_position`).
    pub name: String,
    /// Its weight in the reward (written `weight`, default 1; 0: reported only).
    pub weight: f64,
    /// What it computes.
    pub kind: TermKind,
}

/// What a term computes, written as the term's one kind field.
#[derive(Debug, Clone, PartialEq)]
pub enum TermKind {
    /// `velocity`: the rate of change of a coordinate over the env step:
    /// (after − before) / dt.
    Velocity(Quantity),
    /// `value`: a coordinate after the step. With `observe` (default false) it is also
    /// part of the observation (its `terms` segment, in term order), read from the state
    /// at resets as at steps (a contact wrench: 0 after a reset).
    Value {
        /// The coordinate.
        of: Quantity,
        /// Whether the observation carries it.
        observe: bool,
    },
    /// `ctrl_cost: {}`: the control cost, Σ a² over the step's action values.
    CtrlCost,
    /// `healthy: {}`: 1 when the robot is healthy after the step (see
    /// [`TermsTask::healthy`]), else 0.
    Healthy,
    /// `distance`: the distance between two points after the step.
    Distance([Point; 2]),
    /// `square`: the square of a coordinate's offset from a centre after the step,
    /// `(of − center)²` (Gymnasium's InvertedDoublePendulum penalties).
    Square(Square),
    /// `contact_cost`: Σ over groups of instances and over the six components of each
    /// group's contact wrench (see [`Quantity::ContactWrench`]) of the component clipped
    /// to `[min, max]`, squared (Gymnasium's Ant `contact_cost`).
    ContactCost(ContactCost),
    /// `tolerance`: dm_control's `tolerance` of an earlier term's value (1 inside the
    /// bounds, a sigmoid outside).
    Tolerance(Tolerance),
    /// `product`: Π (scale · value + offset) over earlier terms.
    Product(Vec<Factor>),
    /// `sum`: Σ (scale · value + offset) over earlier terms.
    Sum(Vec<Factor>),
    /// `norm`: √Σ (scale · value + offset)² over earlier terms (a vector's length:
    /// dm_control's humanoid's horizontal speed).
    Norm(Vec<Factor>),
}

impl Term {
    /// Whether the observation carries the term's value.
    pub(crate) fn observed(&self) -> bool {
        matches!(self.kind, TermKind::Value { observe: true, .. })
    }
}

/// Σ clip(wrench component, min, max)² over groups of instances.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactCost {
    /// The groups: each the instances of one body (a MuJoCo body's geoms), summed.
    pub groups: Vec<Vec<String>>,
    /// Lower clip (N and N·m).
    pub min: f64,
    /// Upper clip.
    pub max: f64,
    /// The sum's own upper clip, applied before the weight (Gymnasium's Humanoid clips its
    /// weighted contact cost at 10: `sum_max` = 10 / weight); default none.
    #[serde(default)]
    pub sum_max: Option<f64>,
}

/// `(of − center)²`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Square {
    /// The coordinate.
    pub of: Quantity,
    /// The centre (default 0), in the coordinate's units.
    #[serde(default)]
    pub center: f64,
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

/// A scalar read from the state. Written as a flat object: one kind field and the
/// modifiers it takes (`{"joint": "hip"}`, `{"site": "tip", "axis": "x"}`, `{"sensor":
/// "gyro", "component": 2}`; `fields/`). Each variant names its fields as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "fields::QuantityFields", into = "fields::QuantityFields")]
pub enum Quantity {
    /// `joint`: a joint's position (its first DOF), as observed.
    Joint(String),
    /// `joint_velocity`: a joint's velocity (its first DOF), as observed.
    JointVelocity(String),
    /// `joint_limit_force`: the generalized force a joint's limits applied to its first
    /// DOF, averaged over the step: N or N·m in every unit system, negative at the upper
    /// limit (MuJoCo's `qfrc_constraint` of a limited joint; 0 after a reset).
    JointLimitForce(String),
    /// `tendon_length`: a fixed tendon's length (the document's `assembly.tendons`):
    /// Σ coef · position, SI (m or rad) in every unit system, MuJoCo's `ten_length`.
    TendonLength(String),
    /// `tendon_velocity`: a fixed tendon's rate of change, SI in every unit system
    /// (`ten_velocity`).
    TendonVelocity(String),
    /// `actuator_force`: the generalized force the actions apply to a joint's first DOF
    /// (a torque-mode value's gear × action, clamped by `max_effort`, plus every
    /// actuator's moment × force on it; N or N·m in every unit system): MuJoCo's
    /// `qfrc_actuator`; a direct value under position or velocity targets counts 0.
    ActuatorForce(String),
    /// `actuator`: an actuator's force (N or N·m at its transmission, before the gear:
    /// MuJoCo's `actuator_force`), SI in every unit system.
    Actuator(String),
    /// `actuator_activation`: an actuator's activation (MuJoCo's `act`; 0 for one without
    /// dynamics).
    ActuatorActivation(String),
    /// `sensor`: one of the document's sensors (`assembly.sensors`): its reading, SI in
    /// every unit system; `component` (from 0) is needed when it reports more than one
    /// float.
    Sensor {
        /// The sensor's name.
        name: String,
        /// The component read.
        component: Option<usize>,
    },
    /// `contact_wrench` with `component`: the instances whose contact wrenches over the
    /// step are summed: the external force the contacts applied to them and its torque
    /// about the robot's centre of mass, MuJoCo's `cfrc_ext` of the body the instances make
    /// up; components 0–2 the torque about world x, y, z, 3–5 the force. N and N·m in
    /// every unit system; 0 after a reset.
    ContactWrench {
        /// The instances.
        instances: Vec<String>,
        /// The component, 0–5.
        component: usize,
    },
    /// `body_inertia` with `component`: the inertia about the robot's centre of mass of
    /// the instances that make up one body (a MuJoCo body's geoms): MuJoCo's `cinert`,
    /// 0–5 the inertia tensor (xx, yy, zz, xy, xz, yz; kg·m²), 6–8 mass × the body's
    /// centre's offset (kg·m), 9 the mass (kg), world axes, SI in every unit system.
    BodyInertia {
        /// The instances.
        instances: Vec<String>,
        /// The component, 0–9.
        component: usize,
    },
    /// `body_velocity` with `component`: the velocity of the instances that make up one
    /// (rigid) body: MuJoCo's `cvel`, 0–2 the angular velocity (rad/s), 3–5 the velocity
    /// of the body-fixed point at the robot's centre of mass (m/s), SI in every unit
    /// system.
    BodyVelocity {
        /// The instances.
        instances: Vec<String>,
        /// The component, 0–5.
        component: usize,
    },
    /// `body_center` with `axis`: the world coordinate of the centre of mass of the
    /// instances that make up one body: MuJoCo's `xipos`, SI in every unit system.
    BodyCenter {
        /// The instances.
        instances: Vec<String>,
        /// The world coordinate read.
        axis: Axis,
    },
    /// `instance` (with an optional `point`, mm in its frame; default its centre of mass)
    /// or `site`, with `axis`: one world coordinate of the point.
    Point {
        /// The point.
        at: Point,
        /// The world coordinate read.
        axis: Axis,
    },
    /// `instance` or `site` with `frame_axis` and `axis`: the world `axis` component of
    /// the frame's own axis `frame_axis` (MuJoCo's `xmat[axis, frame_axis]`, e.g. `zz`
    /// for an upright).
    FrameAxis {
        /// The frame.
        frame: Frame,
        /// The frame's own axis (written `frame_axis`).
        local: Axis,
        /// Its world component read.
        axis: Axis,
    },
    /// `instance` (with an optional `point`) or `site`, with `relative_to` and `axis`: the
    /// point's offset from the site `relative_to`, along that site's own `axis`
    /// (dm_control's egocentric positions: `(p − p_site) · xmat`).
    Relative {
        /// The point.
        at: Point,
        /// The site it is measured from (written `relative_to`).
        site: String,
        /// The site's own axis.
        axis: Axis,
    },
    /// `center_of_mass: true` with `axis`: a world coordinate of the whole robot's centre
    /// of mass.
    CenterOfMass(Axis),
    /// `action`: the step's action value of this index (MuJoCo's `ctrl`, as sent; 0 at a
    /// reset).
    Action(usize),
}

/// A point: a site, or a point of an instance. Written `{"site": …}` or `{"instance": …,
/// "point": [x, y, z]}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "fields::PointFields", into = "fields::PointFields")]
pub enum Point {
    /// A point of an instance.
    Instance {
        /// The instance (written `instance`).
        name: String,
        /// The point, mm in the instance's frame; `None`: its centre of mass.
        point: Option<[f64; 3]>,
    },
    /// A site of the document (`assembly.sites`).
    Site(String),
}

/// A frame: an instance's or a site's.
#[derive(Debug, Clone, PartialEq)]
pub enum Frame {
    /// An instance's frame.
    Instance(String),
    /// A site's frame.
    Site(String),
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
    /// Whether the noise moves the floating base too, as MuJoCo's free joint noise does
    /// (SI units only): `position`'s distribution offsets its frame's x, y, z (m) and each
    /// component of its orientation quaternion (then normalized), `velocity`'s draws its
    /// linear (world, m/s) and angular (its own frame, rad/s) velocity.
    #[serde(default)]
    pub base: bool,
    /// Every limited joint with one DOF not set above starts uniform in its range
    /// (dm_control's `randomize_limited_and_rotational_joints`, its limited half; the
    /// cheetah's whole draw).
    #[serde(default)]
    pub limited: bool,
    /// Every unlimited revolute joint with one DOF not set above starts uniform in
    /// [−π, π] rad, and a floating base at a uniformly random orientation, turned about its
    /// frame's origin (the rotational half).
    #[serde(default)]
    pub rotational: bool,
    /// Draw the start again while any two colliders overlap (dm_control's finger,
    /// ball-in-cup and humanoid), at most 1000 times (then the last draw stays).
    #[serde(default)]
    pub reject_contacts: bool,
    /// Where mocap bodies start (a target the episode moves), after the keyframe's pose.
    #[serde(default)]
    pub mocap: Vec<MocapDraw>,
    /// Some joints placed by one of several options, chosen by weight (dm_control's
    /// manipulator: its object in the hand, in the target, or anywhere); a frame option
    /// reads its frame after the other draws are placed.
    #[serde(default)]
    pub choice: Option<Choice>,
    /// Pairs `[a, b]`: joint `a` starts at joint `b`'s drawn position and velocity, after
    /// every other draw (dm_control's manipulator makes its hand symmetric).
    #[serde(default)]
    pub equal: Vec<[String; 2]>,
    /// Physics substeps run with a zero action after the draws, before the episode's
    /// first observation (dm_control's cheetah settles for 200), rounded up to whole env
    /// steps; default 0.
    #[serde(default)]
    pub settle_substeps: u32,
}

/// Positions drawn for some joints: normal (`mean`, `std`), or uniform in the box
/// `[low, high]`, drawn again until
/// the vector's norm lies in `[min_norm, max_norm]` (Gymnasium's Reacher draws its goal in
/// a disk, Pusher its object away from the goal). After 1000 rejected draws the last one
/// is scaled radially into the range. The joints start at rest unless `at_rest` is false.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SetJoints {
    /// The joints (one DOF each), in the order of `low` and `high`.
    pub joints: Vec<String>,
    /// Lower corner of the box, one value per joint (the env's units).
    #[serde(default)]
    pub low: Vec<f64>,
    /// Upper corner.
    #[serde(default)]
    pub high: Vec<f64>,
    /// Instead of a box: each joint drawn from a normal distribution with this mean (one
    /// value per joint) and `std`, unclamped (dm_control's cart-pole: `π + 0.01 · randn`).
    #[serde(default)]
    pub mean: Option<Vec<f64>>,
    /// The normal draws' standard deviations, one per joint.
    #[serde(default)]
    pub std: Option<Vec<f64>>,
    /// Whether the joints start at rest (default true); false keeps the velocity noise
    /// on them (dm_control's cart-pole draws every velocity).
    #[serde(default = "yes")]
    pub at_rest: bool,
    /// Smallest norm accepted (default 0).
    #[serde(default)]
    pub min_norm: Option<f64>,
    /// Largest norm accepted (default none).
    #[serde(default)]
    pub max_norm: Option<f64>,
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

impl TermsTask {
    /// Reads a terms task from JSON; errors name the JSON path (`task.terms[1].weight`).
    pub fn from_json(text: &str) -> Result<Self> {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let mut path = if path == "." {
                "task.terms".to_string()
            } else {
                format!("task.terms.{path}")
            };
            let inner = e.inner();
            let message = inner.to_string();
            // A conversion's error (`fields/`) names its field below the path; its
            // reason is bounded by construction, and serde_json's position is dropped.
            let at = format!(" at line {} column {}", inner.line(), inner.column());
            if let Some((field, reason)) =
                fields::split(message.strip_suffix(&at).unwrap_or(&message))
            {
                if !field.is_empty() {
                    path = format!("{path}.{field}");
                }
                return bad(path, reason);
            }
            let reason: String = message.chars().take(300).collect();
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

fn bounded(path: &str, value: f64, what: &str) -> Result<f64> {
    match out_of_bounds(value, what) {
        None => Ok(value),
        Some(reason) => Err(bad(path, reason)),
    }
}

/// Why `value` is refused as a `what`: not finite, or past ±[`MAX_VALUE`].
fn out_of_bounds(value: f64, what: &str) -> Option<String> {
    (!(value.is_finite() && value.abs() <= MAX_VALUE)).then(|| {
        format!(
            "expected a finite {what} within ±{}, got {}",
            shown(MAX_VALUE),
            shown(value)
        )
    })
}
