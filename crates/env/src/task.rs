//! Tasks: the reward, the goal and the task's own termination, computed inside the step
//! from the simulated state (docs/design.md §6.1). [`TaskSpec`] is what a request asks for,
//! in the user's units; [`ActiveTask`] is it resolved against one env (instance indices,
//! the current target) and evaluated after every step.
//!
//! Rewards are in the document's units: a reach reward of −3.2 means the point is 3.2 mm
//! from the target, a track reward of −4 means the joints are 4 deg (or mm) from theirs.
//! That keeps rewards, targets, radii and observations in one unit system, and expresses
//! the seed guide's reaching loop (`reward = −distance` to a target in mm) exactly.

use gymfleet_assembly::Assembly;
use gymfleet_physics::{JointDof, RobotWorld, Units};
use rand::rngs::Xoshiro256PlusPlus;
use rand::RngExt;

use crate::episode::Termination;
use crate::error::{EnvError, Result};
use crate::terms::{instance, ActiveTerms, Context, TermsTask};

/// Where a reach target comes from.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ReachTarget {
    /// A fixed point, world mm.
    Fixed([f64; 3]),
    /// A point drawn uniformly from this box (world mm) at every reset, from the env's
    /// seeded generator.
    Box {
        /// The lower corner.
        min: [f64; 3],
        /// The upper corner.
        max: [f64; 3],
    },
}

/// What an env is asked to do.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum TaskKind {
    /// Bring a point of an instance to a target.
    Reach {
        /// The instance carrying the point.
        end_effector: String,
        /// The point, mm in the instance's frame; `None`: its centre of mass.
        point: Option<[f64; 3]>,
        /// The target.
        target: ReachTarget,
        /// Within this distance (mm) the goal is reached; 0: never.
        success_radius: f64,
        /// End the episode (`goal_reached`) when it is.
        terminate_on_success: bool,
    },
    /// Hold every DOF at its target.
    Track {
        /// One target per DOF, deg or mm.
        targets: Vec<f64>,
        /// Within this error norm (deg or mm) the goal is reached; 0: never.
        tolerance: f64,
        /// End the episode (`goal_reached`) when it is.
        terminate_on_success: bool,
    },
    /// Keep an instance's axis near world +Z.
    Upright {
        /// The instance.
        instance: String,
        /// The axis in the instance's frame (any length but zero).
        axis: [f64; 3],
        /// The episode ends (`fell`) when the axis tilts further than this, deg.
        max_tilt_deg: f64,
    },
    /// A reward of weighted terms (see [`crate::terms`]), in the env's units.
    Terms(TermsTask),
}

/// A task and the weight of the action cost.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TaskSpec {
    /// What to do.
    pub kind: TaskKind,
    /// Subtracted from the reward: this weight × Σ a² over the step's action values, in
    /// the action's own units (N·m, N, deg, mm, deg/s, mm/s). 0: no cost.
    pub action_cost: f64,
}

/// A task resolved against one env.
#[derive(Debug, Clone)]
pub(crate) struct ActiveTask {
    kind: Active,
    action_cost: f64,
    /// The current reach target, world mm.
    target: [f64; 3],
}

#[derive(Debug, Clone)]
enum Active {
    Reach {
        body: usize,
        point: Option<[f64; 3]>,
        target: ReachTarget,
        success_radius: f64,
        terminate: bool,
    },
    Track {
        targets: Vec<f64>,
        tolerance: f64,
        terminate: bool,
    },
    Upright {
        body: usize,
        axis: [f64; 3],
        cos_max_tilt: f64,
    },
    Terms(Box<ActiveTerms>),
}

/// Largest magnitude accepted for a coordinate, mm (100 km).
const MAX_MM: f64 = 1e8;

fn bad(path: impl Into<String>, reason: impl Into<String>) -> EnvError {
    EnvError::BadTask {
        path: path.into(),
        reason: reason.into(),
    }
}

