//! Client-side mirrors of the domain types (`ActionType`, `Autoreset`, `Observation`, ...)
//! and their conversions from the wire. The client does not link the physics, so these
//! are its own small types, named as in the domain.

use gymfleet_proto::v1 as pb;
pub use gymfleet_proto::v1::{DofUnit, JointType, TerminationReason};

use crate::error::{ClientError, Result};

mod compat;
pub(crate) use compat::typed_termination;
use compat::{flat_env_info, typed_or_named};

/// Floats per end-effector pose: `[x, y, z, qw, qx, qy, qz]`.
pub const POSE_LEN: usize = 7;

/// How a step's action values are interpreted (one value per DOF, in DOF order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ActionType {
    /// Efforts: N·m for rotational DOFs, N for linear ones.
    Torque,
    /// Position targets: deg or mm, tracked by a PD controller.
    Position,
    /// Velocity targets: deg/s or mm/s.
    Velocity,
}

impl From<ActionType> for pb::ActionType {
    fn from(a: ActionType) -> Self {
        match a {
            ActionType::Torque => pb::ActionType::Torque,
            ActionType::Position => pb::ActionType::Position,
            ActionType::Velocity => pb::ActionType::Velocity,
        }
    }
}

/// What a batch does with an environment whose episode ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Autoreset {
    /// Nothing; the client calls `reset`. The default.
    #[default]
    Disabled,
    /// Reset within the step that ended the episode; the final observation is returned
    /// beside it ([`crate::BatchStep::final_observation`]).
    SameStep,
    /// Gymnasium's default: reset on the next step, whose action is ignored.
    NextStep,
}

impl From<Autoreset> for pb::Autoreset {
    fn from(a: Autoreset) -> Self {
        match a {
            Autoreset::Disabled => pb::Autoreset::Disabled,
            Autoreset::SameStep => pb::Autoreset::SameStep,
            Autoreset::NextStep => pb::Autoreset::NextStep,
        }
    }
}

impl TryFrom<i32> for Autoreset {
    type Error = ClientError;

    fn try_from(raw: i32) -> Result<Self> {
        match pb::Autoreset::try_from(raw) {
            Ok(pb::Autoreset::Disabled) => Ok(Autoreset::Disabled),
            Ok(pb::Autoreset::SameStep) => Ok(Autoreset::SameStep),
            Ok(pb::Autoreset::NextStep) => Ok(Autoreset::NextStep),
            Err(_) => Err(ClientError::protocol(format!(
                "unknown autoreset value {raw}"
            ))),
        }
    }
}

/// One environment's observation: measured joint state and end-effector poses.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Observation {
    /// Joint positions per DOF, deg or mm.
    pub joint_positions: Vec<f32>,
    /// Joint velocities per DOF, deg/s or mm/s.
    pub joint_velocities: Vec<f32>,
    /// One `[x, y, z, qw, qx, qy, qz]` per end effector: centre of mass in world mm,
    /// then the world orientation.
    pub end_effector_poses: Vec<[f32; POSE_LEN]>,
    /// What the task adds: a reach task's target, world mm. Empty without one.
    pub task_observation: Vec<f32>,
    /// A floating base's `[x, y, z, qw, qx, qy, qz]` (centre of mass in world mm, world
    /// orientation); empty when the first instance is grounded.
    pub base_pose: Vec<f32>,
    /// A floating base's centre-of-mass velocity (world mm/s), then its angular velocity
    /// (world deg/s); empty when the first instance is grounded.
    pub base_velocity: Vec<f32>,
    /// Per free body ([`EnvInfo::free_bodies`]), `[x, y, z, qw, qx, qy, qz]`: its reference
    /// frame's origin (world mm) and orientation, MuJoCo's `qpos` of its free joint.
    pub free_body_poses: Vec<f32>,
    /// Per free body, its reference frame's origin's velocity (world mm/s), then its angular
    /// velocity in its own axes (deg/s): MuJoCo's `qvel` of its free joint.
    pub free_body_velocities: Vec<f32>,
}

