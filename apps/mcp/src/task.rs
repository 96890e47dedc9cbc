//! The `task` and `randomize` arguments of the create tools: a reach, track or upright
//! task with its action cost, and domain-randomisation ranges, as an agent writes them
//! (the proto's field names), turned into the client's [`Task`] and [`Randomization`].

use gymfleet_client::{Randomization, ReachTask, Task, TrackTask, UprightTask};
use schemars::JsonSchema;
use serde::Deserialize;

use crate::errors::{McpError, Result};

/// A point or direction in mm: {"x": .., "y": .., "z": ..}.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct Vec3Param {
    /// The x coordinate, millimetres.
    x: f64,
    /// The y coordinate, millimetres.
    y: f64,
    /// The z coordinate, millimetres.
    z: f64,
}

impl From<Vec3Param> for [f64; 3] {
    fn from(v: Vec3Param) -> Self {
        [v.x, v.y, v.z]
    }
}

/// A box of world points, mm.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct BoxParam {
    /// The lower corner, world mm.
    min: Vec3Param,
    /// The upper corner, world mm.
    max: Vec3Param,
}

/// Reach: bring a point of an instance to a target; reward = minus the distance in mm.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct ReachParam {
    /// The instance carrying the point, e.g. "forearm".
    end_effector: String,
    /// The point in that instance's frame, mm. Default: its centre of mass.
    point: Option<Vec3Param>,
    /// A fixed target, world mm, e.g. {"x": 20, "y": 0, "z": 40}. Give this or target_box.
    target: Option<Vec3Param>,
    /// A box from which a new target is drawn at every reset (seeded). Give this or
    /// target; the target is appended to the observation either way.
    target_box: Option<BoxParam>,
    /// The goal is reached within this distance, mm. Default 0: never.
    #[serde(default)]
    success_radius: f64,
    /// End the episode (termination_reason "goal_reached") when the goal is reached.
    #[serde(default)]
    terminate_on_success: bool,
}

/// Track: hold every joint at its target; reward = minus the error norm (deg or mm).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct TrackParam {
    /// One target per DOF (action_dim of them), degrees or mm.
    targets: Vec<f64>,
    /// The goal is reached within this error norm, deg or mm. Default 0: never.
    #[serde(default)]
    tolerance: f64,
    /// End the episode (termination_reason "goal_reached") when the goal is reached.
    #[serde(default)]
    terminate_on_success: bool,
}

/// Upright: keep an instance's axis near world +Z; reward +1 per step it stays within
/// max_tilt_deg; the episode ends with termination_reason "fell" when it does not.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct UprightParam {
    /// The instance to keep upright.
    instance: String,
    /// The axis in the instance's frame. Default {"x": 0, "y": 0, "z": 1}.
    axis: Option<Vec3Param>,
    /// Largest tilt from vertical, degrees (between 0 and 180).
    max_tilt_deg: f64,
}

/// What the env is asked to do; the server computes the reward and the task's
/// terminations in every step. Give exactly one of reach, track, upright, terms.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct TaskParam {
    /// Reach a target with a point of an instance.
    reach: Option<ReachParam>,
    /// Hold the joints at targets.
    track: Option<TrackParam>,
    /// Keep an instance upright.
    upright: Option<UprightParam>,
    /// A reward of weighted terms any robot can carry (the Gymnasium suite's): {"terms":
    /// [{"name", "weight", and one of "velocity", "value" (a coordinate: {"joint"},
    /// {"joint_velocity"}, {"joint_limit_force"}, {"tendon_length"}, {"tendon_velocity"},
    /// {"contact_wrench": [instances],
    /// "component"}, {"site", "axis"} or {"instance", "axis"}), "ctrl_cost": {}, "healthy":
    /// {}, "distance": [point, point], "square": {"of", "center"}, "contact_cost":
    /// {"groups", "min", "max"}}],
    /// "healthy": {"ranges": [{"of", "min", "max"}], "terminate"}, "reset_noise":
    /// {"position": {"uniform"}, "velocity": {"normal"}}}, in the document's units (mm,
    /// deg). Each step reports every term's value in "terms".
    terms: Option<serde_json::Map<String, serde_json::Value>>,
    /// Subtracted from each step's reward: this weight × the sum of the squared action
    /// values (in the action's own units). Default 0.
    #[serde(default)]
    action_cost: f32,
}

impl TaskParam {
    /// The client's task, or which argument is wrong.
    pub(crate) fn into_task(self) -> Result<Task> {
        if let Some(terms) = self.terms {
            if self.reach.is_some() || self.track.is_some() || self.upright.is_some() {
                return Err(McpError::bad_argument(
                    "task: give exactly one of \"reach\", \"track\", \"upright\" or \"terms\"",
                ));
            }
            let json = serde_json::Value::Object(terms).to_string();
            return Ok(Task::terms(json).with_action_cost(self.action_cost));
        }
        let task: Task = match (self.reach, self.track, self.upright) {
            (Some(r), None, None) => ReachTask {
                end_effector: r.end_effector,
                point: r.point.map(Into::into),
                target: r.target.map(Into::into),
                target_box: r.target_box.map(|b| (b.min.into(), b.max.into())),
                success_radius: r.success_radius,
                terminate_on_success: r.terminate_on_success,
            }
            .into(),
            (None, Some(t), None) => TrackTask {
                targets: t.targets,
                tolerance: t.tolerance,
                terminate_on_success: t.terminate_on_success,
            }
            .into(),
            (None, None, Some(u)) => UprightTask {
                instance: u.instance,
                axis: u.axis.map(Into::into),
                max_tilt_deg: u.max_tilt_deg,
            }
            .into(),
            _ => {
                return Err(McpError::bad_argument(
                    "task: give exactly one of \"reach\", \"track\", \"upright\" or \"terms\"",
                ))
            }
        };
        Ok(task.with_action_cost(self.action_cost))
    }
}

/// A range of scale factors, 0.01 <= min <= max <= 100.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct RangeParam {
    /// The smallest factor (greater than 0).
    min: f64,
    /// The largest factor (at most 100).
    max: f64,
}

/// Domain randomisation: factors drawn at every reset (seeded), independently for each
/// instance (mass, friction) and each joint (damping, PD gains). Omit a field to leave it.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct RandomizeParam {
    /// Factor range for each instance's mass, e.g. {"min": 0.8, "max": 1.2}.
    mass_scale: Option<RangeParam>,
    /// Factor range for each instance's friction coefficient.
    friction_scale: Option<RangeParam>,
    /// Factor range for each joint's damping.
    damping_scale: Option<RangeParam>,
    /// Factor range for each joint's PD gains (position and velocity actions).
    gain_scale: Option<RangeParam>,
}

impl From<RandomizeParam> for Randomization {
    fn from(r: RandomizeParam) -> Self {
        let range = |r: Option<RangeParam>| r.map(|r| [r.min, r.max]);
        Randomization {
            mass_scale: range(r.mass_scale),
            friction_scale: range(r.friction_scale),
            damping_scale: range(r.damping_scale),
            gain_scale: range(r.gain_scale),
        }
    }
}
