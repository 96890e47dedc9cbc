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
//!
//! # Modules
//!
//! - `env.rs`: `RobotEnv::{reset, step, observe}`, with allocation-free `*_into` variants
//!   that write a flat observation; truncation at `max_steps`; termination with
//!   `PhysicsDiverged` (the last finite observation is returned; only reset is allowed
//!   afterwards). `config.rs`: `EnvConfig` and `EnvSpec` (dt, substeps, max_steps, the DOF
//!   layout, limits, gains, the observation layout). `action.rs`: `ActionType` and action
//!   validation. `episode.rs` (a leaf): `StepFlags`, `StepResult`, `Termination`.
//! - `observation.rs` writes the observation's layout once (`observation::layout`: joint
//!   positions, velocities, a floating base's pose and velocity, the poses, the free
//!   bodies' poses and velocities where the document has them, the task's segment) and
//!   reads any flat row back along a layout (`ObservationParts::split`). Every other layer
//!   splits rows by the layout it is given (the server's single-env replies; over the wire
//!   `observation_layout`, which the Rust client's `Observation::{to_flat, from_flat}`, the
//!   MCP adapter and the Python suite envs read), never by restating the order.
//! - `task.rs`: `TaskSpec` (reach, track, upright, action cost) checked against the robot
//!   into an `ActiveTask` that draws a reach target at reset (after the reset noise, from
//!   the same seeded stream), appends it to the observation, and after every step computes
//!   the reward and the `GoalReached`/`Fell` terminations from the world's readouts.
//! - `terms/`: the terms task (`TermsTask`, parsed from JSON with paths in its errors).
//!   `mod.rs` is the task as enums (a term's kind, a quantity, a point: exactly one by
//!   construction), `fields/` the flat JSON objects they are written as and the checked
//!   conversions, `resolve.rs` checks the task against one env (its coordinates and points
//!   in `quantity.rs`), `active.rs` evaluates it: named, weighted
//!   terms (the velocity of a coordinate over the step, a value, the control cost, healthy
//!   conditions with the `Unhealthy` termination, distances, squares, joint limit forces,
//!   tendon lengths and rates, actuator forces, bodies' `cinert` and `cvel`, contact
//!   wrenches of groups of instances and their clipped cost). The wrenches are read once
//!   per step when a term needs them, and each group's `cinert` and `cvel` (and every
//!   sensor's reading, for `{"sensor": ..}` coordinates) once per evaluation (`Now`),
//!   however many of their components are terms. `"observe": true` value terms are also the
//!   observation's `terms` segment, written by `RobotEnv::observe_task_into` after a step's
//!   evaluation and a reset's start. Each step's values are written into
//!   `RobotEnv::term_values` (the batch copies them per env before an autoreset). The task
//!   also holds the reset's noise (uniform or normal, positions and velocities, a floating
//!   base's too). `terms/tolerance.rs` holds the terms made of earlier terms (dm_control's
//!   `tolerance` and its sigmoids, `sum`, `product`, `norm`; a term reads only terms listed
//!   before it, from the step's f64 values); `terms/placement.rs` the mocap bodies' start
//!   draws (boxes, arcs, a turn); `terms/choice.rs` joints placed by one of several
//!   weighted options (a box, or a frame's pose: `reset.rs` places the world once, reads
//!   the frame, and places it again with the joints there). The env's `Units` (physics'
//!   `units.rs`: the document's or SI) apply to the observation and the terms. The
//!   Gymnasium suite is built on this in Python (`client/python/python/gymfleet/suite/`),
//!   and so is the Control Suite (`.../dmc/`).
//! - `reset.rs`: `RobotEnv::reset_into` and `reset_keyed_into`: the world's initial state,
//!   the draws, a keyframe's start (`keyframe.rs`: the document's keyframes resolved to DOF
//!   offsets, velocities and a base pose; `reset_to_into` by name), then the noise on top.
//!   With the task's `reject_contacts`, a start is drawn again (a bounded number of times)
//!   while `RobotWorld::penetrating` (physics' `touching.rs`) finds overlapping colliders;
//!   then the task's settling steps run.
//! - `mocap.rs`: mocap targets set by name (`set_mocap_pose`) or all at once
//!   (`set_mocap_poses`, what a step request carries), checked (finite, a non-zero
//!   quaternion, normalised, within 10 km) in the env's units before any is set.
//!   `terrain.rs`: `set_heightfield` by name (`EnvSpec::heightfields`), checked before
//!   anything changes. End effectors may name a site (with its axes).
//! - `access.rs`: `RobotEnv::set_joint_state` (checked counts and values, then the world's;
//!   the episode goes on) and `RobotEnv::bodies` (every instance's mass, centre, `cinert`,
//!   `cvel` and contact wrench, every site's pose, `qfrc_actuator`, every sensor's reading:
//!   what MuJoCo-shaped access reads).
//! - `setup.rs`: what `RobotEnv::new` derives before it builds the env: the end
//!   effectors, the positions' reset noise, and the env's spec.
//! - `state.rs`: `SavedState`, an env's whole state (document text, options, episode,
//!   generator, draws, task target, `DynamicState`) as `"GFST"`, a format version, a CRC-32
//!   and `postcard` fields. `RobotEnv::save` re-seats the env from the state it returns (so
//!   it and every env loaded from it continue bitwise alike), `load` checks the document
//!   and options and every field before changing anything, and `from_state` builds the env
//!   anew. The document text comes from `Assembly::source`.
//!
//! Benchmarks: `benches/env_step.rs` and `benches/state.rs`, and `examples/task_cost.rs`
//! (the interleaved measure of a task's cost); `examples/peer_step.rs` is the gymfleet side
//! of the MuJoCo peer benchmark.

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
mod setup;
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