fn finite_vec(path: &str, v: [f64; 3]) -> Result<()> {
    for (k, c) in v.iter().enumerate() {
        if !(c.is_finite() && c.abs() <= MAX_MM) {
            let axis = ["x", "y", "z"][k];
            return Err(bad(
                format!("{path}.{axis}"),
                format!("expected a finite coordinate within ±{MAX_MM} mm, got {c}"),
            ));
        }
    }
    Ok(())
}

fn non_negative(path: &str, value: f64, unit: &str) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(bad(
            path,
            format!("expected a finite value >= 0 ({unit}), got {value}"),
        ))
    }
}

impl TaskSpec {
    /// Checks the task against the env's assembly, DOFs, units and step; the errors'
    /// paths start at `task`.
    pub(crate) fn resolve(&self, cx: &Context<'_>) -> Result<ActiveTask> {
        let (assembly, dofs) = (cx.assembly, cx.dofs);
        if cx.units != Units::Document && !matches!(self.kind, TaskKind::Terms(_)) {
            return Err(bad(
                "task",
                "reach, track and upright tasks are in the document's units (mm, deg); \
                 with units \"si\" use a terms task",
            ));
        }
        if !(self.action_cost.is_finite() && self.action_cost >= 0.0) {
            return Err(bad(
                "task.action_cost",
                format!("expected a finite weight >= 0, got {}", self.action_cost),
            ));
        }
        let kind = match &self.kind {
            TaskKind::Reach {
                end_effector,
                point,
                target,
                success_radius,
                terminate_on_success,
            } => reach(
                assembly,
                end_effector,
                *point,
                target,
                *success_radius,
                *terminate_on_success,
            )?,
            TaskKind::Track {
                targets,
                tolerance,
                terminate_on_success,
            } => track(dofs, targets, *tolerance, *terminate_on_success)?,
            TaskKind::Upright {
                instance: name,
                axis,
                max_tilt_deg,
            } => upright(assembly, name, *axis, *max_tilt_deg)?,
            TaskKind::Terms(terms) => Active::Terms(Box::new(terms.resolve(cx)?)),
        };
        let target = match &self.kind {
            TaskKind::Reach {
                target: ReachTarget::Fixed(t),
                ..
            } => *t,
            _ => [0.0; 3],
        };
        Ok(ActiveTask {
            kind,
            action_cost: self.action_cost,
            target,
        })
    }
}

/// A reach task's end effector, point and target checked.
fn reach(
    assembly: &Assembly,
    end_effector: &str,
    point: Option<[f64; 3]>,
    target: &ReachTarget,
    success_radius: f64,
    terminate_on_success: bool,
) -> Result<Active> {
    let body = instance(assembly, "task.reach.end_effector", end_effector)?;
    if let Some(p) = point {
        finite_vec("task.reach.point", p)?;
    }
    match target {
        ReachTarget::Fixed(t) => finite_vec("task.reach.target", *t)?,
        ReachTarget::Box { min, max } => {
            finite_vec("task.reach.target_box.min", *min)?;
            finite_vec("task.reach.target_box.max", *max)?;
            for k in 0..3 {
                if min[k] > max[k] {
                    let axis = ["x", "y", "z"][k];
                    return Err(bad(
                        format!("task.reach.target_box.max.{axis}"),
                        format!("expected at least min.{axis} = {}, got {}", min[k], max[k]),
                    ));
                }
            }
        }
    }
    non_negative("task.reach.success_radius", success_radius, "mm")?;
    if terminate_on_success && success_radius == 0.0 {
        return Err(bad(
            "task.reach.terminate_on_success",
            "needs a success_radius > 0 (mm)",
        ));
    }
    Ok(Active::Reach {
        body,
        point,
        target: target.clone(),
        success_radius,
        terminate: terminate_on_success,
    })
}

