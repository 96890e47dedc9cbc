//! The tools' outputs, shaped as in the user guide, with their schemas. Server floats are
//! `f32`; each is widened through its shortest decimal form ([`clean`]) so that a pose of
//! `10.042` prints as `10.042`, not `10.041999816894531`.

use std::collections::BTreeMap;

use gymfleet_client::{
    ActuatorInfo, Autoreset, BatchInfo, EnvInfo, JointInfo, Observation, StepResult, POSE_LEN,
};
use schemars::JsonSchema;
use serde::Serialize;

/// `x` as the `f64` with the same shortest decimal form.
pub(crate) fn clean(x: f32) -> f64 {
    format!("{x}").parse().unwrap_or(f64::from(x))
}

fn clean_all(xs: &[f32]) -> Vec<f64> {
    xs.iter().copied().map(clean).collect()
}

/// One environment's observation.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct ObservationOut {
    /// Joint positions per DOF in document joint order: degrees (revolute) or mm
    /// (prismatic); measured, not targets.
    pub(crate) joint_positions: Vec<f64>,
    /// Joint velocities per DOF: degrees/s or mm/s.
    pub(crate) joint_velocities: Vec<f64>,
    /// One [x, y, z, qw, qx, qy, qz] per end effector, in end_effector_ids order: centre
    /// of mass in world mm, then the world orientation as a unit quaternion.
    pub(crate) end_effector_poses: Vec<[f64; POSE_LEN]>,
    /// With a reach task only: the target [x, y, z] in world mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) target: Option<[f64; 3]>,
    /// With a floating base only: its [x, y, z, qw, qx, qy, qz], centre of mass in world
    /// mm, then the world orientation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) base_pose: Option<[f64; POSE_LEN]>,
    /// With a floating base only: its centre of mass's velocity [vx, vy, vz] in world
    /// mm/s, then its angular velocity [wx, wy, wz] in world degrees/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) base_velocity: Option<[f64; 6]>,
    /// With free bodies only (objects, in free_bodies order): each one's [x, y, z, qw, qx,
    /// qy, qz], its frame's origin in world mm and its orientation.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) free_body_poses: Vec<[f64; POSE_LEN]>,
    /// With free bodies only: each one's [vx, vy, vz] in world mm/s, then its angular
    /// velocity [wx, wy, wz] in its own axes, degrees/s.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) free_body_velocities: Vec<[f64; 6]>,
}

/// A floating base's pose and velocity, if the observation has them.
fn base(pose: &[f32], velocity: &[f32]) -> (Option<[f64; POSE_LEN]>, Option<[f64; 6]>) {
    match (pose.len(), velocity.len()) {
        (POSE_LEN, 6) => (
            Some(std::array::from_fn(|i| clean(pose[i]))),
            Some(std::array::from_fn(|i| clean(velocity[i]))),
        ),
        _ => (None, None),
    }
}

/// A reach task's target from the task's part of an observation.
fn target(task: &[f32]) -> Option<[f64; 3]> {
    match task {
        [x, y, z] => Some([clean(*x), clean(*y), clean(*z)]),
        _ => None,
    }
}

impl From<&Observation> for ObservationOut {
    fn from(o: &Observation) -> Self {
        let (base_pose, base_velocity) = base(&o.base_pose, &o.base_velocity);
        ObservationOut {
            base_pose,
            base_velocity,
            joint_positions: clean_all(&o.joint_positions),
            joint_velocities: clean_all(&o.joint_velocities),
            end_effector_poses: o
                .end_effector_poses
                .iter()
                .map(|pose| pose.map(clean))
                .collect(),
            target: target(&o.task_observation),
            free_body_poses: o
                .free_body_poses
                .chunks_exact(POSE_LEN)
                .map(|c| std::array::from_fn(|i| clean(c[i])))
                .collect(),
            free_body_velocities: o
                .free_body_velocities
                .chunks_exact(6)
                .map(|c| std::array::from_fn(|i| clean(c[i])))
                .collect(),
        }
    }
}

impl ObservationOut {
    /// One row of a batch's flat observations, split along the batch's own layout.
    pub(crate) fn from_row(row: &[f32], layout: &[(String, usize)]) -> Self {
        ObservationOut::from(&Observation::from_flat(row, layout))
    }
}

