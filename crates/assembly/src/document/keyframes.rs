//! *(ext)* Keyframes: named initial states of a document (MJCF's `<keyframe><key>`), which
//! a reset may start from instead of the document's pose.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::Vec3;

/// A named initial state: where the joints (and the floating base) start when a reset
/// names it, before the reset's noise. What it does not name starts where a reset without
/// it would.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeDef {
    /// Its name, unique among the keyframes.
    pub name: String,
    /// Positions of revolute (deg) and prismatic (mm) joints by joint name, as observed
    /// (from the document's pose, the joint's `reference` included).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub positions: BTreeMap<String, f64>,
    /// Velocities of revolute (deg/s) and prismatic (mm/s) joints by joint name; default 0.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub velocities: BTreeMap<String, f64>,
    /// Ball joints' rotations by joint name, quaternions `[qw, qx, qy, qz]` (MuJoCo's
    /// qpos of a ball joint; normalised on load): observed as the rotation vector.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub rotations: BTreeMap<String, [f64; 4]>,
    /// Ball joints' angular velocities by joint name, deg/s in the child's axes (MuJoCo's
    /// qvel of a ball joint); default 0.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub spins: BTreeMap<String, Vec3>,
    /// Where the floating base starts; default where the document puts it, at rest.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<BaseKeyDef>,
    /// Where free bodies start, by instance name: the reference frame's pose as observed
    /// (`free_body_poses`: world mm, `[qw, qx, qy, qz]`), its origin's velocity (world
    /// mm/s) and its angular velocity in its own axes (deg/s): MuJoCo's `qpos` and `qvel`
    /// of a free joint. A free body the keyframe does not name starts where a plain reset
    /// puts it.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub free_bodies: BTreeMap<String, BaseKeyDef>,
    /// Where mocap bodies start, by instance name: the reference frame's pose (world mm,
    /// `[qw, qx, qy, qz]`; MuJoCo's `mpos`, `mquat`), held until a target moves it. No
    /// velocities.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub mocap: BTreeMap<String, BaseKeyDef>,
    /// The command held at the reset, by actuator (or directly actuated joint) name: its
    /// control (MuJoCo's `ctrl`), until the first step's action replaces it; default 0.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub controls: BTreeMap<String, f64>,
    /// Actuators' activations at the reset, by name (MuJoCo's `act`); default 0.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub activations: BTreeMap<String, f64>,
    /// The time the state was recorded at, s (MJCF's `time`): kept, not used (an episode's
    /// time starts at 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
}

/// A floating base's start in a keyframe: its instance's frame in the world.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BaseKeyDef {
    /// The instance's origin, world mm.
    pub position: Vec3,
    /// Its orientation, a quaternion `[qw, qx, qy, qz]` (normalised on load).
    pub orientation: [f64; 4],
    /// Its origin's velocity, world mm/s; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear_velocity: Option<Vec3>,
    /// Its angular velocity, world deg/s; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular_velocity: Option<Vec3>,
}