/// A track task's targets checked against the DOFs and their limits.
fn track(
    dofs: &[JointDof],
    targets: &[f64],
    tolerance: f64,
    terminate_on_success: bool,
) -> Result<Active> {
    if targets.len() != dofs.len() {
        return Err(bad(
            "task.track.targets",
            format!(
                "expected one target per DOF ({}), got {}",
                dofs.len(),
                targets.len()
            ),
        ));
    }
    for (k, (t, dof)) in targets.iter().zip(dofs).enumerate() {
        if !(t.is_finite() && t.abs() <= MAX_MM) {
            return Err(bad(
                format!("task.track.targets[{k}]"),
                format!("expected a finite target (deg or mm), got {t}"),
            ));
        }
        if let Some([lo, hi]) = dof.limits.map(|l| l.map(|v| v + dof.reference)) {
            if *t < lo || *t > hi {
                return Err(bad(
                    format!("task.track.targets[{k}]"),
                    format!(
                        "{t} is outside joint {:?}'s limits [{lo}, {hi}]",
                        dof.joint_name
                    ),
                ));
            }
        }
    }
    non_negative("task.track.tolerance", tolerance, "deg or mm")?;
    if terminate_on_success && tolerance == 0.0 {
        return Err(bad(
            "task.track.terminate_on_success",
            "needs a tolerance > 0",
        ));
    }
    Ok(Active::Track {
        targets: targets.to_vec(),
        tolerance,
        terminate: terminate_on_success,
    })
}

/// An upright task's instance and axis checked, the axis normalised.
fn upright(assembly: &Assembly, name: &str, axis: [f64; 3], max_tilt_deg: f64) -> Result<Active> {
    let body = instance(assembly, "task.upright.instance", name)?;
    finite_vec("task.upright.axis", axis)?;
    let norm = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    if norm == 0.0 {
        return Err(bad(
            "task.upright.axis",
            "expected a direction, got the zero vector",
        ));
    }
    if !(max_tilt_deg.is_finite() && max_tilt_deg > 0.0 && max_tilt_deg < 180.0) {
        return Err(bad(
            "task.upright.max_tilt_deg",
            format!("expected an angle in (0, 180) deg, got {max_tilt_deg}"),
        ));
    }
    Ok(Active::Upright {
        body,
        axis: axis.map(|c| c / norm),
        cos_max_tilt: max_tilt_deg.to_radians().cos(),
    })
}

impl ActiveTask {
    /// A reach task's current target, world mm.
    pub(crate) fn reach_target(&self) -> Option<[f64; 3]> {
        matches!(self.kind, Active::Reach { .. }).then_some(self.target)
    }

    /// Floats the task appends to the observation: a reach task's target (x, y, z mm), a
    /// terms task's observed terms.
    pub(crate) fn observation_dim(&self) -> usize {
        match &self.kind {
            Active::Reach { .. } => 3,
            Active::Terms(t) => t.observation_dim(),
            Active::Track { .. } | Active::Upright { .. } => 0,
        }
    }