/// The segment names of `observation_layout` on the wire (the env crate writes them;
/// any other name is the task's segment).
pub(crate) mod segment {
    /// Joint positions, one per DOF.
    pub(crate) const JOINT_POSITIONS: &str = "joint_positions";
    /// Joint velocities, one per DOF.
    pub(crate) const JOINT_VELOCITIES: &str = "joint_velocities";
    /// A floating base's pose.
    pub(crate) const BASE_POSE: &str = "base_pose";
    /// A floating base's velocity.
    pub(crate) const BASE_VELOCITY: &str = "base_velocity";
    /// The free bodies' poses.
    pub(crate) const FREE_BODY_POSES: &str = "free_body_poses";
    /// The free bodies' velocities.
    pub(crate) const FREE_BODY_VELOCITIES: &str = "free_body_velocities";
    /// The end effectors' poses.
    pub(crate) const END_EFFECTOR_POSES: &str = "end_effector_poses";
}

impl Observation {
    /// The flat row, segment by segment in `layout`'s order: the env's own layout, as
    /// [`EnvInfo::observation_layout`] and [`BatchInfo::observation_layout`] carry it.
    /// A segment of another name is the task's.
    pub fn to_flat(&self, layout: &[(String, usize)]) -> Vec<f32> {
        let mut out = Vec::with_capacity(layout.iter().map(|(_, size)| size).sum());
        for (name, _) in layout {
            out.extend_from_slice(match name.as_str() {
                segment::JOINT_POSITIONS => &self.joint_positions,
                segment::JOINT_VELOCITIES => &self.joint_velocities,
                segment::BASE_POSE => &self.base_pose,
                segment::BASE_VELOCITY => &self.base_velocity,
                segment::FREE_BODY_POSES => &self.free_body_poses,
                segment::FREE_BODY_VELOCITIES => &self.free_body_velocities,
                segment::END_EFFECTOR_POSES => self.end_effector_poses.as_flattened(),
                _ => &self.task_observation,
            });
        }
        out
    }

    /// One flat row (of a batch's observations) read back, segment by segment as
    /// `layout` names them; a segment past the row's end is cut short.
    pub fn from_flat(row: &[f32], layout: &[(String, usize)]) -> Self {
        let mut o = Observation::default();
        let mut rest = row;
        for (name, size) in layout {
            let (part, tail) = rest.split_at((*size).min(rest.len()));
            rest = tail;
            let part = part.to_vec();
            match name.as_str() {
                segment::JOINT_POSITIONS => o.joint_positions = part,
                segment::JOINT_VELOCITIES => o.joint_velocities = part,
                segment::BASE_POSE => o.base_pose = part,
                segment::BASE_VELOCITY => o.base_velocity = part,
                segment::FREE_BODY_POSES => o.free_body_poses = part,
                segment::FREE_BODY_VELOCITIES => o.free_body_velocities = part,
                segment::END_EFFECTOR_POSES => {
                    o.end_effector_poses = part
                        .chunks_exact(POSE_LEN)
                        .map(|c| std::array::from_fn(|i| c[i]))
                        .collect();
                }
                _ => o.task_observation = part,
            }
        }
        o
    }
}

impl TryFrom<pb::Observation> for Observation {
    type Error = ClientError;

    fn try_from(o: pb::Observation) -> Result<Self> {
        if !o.end_effector_poses.len().is_multiple_of(POSE_LEN) {
            return Err(ClientError::protocol(format!(
                "observation: {} pose values is not a multiple of {POSE_LEN}",
                o.end_effector_poses.len()
            )));
        }
        let base = (o.base_pose.len(), o.base_velocity.len());
        if base != (0, 0) && base != (POSE_LEN, 6) {
            return Err(ClientError::protocol(format!(
                "observation: a floating base has {POSE_LEN} pose and 6 velocity values, got {} and {}",
                base.0, base.1
            )));
        }
        let free = (o.free_body_poses.len(), o.free_body_velocities.len());
        if !free.0.is_multiple_of(POSE_LEN) || free.0 / POSE_LEN * 6 != free.1 {
            return Err(ClientError::protocol(format!(
                "observation: free bodies have {POSE_LEN} pose and 6 velocity values each, got {} and {}",
                free.0, free.1
            )));
        }
        let end_effector_poses = o
            .end_effector_poses
            .chunks_exact(POSE_LEN)
            .map(|c| {
                let mut pose = [0.0; POSE_LEN];
                pose.copy_from_slice(c);
                pose
            })
            .collect();
        Ok(Observation {
            joint_positions: o.joint_positions,
            joint_velocities: o.joint_velocities,
            end_effector_poses,
            task_observation: o.task_observation,
            base_pose: o.base_pose,
            base_velocity: o.base_velocity,
            free_body_poses: o.free_body_poses,
            free_body_velocities: o.free_body_velocities,
        })
    }
}

