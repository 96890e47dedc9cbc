//! Gym-style robot environments over a gymfleet physics world.
//!
//! This crate owns the episode semantics of docs/design.md §2: [`RobotEnv`] with
//! `reset`/`step`/`observe`, action validation ([`ActionType`], length, finiteness),
//! the flat observation layout (joint positions, joint velocities, then one
//! `[x, y, z, qw, qx, qy, qz]` per end effector), time (`dt` as `substeps` substeps),
//! truncation at `max_steps`, and termination when the physics diverges. Tasks
//! ([`TaskSpec`]: reach, track, upright, with an action cost) compute the reward and the
//! task's terminations (`goal_reached`, `fell`) inside the step; a reach task's target is
//! appended to the observation. Domain randomisation ([`Randomization`]) draws mass,
//! friction, damping and gain factors at every reset from the env's seeded stream.
//!
//! Saved states ([`SavedState`], `state.rs`): an env's whole state as versioned,
//! checksummed bytes that rebuild it anywhere, validated field by field on load.
//!
//! It leaves parsing to `gymfleet-assembly`, simulation to `gymfleet-physics`, and
//! parallelism to `gymfleet-batch`. It knows nothing of networks.

mod access;
mod action;
mod config;
mod env;
mod episode;
mod error;
mod keyframe;
mod mocap;
mod observation;
mod reset;
mod state;
mod task;
pub mod terms;
mod terrain;

pub use access::Bodies;
pub use action::ActionType;
pub use config::{
    ActuatorSpec, EnvConfig, EnvSpec, Randomization, DEFAULT_DT, DEFAULT_MAX_STEPS,
    DEFAULT_SUBSTEPS,
};
pub use env::{DrawReport, RobotEnv, Scene};
pub use episode::{StepFlags, StepResult, Termination};
pub use error::{EnvError, Result};
pub use gymfleet_assembly::{AssemblyError, DofKind, JointType};
pub use gymfleet_physics::Units;
pub use gymfleet_physics::{JointDof, PdGains, SceneJoint, ScenePart, SceneShape, StateAdjustment};
pub use observation::{
    layout as observation_layout, segment, Observation, ObservationParts, ObservationSegment,
    Observed, BASE_VELOCITY_LEN, FREE_POSE_LEN, FREE_VELOCITY_LEN, POSE_LEN,
};
pub use state::{SavedState, STATE_VERSION};
pub use task::{ReachTarget, TaskKind, TaskSpec};
pub use terms::TermsTask;