    /// The name of the observation segment the task appends, if any.
    pub(crate) fn observation_name(&self) -> Option<&'static str> {
        match &self.kind {
            Active::Reach { .. } => Some("target"),
            Active::Terms(t) if t.observation_dim() > 0 => Some("terms"),
            Active::Track { .. } | Active::Upright { .. } | Active::Terms(_) => None,
        }
    }

    /// The task's episode state (a saved state's part): the current target, world mm
    /// (`[0, 0, 0]` but for reach tasks).
    pub(crate) fn target(&self) -> [f64; 3] {
        self.target
    }

    /// Puts a saved target back, if it is one this task could have drawn: finite, in a
    /// reach task's box (or its fixed point), zero for the other tasks.
    pub(crate) fn restore_target(&mut self, target: [f64; 3]) -> Result<()> {
        let (lo, hi) = match &self.kind {
            Active::Reach {
                target: ReachTarget::Box { min, max },
                ..
            } => (*min, *max),
            Active::Reach {
                target: ReachTarget::Fixed(t),
                ..
            } => (*t, *t),
            Active::Track { .. } | Active::Upright { .. } | Active::Terms(_) => {
                ([0.0; 3], [0.0; 3])
            }
        };
        for k in 0..3 {
            if !(target[k] >= lo[k] && target[k] <= hi[k]) {
                return Err(EnvError::BadState {
                    path: format!("task_target[{k}]"),
                    reason: format!(
                        "expected a value this task can draw, in [{}, {}], got {}",
                        lo[k], hi[k], target[k]
                    ),
                });
            }
        }
        self.target = target;
        Ok(())
    }

    /// A new episode: draws the reach target from its box (after the reset noise).
    pub(crate) fn reset(&mut self, rng: &mut Xoshiro256PlusPlus) {
        if let Active::Reach {
            target: ReachTarget::Box { min, max },
            ..
        } = &self.kind
        {
            for k in 0..3 {
                self.target[k] = if min[k] < max[k] {
                    rng.random_range(min[k]..=max[k])
                } else {
                    min[k]
                };
            }
        }
    }

    /// Writes the task's part of the observation (see [`ActiveTask::observation_dim`]): a reach task's target, a terms task's
    /// observed terms (from `world` and the observed joint state).
    pub(crate) fn observe(
        &self,
        world: &RobotWorld,
        positions: &[f32],
        velocities: &[f32],
        out: &mut [f32],
    ) {
        match &self.kind {
            Active::Reach { .. } => {
                for (o, t) in out.iter_mut().zip(self.target) {
                    *o = t as f32;
                }
            }
            Active::Terms(t) => t.observe(world, positions, velocities, out),
            Active::Track { .. } | Active::Upright { .. } => {}
        }
    }

    /// A terms task's resolved terms.
    pub(crate) fn terms(&self) -> Option<&ActiveTerms> {
        match &self.kind {
            Active::Terms(t) => Some(t),
            _ => None,
        }
    }

    /// After a reset or a state put back: a terms task's velocity terms start from the
    /// observed state.
    pub(crate) fn start(&mut self, world: &RobotWorld, positions: &[f32], velocities: &[f32]) {
        if let Active::Terms(t) = &mut self.kind {
            t.start(world, positions, velocities);
        }
    }

    /// The step's reward, and the termination the task calls for, from the state after
    /// the step (`positions`, `velocities`: the joint state the step just observed) and
    /// the action that led there. A terms task writes its terms' values into `values`.
    pub(crate) fn evaluate(
        &mut self,
        world: &RobotWorld,
        positions: &[f32],
        velocities: &[f32],
        action: &[f32],
        values: &mut [f32],
    ) -> (f64, Option<Termination>) {
        let cost = if self.action_cost > 0.0 {
            self.action_cost * crate::action::sum_of_squares(action)
        } else {
            0.0
        };
        let (reward, termination) = match &mut self.kind {
            Active::Reach {
                body,
                point,
                success_radius,
                terminate,
                ..
            } => {
                let p = match point {
                    Some(offset) => world.point_position(Units::Document, *body, *offset),
                    None => world.center_of_mass(Units::Document, *body),
                };
                let d = distance(p, self.target);
                let reached = *success_radius > 0.0 && d <= *success_radius;
                (
                    -d,
                    (reached && *terminate).then_some(Termination::GoalReached),
                )
            }
            Active::Track {
                targets,
                tolerance,
                terminate,
            } => {
                let error = positions
                    .iter()
                    .zip(targets.iter())
                    .map(|(&q, &t)| (f64::from(q) - t).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let reached = *tolerance > 0.0 && error <= *tolerance;
                (
                    -error,
                    (reached && *terminate).then_some(Termination::GoalReached),
                )
            }
            Active::Upright {
                body,
                axis,
                cos_max_tilt,
            } => {
                let up = world.direction(*body, *axis);
                // The tilt is the angle between the axis and world +Z: cos = up.z.
                if up[2] < *cos_max_tilt {
                    (0.0, Some(Termination::Fell))
                } else {
                    (1.0, None)
                }
            }
            Active::Terms(terms) => terms.evaluate(world, positions, velocities, action, values),
        };
        (reward - cost, termination)
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
