//! Errors of environment creation and stepping.

use gymfleet_assembly::AssemblyError;
use gymfleet_physics::PhysicsError;

/// Why an environment could not be created or stepped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EnvError {
    /// The document is malformed or inconsistent.
    #[error(transparent)]
    Document(#[from] AssemblyError),
    /// The physics options (such as PD gains) are unusable.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// An end-effector id names no instance.
    #[error("end_effector_ids[{index}]: unknown instance {id} (known: {known})")]
    UnknownEndEffector {
        /// Position in `end_effector_ids`.
        index: usize,
        /// The id given, quoted (and shortened if long).
        id: String,
        /// The instance names, comma-separated.
        known: String,
    },
    /// A configuration value is out of range.
    #[error("{field}: {reason}")]
    BadConfig {
        /// The option's name, e.g. `dt`.
        field: &'static str,
        /// What was expected and what was given.
        reason: String,
    },
    /// The task is unusable for this env; `path` starts at `task`, e.g.
    /// `task.reach.end_effector`.
    #[error("{path}: {reason}")]
    BadTask {
        /// Where in the task.
        path: String,
        /// What was expected and what was given.
        reason: String,
    },
    /// The action has the wrong number of values.
    #[error(
        "values: expected {expected} action {} (one per actuated DOF), got {got}",
        if *expected == 1 { "value" } else { "values" }
    )]
    ActionLength {
        /// The env's `action_dim`.
        expected: usize,
        /// How many were given.
        got: usize,
    },
    /// An action value is NaN or infinite.
    #[error("values[{index}]: expected a finite number, got {value}")]
    NonFiniteAction {
        /// Position of the bad value.
        index: usize,
        /// The bad value.
        value: f32,
    },
    /// The action type string is not one of the known ones.
    #[error("action_type: expected one of \"torque\", \"position\", \"velocity\", got {got:?}")]
    UnknownActionType {
        /// What was given.
        got: String,
    },
    /// A saved state's bytes are not a state of this format (see `state.rs`).
    #[error("state: {reason}")]
    StateFormat {
        /// What is wrong: length, magic, version, checksum or encoding.
        reason: String,
    },
    /// A saved state does not fit the env, or holds an unusable value.
    #[error("state.{path}: {reason}")]
    BadState {
        /// The field, e.g. `draws.mass[2]` or `config.substeps`.
        path: String,
        /// What was expected and what was given.
        reason: String,
    },
    /// A joint state to set ([`RobotEnv::set_joint_state`](crate::RobotEnv::set_joint_state))
    /// is unusable.
    #[error("{field}: {reason}")]
    BadJointState {
        /// The field, e.g. `joint_positions` or `base_state[3..7]`.
        field: String,
        /// What was expected and what was given.
        reason: String,
    },
    /// A reset names a keyframe the document does not have.
    #[error("keyframe: no keyframe is named {name}; {known}")]
    UnknownKeyframe {
        /// The name given, quoted (and shortened if long).
        name: String,
        /// The document's keyframes, or that it has none.
        known: String,
    },
    /// A heightfield replacement names no heightfield.
    #[error("unknown heightfield {name} (known: {known})")]
    UnknownHeightfield {
        /// The name given, quoted (and shortened if long).
        name: String,
        /// The heightfields' names, or that there are none.
        known: String,
    },
    /// A heightfield replacement's heights do not fit its grid.
    #[error("heightfield {name}: {reason}")]
    BadHeights {
        /// The heightfield, quoted.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// A pose target names no mocap body.
    #[error("unknown mocap body {name} (known: {known})")]
    UnknownMocapBody {
        /// The name given, quoted (and shortened if long).
        name: String,
        /// The mocap bodies' names, or why there are none.
        known: String,
    },
    /// A step's mocap poses have the wrong number of values.
    #[error(
        "mocap_poses: expected {expected} values (7 per mocap body: x, y, z, qw, qx, qy, qz; the env has {bodies}), or none to keep the targets, got {got}"
    )]
    MocapPosesLength {
        /// 7 × the env's mocap bodies.
        expected: usize,
        /// How many were given.
        got: usize,
        /// The env's mocap bodies.
        bodies: usize,
    },
    /// A mocap pose target is unusable.
    #[error("{what}: {reason}")]
    BadMocapPose {
        /// Which target (`mocap body "robot0:mocap"`, `mocap_poses[7..14] (…)`).
        what: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The physics diverged earlier in this episode; only `reset` is possible.
    #[error("the simulation diverged (non-finite state) and was terminated; call reset before stepping again")]
    NeedsReset,
    /// The step's contacts asked for more solver work than the env's limit; the step
    /// stopped before its solver.
    #[error(
        "the step found {} contact pairs with {} contact points: {} contact point-substeps \
         ({} points × {} substeps), over the limit of {} per env step; {}",
        .0.pairs, .0.points, .0.work, .0.points, .0.substeps, .0.max, overload_outcome(.0)
    )]
    ContactWork(gymfleet_physics::ContactOverload),
}

/// What a [`EnvError::ContactWork`] step left.
fn overload_outcome(overload: &gymfleet_physics::ContactOverload) -> String {
    match overload.substeps_done {
        0 => "the env was left where its last step left it (reset it, or set another state)"
            .to_string(),
        done => format!(
            "it stopped after {done} of its substeps, with its contacts grown past the limit \
             within the step, and must be reset"
        ),
    }
}

/// Result alias for this crate.
pub type Result<T, E = EnvError> = std::result::Result<T, E>;