/// The outcome of one single-env step.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepResult {
    /// The observation after the step.
    pub observation: Observation,
    /// The step's reward (0 unless the env defines a task).
    pub reward: f32,
    /// The episode ended for a task or physics reason.
    pub terminated: bool,
    /// The episode reached `max_steps`.
    pub truncated: bool,
    /// `terminated || truncated`.
    pub done: bool,
    /// Why the episode terminated, e.g. `physics_diverged`.
    pub termination_reason: Option<String>,
    /// The same reason, typed (`None` with no reason, or from a server that sends only
    /// the string).
    pub termination: Option<TerminationReason>,
    /// Steps taken in the current episode, this one included.
    pub episode_step: u32,
    /// A terms task's values for this step, in [`EnvInfo::term_names`] order.
    pub terms: Vec<f32>,
}

impl TryFrom<pb::StepResult> for StepResult {
    type Error = ClientError;

    fn try_from(r: pb::StepResult) -> Result<Self> {
        let observation = r
            .observation
            .ok_or_else(|| ClientError::protocol("step result without an observation"))?;
        Ok(StepResult {
            observation: observation.try_into()?,
            reward: r.reward,
            terminated: r.terminated,
            truncated: r.truncated,
            done: r.done,
            termination_reason: r.termination_reason,
            termination: typed_termination(r.termination),
            episode_step: r.episode_step,
            terms: r.terms,
        })
    }
}

/// The limits of one DOF.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DofLimit {
    /// `"deg"` or `"mm"`.
    pub unit: String,
    /// The same unit, typed.
    pub dof_unit: DofUnit,
    /// Lower hard stop, if any.
    pub min: Option<f64>,
    /// Upper hard stop, if any.
    pub max: Option<f64>,
}

/// One non-fixed joint, in document order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointInfo {
    /// The joint's name.
    pub name: String,
    /// `"revolute"`, `"prismatic"`, `"cylindrical"` or `"ball"`.
    pub joint_type: String,
    /// The same type, typed.
    pub kind: JointType,
    /// DOFs it contributes.
    pub dof: usize,
    /// One per DOF.
    pub limits: Vec<DofLimit>,
    /// Parent instance name.
    pub parent: String,
    /// Child instance name.
    pub child: String,
    /// The effort clamp of each of its DOFs, N·m or N; `None`: unclamped.
    pub max_effort: Option<f64>,
    /// Whether it is driven; a passive joint's DOFs are observed but take no action.
    pub actuated: bool,
    /// The motor's gear: a torque action value is a control signal, the effort
    /// `gear ×` it (bound `max_effort / |gear|`). 1: values are efforts.
    pub gear: f64,
    /// The position the joint reports at the document's pose (deg or mm).
    pub reference: f64,
    /// One per DOF: the bound of a torque action value (`max_effort / |gear|`, or the
    /// server's model-derived default without a `max_effort`); empty from older servers.
    pub action_bounds: Vec<f64>,
}

impl From<pb::JointInfo> for JointInfo {
    fn from(j: pb::JointInfo) -> Self {
        JointInfo {
            name: j.name,
            // A server from before the enums sends only the strings.
            kind: typed_or_named(j.kind, &j.r#type, "JOINT_TYPE_"),
            joint_type: j.r#type,
            dof: j.dof as usize,
            limits: j
                .limits
                .into_iter()
                .map(|l| DofLimit {
                    dof_unit: typed_or_named(l.dof_unit, &l.unit, "DOF_UNIT_"),
                    unit: l.unit,
                    min: l.min,
                    max: l.max,
                })
                .collect(),
            parent: j.parent,
            child: j.child,
            max_effort: j.max_effort,
            actuated: j.actuated,
            // Servers before gears sent nothing: 0 reads as 1.
            gear: if j.gear == 0.0 { 1.0 } else { j.gear },
            reference: j.reference,
            action_bounds: j.action_bounds,
        }
    }
}

/// One actuator (the document's `assembly.actuators`, MJCF's `<actuator>` elements): its
/// control is one action value, after the actuated joints' values.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ActuatorInfo {
    /// Its name.
    pub name: String,
    /// Its kind as written (`"motor"`, `"position"`, …; a converted MJCF's: `"general"`).
    pub actuator_type: String,
    /// The joint or fixed tendon it drives.
    pub target: String,
    /// Controls are clamped into `[min, max]` (MuJoCo's `ctrlrange`); `None`: unclamped.
    pub ctrl_range: Option<[f64; 2]>,
}

