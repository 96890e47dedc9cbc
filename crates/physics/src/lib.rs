//! A Rapier world built from a validated [`gymfleet_assembly::Assembly`].
//!
//! This crate owns everything between a document and the rigid-body solver: one body per
//! instance with its exact primitive collider and mass from volume × density, the joint
//! tree as a reduced-coordinate multibody rooted at the grounded instance (or at a
//! floating base, whose pose and velocity it reads out), actuation
//! (real torques and forces, force-based PD motors for position and velocity targets),
//! measured joint state readout in user units, and an exact reset from a snapshot.
//!
//! It knows nothing of episodes, rewards or observation layout (that is `gymfleet-env`),
//! and nothing of threads or networks. Its plain data types ([`DynamicState`], [`Draws`],
//! [`PdGains`], [`ActionMode`]) derive serde for the env's saved states; the format is
//! the env's.
//!
//! Units at this crate's boundary are the user's: degrees and millimetres for joint
//! state and targets, N·m and N for efforts, millimetres for poses. Inside, all is SI.

mod action_bound;
mod actuation;
mod actuators;
mod bodies;
mod build;
mod colliders;
mod command;
mod contact_budget;
mod contact_filter;
mod contacts;
mod error;
mod fluid;
mod free_bodies;
mod loads;
mod loops;
mod perturb;
mod prefetch;
mod randomize;
mod readout;
mod scene;
mod sensors;
mod set_state;
mod spatial;
mod springdamper;
mod state;
mod tendons;
mod terrain;
mod touching;
mod units;
mod world;

pub use action_bound::{FALLBACK_ACCELERATION, GRAVITY_MULTIPLE};
pub use actuation::{GRAVITY_SAG_ANGULAR, GRAVITY_SAG_LINEAR};
pub use bodies::{INERTIA_LEN, VELOCITY_LEN};
pub use command::{ActionMode, PdGains, DEFAULT_PD_FREQUENCY_HZ};
pub use contacts::WRENCH_LEN;
pub use error::{PhysicsError, Result};
pub use free_bodies::{FREE_POSE_LEN, FREE_VELOCITY_LEN};
pub use perturb::BASE_NOISE_LEN;
pub use randomize::Draws;
pub use rapier3d::geometry::ContactLoad;
pub use readout::BASE_STATE_LEN;
pub use scene::{SceneJoint, ScenePart, SceneShape};
pub use set_state::StateAdjustment;
pub use state::{BodyMotion, DynamicState, JointCoords};
pub use units::Units;
pub use world::{ContactOverload, JointDof, RobotWorld, WorldOptions};