/// The limits of one DOF.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct DofLimitOut {
    /// "deg" or "mm".
    pub(crate) unit: String,
    /// Lower hard stop in that unit, or null for none.
    pub(crate) min: Option<f64>,
    /// Upper hard stop in that unit, or null for none.
    pub(crate) max: Option<f64>,
}

/// One non-fixed joint.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct JointOut {
    /// The joint's name.
    pub(crate) name: String,
    /// "revolute", "prismatic", "cylindrical" or "ball".
    #[serde(rename = "type")]
    pub(crate) joint_type: String,
    /// DOFs (action values) it contributes.
    pub(crate) dof: usize,
    /// Parent instance name.
    pub(crate) parent: String,
    /// Child instance name.
    pub(crate) child: String,
    /// One entry per DOF.
    pub(crate) limits: Vec<DofLimitOut>,
    /// One per DOF: the largest sensible torque action value (N·m, N for a linear DOF, over
    /// the gear), the joint's max_effort, else twice what holds its subtree against gravity.
    pub(crate) torque_bounds: Vec<f64>,
}

fn joints(joints: &[JointInfo]) -> Vec<JointOut> {
    joints
        .iter()
        .map(|j| JointOut {
            name: j.name.clone(),
            joint_type: j.joint_type.clone(),
            dof: j.dof,
            parent: j.parent.clone(),
            child: j.child.clone(),
            limits: j
                .limits
                .iter()
                .map(|l| DofLimitOut {
                    unit: l.unit.clone(),
                    min: l.min,
                    max: l.max,
                })
                .collect(),
            torque_bounds: j.action_bounds.clone(),
        })
        .collect()
}

/// One actuator (a converted MJCF's `<actuator>`): its control is one action value, after
/// the actuated joints' values.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct ActuatorOut {
    /// The actuator's name.
    pub(crate) name: String,
    /// Its kind as written ("motor", "position", …; a converted MJCF's: "general").
    #[serde(rename = "type")]
    pub(crate) actuator_type: String,
    /// The joint or fixed tendon it drives.
    pub(crate) target: String,
    /// Controls are clamped into [min, max] (MuJoCo's ctrlrange); absent: unclamped.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) ctrl_range: Option<[f64; 2]>,
}

fn actuators(list: &[ActuatorInfo]) -> Vec<ActuatorOut> {
    list.iter()
        .map(|a| ActuatorOut {
            name: a.name.clone(),
            actuator_type: a.actuator_type.clone(),
            target: a.target.clone(),
            ctrl_range: a.ctrl_range,
        })
        .collect()
}

/// What an env is, as `create_robot_env` and `batch_create_envs` return it (a batch's
/// describes every env of it).
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct EnvShape {
    /// Non-fixed joints (per env).
    pub(crate) num_joints: usize,
    /// Values per action (per env action in a batch): the total DOF.
    pub(crate) action_dim: usize,
    /// Observation size: 2·action_dim + 7·(number of end effectors).
    pub(crate) observation_dim: usize,
    /// Observed end effectors, in observation order.
    pub(crate) end_effector_ids: Vec<String>,
    /// Seconds per step.
    pub(crate) dt: f64,
    /// Physics substeps per step.
    pub(crate) substeps: u32,
    /// Episode length in steps.
    pub(crate) max_steps: u32,
    /// The non-fixed joints in document order (the DOF order of actions and observations).
    pub(crate) joints: Vec<JointOut>,
    /// Objects that move freely, observed as free_body_poses and free_body_velocities.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) free_bodies: Vec<String>,
    /// Mocap bodies: kinematic handles gym_set_mocap_pose moves (and what is welded to
    /// them follows).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) mocap_bodies: Vec<String>,
    /// Actuators (only when there are any): the action's last values are their controls,
    /// in this order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) actuators: Vec<ActuatorOut>,
    /// Keyframes (only when there are any): named initial states gym_reset (batch_reset)
    /// may start from.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) keyframes: Vec<String>,
}

impl EnvShape {
    pub(crate) fn new(info: &EnvInfo) -> Self {
        EnvShape {
            num_joints: info.num_joints,
            action_dim: info.action_dim,
            observation_dim: info.observation_dim,
            end_effector_ids: info.end_effector_ids.clone(),
            dt: info.dt,
            substeps: info.substeps,
            max_steps: info.max_steps,
            joints: joints(&info.joints),
            free_bodies: info.free_bodies.clone(),
            mocap_bodies: info.mocap_bodies.clone(),
            actuators: actuators(&info.actuators),
            keyframes: info.keyframes.clone(),
        }
    }
}