impl From<pb::ActuatorInfo> for ActuatorInfo {
    fn from(a: pb::ActuatorInfo) -> Self {
        ActuatorInfo {
            name: a.name,
            actuator_type: a.r#type,
            target: a.target,
            ctrl_range: a.ctrl_min.zip(a.ctrl_max).map(|(lo, hi)| [lo, hi]),
        }
    }
}

/// Describes a created environment.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EnvInfo {
    /// `"sim_<n>"`.
    pub env_id: String,
    /// Non-fixed joints.
    pub num_joints: usize,
    /// Values per action (the actuated joints' DOFs, then one per actuator).
    pub action_dim: usize,
    /// `2·DOF + 7·end effectors` + the task's floats.
    pub observation_dim: usize,
    /// Observed end effectors, in order.
    pub end_effector_ids: Vec<String>,
    /// Seconds per step.
    pub dt: f64,
    /// Physics substeps per step.
    pub substeps: u32,
    /// Episode length in steps.
    pub max_steps: u32,
    /// The non-fixed joints, in document order.
    pub joints: Vec<JointInfo>,
    /// The observation's segments, `(name, size)` in order.
    pub observation_layout: Vec<(String, usize)>,
    /// The observation's units.
    pub units: Units,
    /// A terms task's term names, in the order of [`StepResult::terms`].
    pub term_names: Vec<String>,
    /// The free bodies (objects and robots joined to nothing), in the order
    /// [`Observation::free_body_poses`] lists them.
    pub free_bodies: Vec<String>,
    /// The mocap bodies, in the order a step's mocap targets give them.
    pub mocap_bodies: Vec<String>,
    /// The mass of everything that moves (neither fixed to the world nor a mocap body), kg.
    pub moving_mass: f64,
    /// The actuators, in order: the action's last `actuators.len()` values.
    pub actuators: Vec<ActuatorInfo>,
    /// The document's keyframes (named initial states), in order: what
    /// [`crate::Env::reset_to`] may name.
    pub keyframes: Vec<String>,
    /// The heightfields (terrain): name, rows, columns; what `set_heightfield` names.
    pub heightfields: Vec<(String, usize, usize)>,
}

/// The units of observations and of a terms task's values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Units {
    /// The document's: deg or mm (and per second), world mm.
    #[default]
    Document,
    /// SI, as MuJoCo and Gymnasium report them: rad or m (and per second), world m.
    Si,
}

impl From<Units> for pb::Units {
    fn from(u: Units) -> Self {
        match u {
            Units::Document => pb::Units::Document,
            Units::Si => pb::Units::Si,
        }
    }
}

impl Units {
    fn from_wire(raw: i32) -> Self {
        match pb::Units::try_from(raw) {
            Ok(pb::Units::Si) => Units::Si,
            _ => Units::Document,
        }
    }
}

/// The observed DOFs (passive joints' included): the `joint_positions` segment's size.
fn observed_dofs(layout: &[(String, usize)], action_dim: usize) -> usize {
    layout
        .iter()
        .find(|(name, _)| name == segment::JOINT_POSITIONS)
        .map_or(action_dim, |(_, size)| *size)
}

/// Whether the layout has a floating base's segments.
fn floats(layout: &[(String, usize)]) -> bool {
    layout.iter().any(|(name, _)| name == segment::BASE_POSE)
}

impl EnvInfo {
    /// Every DOF's count, passive joints' included (positions per observation).
    pub fn num_dofs(&self) -> usize {
        observed_dofs(&self.observation_layout, self.action_dim)
    }

    /// Whether the env's first instance is a floating base (observed as `base_pose` and
    /// `base_velocity`).
    pub fn floating_base(&self) -> bool {
        floats(&self.observation_layout)
    }
}

