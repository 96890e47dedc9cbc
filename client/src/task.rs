//! [`Task`]: what an env is asked to do (its reward, goal and task terminations,
//! computed by the server inside the step), as the client builds it for
//! [`crate::EnvOptions::task`] and [`crate::BatchOptions::task`]; and
//! [`Randomization`], the domain-randomisation ranges beside it, with the
//! [`RandomizationDraws`] an env reports.
//!
//! ```
//! use gymfleet_client::{ReachTask, Task};
//!
//! // The seed guide's reaching loop: reward = −distance (mm) to [20, 0, 40] mm.
//! let task = Task::from(ReachTask {
//!     end_effector: "forearm".into(),
//!     target: Some([20.0, 0.0, 40.0]),
//!     ..ReachTask::default()
//! });
//! assert_eq!(task.action_cost, 0.0);
//! ```

use gymfleet_proto::v1 as pb;

/// Bring a point of an instance to a target. Reward: minus the distance in mm, minus
/// the action cost; the target is appended to the observation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ReachTask {
    /// The instance carrying the point.
    pub end_effector: String,
    /// The point in the instance's frame, mm; `None`: its centre of mass.
    pub point: Option<[f64; 3]>,
    /// A fixed target, world mm (exactly one of `target` and `target_box`).
    pub target: Option<[f64; 3]>,
    /// `(min, max)` corners of a box (world mm) from which a target is drawn at every
    /// reset, from the env's seeded generator.
    pub target_box: Option<([f64; 3], [f64; 3])>,
    /// The goal is reached within this distance, mm; 0: never.
    pub success_radius: f64,
    /// End the episode (`goal_reached`) when the goal is reached.
    pub terminate_on_success: bool,
}

/// Hold every DOF at its target. Reward: minus the error norm (deg or mm).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrackTask {
    /// One target per DOF, deg or mm.
    pub targets: Vec<f64>,
    /// The goal is reached within this error norm; 0: never.
    pub tolerance: f64,
    /// End the episode (`goal_reached`) when the goal is reached.
    pub terminate_on_success: bool,
}

/// Keep an instance's axis near world +Z. Reward +1 per step that ends upright; the
/// episode ends (`fell`) past `max_tilt_deg`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct UprightTask {
    /// The instance.
    pub instance: String,
    /// The axis in the instance's frame; `None`: +Z.
    pub axis: Option<[f64; 3]>,
    /// Largest tilt, deg.
    pub max_tilt_deg: f64,
}

/// The kinds of task.
#[derive(Debug, Clone, PartialEq)]
pub enum TaskKind {
    /// See [`ReachTask`].
    Reach(ReachTask),
    /// See [`TrackTask`].
    Track(TrackTask),
    /// See [`UprightTask`].
    Upright(UprightTask),
    /// A terms task, as its JSON (see docs/tasks.md, "Terms tasks"): weighted terms,
    /// healthy conditions and reset noise, in the env's units.
    Terms(String),
}

/// A task and the weight of its action cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Task {
    /// What to do.
    pub kind: TaskKind,
    /// Subtracted from each step's reward: this × Σ a² over the action values.
    pub action_cost: f32,
}

impl Task {
    /// A terms task from its JSON (`{"terms": [...], "healthy": {...},
    /// "reset_noise": {...}}`); the server checks it against the robot.
    pub fn terms(json: impl Into<String>) -> Self {
        Task {
            kind: TaskKind::Terms(json.into()),
            action_cost: 0.0,
        }
    }

    /// The same task with an action cost.
    pub fn with_action_cost(mut self, weight: f32) -> Self {
        self.action_cost = weight;
        self
    }
}

impl From<ReachTask> for Task {
    fn from(t: ReachTask) -> Self {
        Task {
            kind: TaskKind::Reach(t),
            action_cost: 0.0,
        }
    }
}

impl From<TrackTask> for Task {
    fn from(t: TrackTask) -> Self {
        Task {
            kind: TaskKind::Track(t),
            action_cost: 0.0,
        }
    }
}

impl From<UprightTask> for Task {
    fn from(t: UprightTask) -> Self {
        Task {
            kind: TaskKind::Upright(t),
            action_cost: 0.0,
        }
    }
}

fn vec3([x, y, z]: [f64; 3]) -> pb::Vec3 {
    pb::Vec3 { x, y, z }
}

impl From<Task> for pb::Task {
    fn from(t: Task) -> Self {
        use pb::task::Kind;
        let kind = match t.kind {
            TaskKind::Reach(r) => Kind::Reach(pb::ReachTask {
                end_effector: r.end_effector,
                point: r.point.map(vec3),
                target: r.target.map(vec3),
                target_box: r.target_box.map(|(min, max)| pb::Box3 {
                    min: Some(vec3(min)),
                    max: Some(vec3(max)),
                }),
                success_radius: r.success_radius,
                terminate_on_success: r.terminate_on_success,
            }),
            TaskKind::Track(r) => Kind::Track(pb::TrackTask {
                targets: r.targets,
                tolerance: r.tolerance,
                terminate_on_success: r.terminate_on_success,
            }),
            TaskKind::Upright(r) => Kind::Upright(pb::UprightTask {
                instance: r.instance,
                axis: r.axis.map(vec3),
                max_tilt_deg: r.max_tilt_deg,
            }),
            TaskKind::Terms(json) => Kind::Terms(pb::TermsTask { json }),
        };
        pb::Task {
            kind: Some(kind),
            action_cost: t.action_cost,
        }
    }
}

/// Domain randomisation ranges `[min, max]` of scale factors, drawn at every reset by the
/// env's seeded generator, per instance (mass, friction) and per joint (damping, gains);
/// `None` leaves that quantity as the document has it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Randomization {
    /// Multiplies each instance's mass.
    pub mass_scale: Option<[f64; 2]>,
    /// Multiplies each instance's friction.
    pub friction_scale: Option<[f64; 2]>,
    /// Multiplies each joint's damping.
    pub damping_scale: Option<[f64; 2]>,
    /// Multiplies each joint's PD gains.
    pub gain_scale: Option<[f64; 2]>,
}

impl From<Randomization> for pb::Randomization {
    fn from(r: Randomization) -> Self {
        let range = |r: Option<[f64; 2]>| r.map(|[min, max]| pb::Range { min, max });
        pb::Randomization {
            mass_scale: range(r.mass_scale),
            friction_scale: range(r.friction_scale),
            damping_scale: range(r.damping_scale),
            gain_scale: range(r.gain_scale),
        }
    }
}

/// The factors an env drew at its last reset, in document order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RandomizationDraws {
    /// `(instance, mass factor, friction factor)`.
    pub instances: Vec<(String, f64, f64)>,
    /// `(joint, damping factor, gain factor)`, fixed joints included.
    pub joints: Vec<(String, f64, f64)>,
}

impl From<pb::RandomizationDraws> for RandomizationDraws {
    fn from(d: pb::RandomizationDraws) -> Self {
        RandomizationDraws {
            instances: d
                .instances
                .into_iter()
                .map(|i| (i.name, i.mass_scale, i.friction_scale))
                .collect(),
            joints: d
                .joints
                .into_iter()
                .map(|j| (j.name, j.damping_scale, j.gain_scale))
                .collect(),
        }
    }
}
