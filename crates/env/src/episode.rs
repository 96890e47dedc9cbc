//! What one step tells: its flags and reward ([`StepFlags`]), with the observation
//! ([`StepResult`]), and why an episode terminated ([`Termination`]). A leaf below the env,
//! its tasks and the batch.

use crate::observation::Observation;

/// Why an episode terminated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Termination {
    /// The simulation produced a non-finite or absurd state. The observation returned
    /// with it is the last finite one; the env must be reset.
    PhysicsDiverged,
    /// The task's goal was reached (reach or track, with `terminate_on_success`).
    GoalReached,
    /// An upright task's instance tilted past its bound.
    Fell,
    /// A terms task's healthy conditions failed (with `terminate`).
    Unhealthy,
}

impl Termination {
    /// A short machine-readable reason: `physics_diverged`, `goal_reached`, `fell`,
    /// `unhealthy`.
    pub fn as_str(self) -> &'static str {
        match self {
            Termination::PhysicsDiverged => "physics_diverged",
            Termination::GoalReached => "goal_reached",
            Termination::Fell => "fell",
            Termination::Unhealthy => "unhealthy",
        }
    }
}

/// The flags of one step, without the observation (written in place by
/// [`RobotEnv::step_into`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepFlags {
    /// The task's reward for the step (see [`crate::TaskSpec`]); 0.0 without a task.
    pub reward: f32,
    /// The episode ended for a task or physics reason.
    pub terminated: bool,
    /// The episode reached `max_steps`.
    pub truncated: bool,
    /// Why it terminated, if it did.
    pub termination: Option<Termination>,
}

impl StepFlags {
    /// `terminated || truncated`.
    pub fn done(&self) -> bool {
        self.terminated || self.truncated
    }
}

/// The result of one step, structured.
#[derive(Debug, Clone, PartialEq)]
pub struct StepResult {
    /// The observation after the step.
    pub observation: Observation,
    /// Flags and reward.
    pub flags: StepFlags,
}