/// What `create_robot_env` returns.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct EnvCreated {
    /// Handle for gym_reset, gym_step, gym_observe and gym_close, e.g. "sim_1".
    pub(crate) env_id: String,
    /// What the env is.
    #[serde(flatten)]
    pub(crate) shape: EnvShape,
}

impl EnvCreated {
    pub(crate) fn new(env_id: String, info: &EnvInfo) -> Self {
        EnvCreated {
            env_id,
            shape: EnvShape::new(info),
        }
    }
}

/// What `gym_step` returns.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct StepOut {
    /// The observation after the step.
    pub(crate) observation: ObservationOut,
    /// The step's reward: the task's (see the create tools' task), 0.0 without one.
    pub(crate) reward: f64,
    /// terminated || truncated: the episode is over; call gym_reset.
    pub(crate) done: bool,
    /// The episode ended for a task or physics reason.
    pub(crate) terminated: bool,
    /// The episode reached max_steps.
    pub(crate) truncated: bool,
    /// Why it terminated, when it did (e.g. "physics_diverged").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) termination_reason: Option<String>,
    /// A terms task's values for the step, by term name (the reward is the weighted sum).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub(crate) terms: BTreeMap<String, f64>,
}

/// A terms task's values by name.
pub(crate) fn terms(names: &[String], values: &[f32]) -> BTreeMap<String, f64> {
    names
        .iter()
        .zip(values)
        .map(|(n, v)| (n.clone(), clean(*v)))
        .collect()
}

impl StepOut {
    /// A step's result; `term_names` name its terms' values.
    pub(crate) fn new(r: &StepResult, term_names: &[String]) -> Self {
        StepOut {
            observation: ObservationOut::from(&r.observation),
            reward: clean(r.reward),
            done: r.done,
            terminated: r.terminated,
            truncated: r.truncated,
            termination_reason: r.termination_reason.clone(),
            terms: terms(term_names, &r.terms),
        }
    }
}

/// What `list_models` returns.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct ModelsOut {
    /// The server's model library, by name; empty when it has none.
    pub(crate) models: Vec<ModelOut>,
}

/// One model of the library.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct ModelOut {
    /// The name to give create_robot_env or batch_create_envs as `model`.
    pub(crate) name: String,
    /// Its file's format: "json" or "mjcf".
    pub(crate) format: String,
    /// Degrees of freedom.
    pub(crate) dofs: usize,
    /// Values per action.
    pub(crate) action_dim: usize,
}

/// What `gym_save_state` returns.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct StateSaved {
    /// The env whose state was saved.
    pub(crate) env_id: String,
    /// The whole state (document, episode, physics), base64: pass it to gym_load_state to
    /// return to this moment.
    pub(crate) state: String,
    /// The state's size in bytes (before base64).
    pub(crate) bytes: usize,
}

/// What `gym_close` returns.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct EnvClosed {
    /// The env that was closed; its id is no longer valid.
    pub(crate) env_id: String,
    /// Always true.
    pub(crate) closed: bool,
}

/// What `batch_create_envs` returns.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct BatchCreated {
    /// Handle for batch_step, batch_reset and batch_close, e.g. "batch_1".
    pub(crate) batch_id: String,
    /// Number of environments.
    pub(crate) n_envs: usize,
    /// "disabled", "same_step" or "next_step".
    pub(crate) autoreset: String,
    /// What every env is.
    #[serde(flatten)]
    pub(crate) shape: EnvShape,
}

impl BatchCreated {
    pub(crate) fn new(batch_id: String, info: &BatchInfo) -> Self {
        let autoreset = match info.autoreset {
            Autoreset::Disabled => "disabled",
            Autoreset::SameStep => "same_step",
            Autoreset::NextStep => "next_step",
        };
        BatchCreated {
            batch_id,
            n_envs: info.n_envs,
            autoreset: autoreset.to_string(),
            shape: EnvShape::new(&info.env),
        }
    }
}