fn layout(segments: Vec<pb::ObservationSegment>) -> Vec<(String, usize)> {
    segments
        .into_iter()
        .map(|s| (s.name, s.size as usize))
        .collect()
}

impl From<pb::EnvInfo> for EnvInfo {
    fn from(i: pb::EnvInfo) -> Self {
        EnvInfo {
            env_id: i.env_id,
            num_joints: i.num_joints as usize,
            action_dim: i.action_dim as usize,
            observation_dim: i.observation_dim as usize,
            end_effector_ids: i.end_effector_ids,
            dt: i.dt,
            substeps: i.substeps,
            max_steps: i.max_steps,
            joints: i.joints.into_iter().map(Into::into).collect(),
            observation_layout: layout(i.observation_layout),
            units: Units::from_wire(i.units),
            term_names: i.term_names,
            free_bodies: i.free_bodies,
            mocap_bodies: i.mocap_bodies,
            moving_mass: i.moving_mass,
            actuators: i.actuators.into_iter().map(Into::into).collect(),
            keyframes: i.keyframes,
            heightfields: i
                .heightfields
                .into_iter()
                .map(|h| (h.name, h.rows as usize, h.columns as usize))
                .collect(),
        }
    }
}

/// Describes a created batch; every env of it has this shape.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BatchInfo {
    /// The batch id, `"batch_<n>"`.
    pub batch_id: String,
    /// Number of environments.
    pub n_envs: usize,
    /// What happens to finished envs.
    pub autoreset: Autoreset,
    /// What every env of the batch is (its `env_id` empty); its fields read through
    /// `BatchInfo` too (`info.observation_dim`).
    pub env: EnvInfo,
}

impl std::ops::Deref for BatchInfo {
    type Target = EnvInfo;

    fn deref(&self) -> &EnvInfo {
        &self.env
    }
}

impl std::ops::DerefMut for BatchInfo {
    fn deref_mut(&mut self) -> &mut EnvInfo {
        &mut self.env
    }
}

impl TryFrom<pb::BatchInfo> for BatchInfo {
    type Error = ClientError;

    fn try_from(mut i: pb::BatchInfo) -> Result<Self> {
        let env = match i.env.take() {
            Some(env) => env,
            // A server from before `BatchInfo.env`: the same description, flat.
            None => flat_env_info(i.clone()),
        };
        Ok(BatchInfo {
            autoreset: Autoreset::try_from(i.autoreset)?,
            batch_id: i.batch_id,
            n_envs: i.n_envs as usize,
            env: env.into(),
        })
    }
}

/// The limits a server enforces; 0 means no limit.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ServerLimits {
    /// Most environments held at once.
    pub max_envs: u64,
    /// Most environments in one batch.
    pub max_batch_size: u64,
    /// Largest accepted document, bytes.
    pub max_document_bytes: u64,
    /// Largest gRPC message, bytes.
    pub max_message_bytes: u64,
    /// Idle time after which envs and batches are closed, s (0: never).
    pub idle_ttl_seconds: u64,
    /// Most instances per document.
    pub max_instances: u64,
    /// Most joints per document.
    pub max_joints: u64,
    /// Most DOFs per document.
    pub max_dofs: u64,
    /// Most end effectors per env.
    pub max_end_effectors: u64,
    /// Most environments one tenant holds at once.
    pub tenant_max_envs: u64,
    /// Most work per step call, in DOF-substeps (envs × substeps × DOFs).
    pub max_step_work: u64,
    /// Most contact work per env step, in contact point-substeps (contact points ×
    /// substeps).
    pub max_contact_work: u64,
}

/// Describes a server.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ServerInfo {
    /// The server's version.
    pub version: String,
    /// Worker threads in its simulation pool.
    pub threads: u32,
    /// Single environments open (the caller's own, when the server requires tokens).
    pub envs: u64,
    /// Batches open (the caller's own, when the server requires tokens).
    pub batches: u64,
    /// Environments held in open batches (the caller's own, when the server requires
    /// tokens).
    pub batch_envs: u64,
    /// Its limits.
    pub limits: ServerLimits,
    /// The caller's tenant, from its token; empty when the server requires none.
    pub tenant: String,
    /// Whether the server requires a token.
    pub auth_required: bool,
    /// A random id, new at every start of the server process: if it changes between two
    /// calls, the server restarted and every env and batch it held is gone.
    pub instance_id: String,
}