/// One env's part of a batch step.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct EnvStepOut {
    /// The env's index in the batch (0-based; the order of the actions arrays).
    pub(crate) env_index: usize,
    /// The env's observation after the step (after its reset, with same_step autoreset).
    pub(crate) observation: ObservationOut,
    /// The env's reward.
    pub(crate) reward: f64,
    /// terminated || truncated.
    pub(crate) done: bool,
    /// The env's episode ended for a task or physics reason.
    pub(crate) terminated: bool,
    /// The env's episode reached max_steps.
    pub(crate) truncated: bool,
    /// Why it terminated, when it did.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) termination_reason: Option<String>,
    /// With same_step autoreset, the last observation of the episode that just ended.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) final_observation: Option<ObservationOut>,
    /// A terms task's values for the env's step, by term name.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub(crate) terms: BTreeMap<String, f64>,
}

/// What `batch_step` returns: results grouped by environment.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct BatchStepOut {
    /// The batch that was stepped.
    pub(crate) batch_id: String,
    /// One entry per env, env 0 first.
    pub(crate) results: Vec<EnvStepOut>,
}

/// What `batch_reset` returns.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct BatchObservationsOut {
    /// The batch that was reset.
    pub(crate) batch_id: String,
    /// One observation per env, env 0 first.
    pub(crate) observations: Vec<ObservationOut>,
}

/// What `batch_close` returns.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct BatchClosed {
    /// The batch that was closed; its id is no longer valid.
    pub(crate) batch_id: String,
    /// Always true.
    pub(crate) closed: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_widen_through_their_shortest_form() {
        assert_eq!(f64::from(10.042_f32), 10.041999816894531);
        assert_eq!(clean(10.042), 10.042);
        assert_eq!(clean(-0.001), -0.001);
        assert_eq!(clean(1e-7), 1e-7);
        assert_eq!(clean(3.4e38), 3.4e38);
        let text = serde_json::to_string(&[clean(24.997), clean(0.999)]).unwrap();
        assert_eq!(text, "[24.997,0.999]");
    }

    /// A one-DOF arm's layout with one end effector, or a floating base and none.
    fn layout(floating_base: bool) -> Vec<(String, usize)> {
        let mut segments = vec![("joint_positions", 1), ("joint_velocities", 1)];
        if floating_base {
            segments.extend([("base_pose", 7), ("base_velocity", 6)]);
        }
        segments.push(("end_effector_poses", if floating_base { 0 } else { 7 }));
        segments
            .into_iter()
            .map(|(n, s)| (n.to_string(), s))
            .collect()
    }

    #[test]
    fn rows_split_into_the_guide_layout() {
        let row = [0.12, 28.6, 10.042, 10.0, 24.997, 0.999, 0.0, 0.001, 0.0];
        let obs = ObservationOut::from_row(&row, &layout(false));
        let text = serde_json::to_string(&obs).unwrap();
        assert_eq!(
            text,
            r#"{"joint_positions":[0.12],"joint_velocities":[28.6],"end_effector_poses":[[10.042,10.0,24.997,0.999,0.0,0.001,0.0]]}"#
        );
    }

    #[test]
    fn a_floating_base_comes_before_the_poses() {
        let mut row = vec![0.5, -1.0];
        row.extend([50.0, 50.0, 510.0, 1.0, 0.0, 0.0, 0.0]);
        row.extend([0.0, 0.0, -981.0, 0.0, 0.0, 0.0]);
        let obs = ObservationOut::from_row(&row, &layout(true));
        let text = serde_json::to_string(&obs).unwrap();
        assert_eq!(
            text,
            r#"{"joint_positions":[0.5],"joint_velocities":[-1.0],"end_effector_poses":[],"base_pose":[50.0,50.0,510.0,1.0,0.0,0.0,0.0],"base_velocity":[0.0,0.0,-981.0,0.0,0.0,0.0]}"#
        );
    }
}

/// `gym_render`'s text and structured content (the picture itself is image content).
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct RenderOut {
    /// The env pictured.
    pub(crate) env_id: String,
    /// Image width in pixels.
    pub(crate) width: u32,
    /// Image height in pixels.
    pub(crate) height: u32,
    /// The distance between two ground-grid lines in mm (every fifth line is darker).
    pub(crate) grid_mm: f32,
    /// What the picture shows: camera, grid, marker colours, end effector and target positions.
    pub(crate) description: String,
}