impl From<pb::ServerInfo> for ServerInfo {
    fn from(i: pb::ServerInfo) -> Self {
        let l = i.limits.unwrap_or_default();
        ServerInfo {
            version: i.version,
            threads: i.threads,
            envs: i.envs,
            batches: i.batches,
            batch_envs: i.batch_envs,
            limits: ServerLimits {
                max_envs: l.max_envs,
                max_batch_size: l.max_batch_size,
                max_document_bytes: l.max_document_bytes,
                max_message_bytes: l.max_message_bytes,
                idle_ttl_seconds: l.idle_ttl_seconds,
                max_instances: l.max_instances,
                max_joints: l.max_joints,
                max_dofs: l.max_dofs,
                max_end_effectors: l.max_end_effectors,
                tenant_max_envs: l.tenant_max_envs,
                max_step_work: l.max_step_work,
                max_contact_work: l.max_contact_work,
            },
            tenant: i.tenant,
            auth_required: i.auth_required,
            instance_id: i.instance_id,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout_of(segments: &[(&str, usize)]) -> Vec<(String, usize)> {
        segments.iter().map(|&(n, s)| (n.to_string(), s)).collect()
    }

    #[test]
    fn observations_unpack_poses() {
        let o = Observation::try_from(pb::Observation {
            joint_positions: vec![1.0],
            joint_velocities: vec![2.0],
            end_effector_poses: vec![10.0, 10.0, 25.0, 1.0, 0.0, 0.0, 0.0],
            task_observation: vec![20.0, 0.0, 40.0],
            ..Default::default()
        })
        .unwrap();
        assert_eq!(
            o.end_effector_poses,
            [[10.0, 10.0, 25.0, 1.0, 0.0, 0.0, 0.0]]
        );
        assert_eq!(o.task_observation, [20.0, 0.0, 40.0]);
        let layout = layout_of(&[
            ("joint_positions", 1),
            ("joint_velocities", 1),
            ("end_effector_poses", 7),
            ("target", 3),
        ]);
        let flat = o.to_flat(&layout);
        assert_eq!(flat.len(), 12);
        assert_eq!(Observation::from_flat(&flat, &layout), o);
        let bad = pb::Observation {
            end_effector_poses: vec![0.0; 8],
            ..Default::default()
        };
        assert!(matches!(
            Observation::try_from(bad),
            Err(ClientError::Protocol { .. })
        ));
    }

    #[test]
    fn a_floating_base_comes_between_the_joints_and_the_poses() {
        let o = Observation::try_from(pb::Observation {
            joint_positions: vec![1.0],
            joint_velocities: vec![2.0],
            base_pose: vec![3.0, 4.0, 5.0, 1.0, 0.0, 0.0, 0.0],
            base_velocity: vec![6.0, 7.0, 8.0, 9.0, 10.0, 11.0],
            end_effector_poses: vec![10.0, 10.0, 25.0, 1.0, 0.0, 0.0, 0.0],
            ..Default::default()
        })
        .unwrap();
        // The order is the layout's (the server's), not this crate's.
        let layout = layout_of(&[
            ("joint_positions", 1),
            ("joint_velocities", 1),
            ("base_pose", 7),
            ("base_velocity", 6),
            ("end_effector_poses", 7),
        ]);
        let flat = o.to_flat(&layout);
        assert_eq!(flat.len(), 2 + 13 + 7);
        assert_eq!(flat[2..4], [3.0, 4.0]);
        assert_eq!(flat[15], 10.0);
        assert_eq!(Observation::from_flat(&flat, &layout), o);
        let reversed: Vec<_> = layout.iter().rev().cloned().collect();
        assert_eq!(
            o.to_flat(&reversed)[..7],
            [10.0, 10.0, 25.0, 1.0, 0.0, 0.0, 0.0]
        );
        let bad = pb::Observation {
            base_pose: vec![0.0; 7],
            base_velocity: vec![0.0; 3],
            ..Default::default()
        };
        let err = Observation::try_from(bad).unwrap_err().to_string();
        assert!(
            err.contains("a floating base has 7 pose and 6 velocity values, got 7 and 3"),
            "{err}"
        );
    }
}
