//! The observation: measured joint state, a floating base's state and end-effector poses.

/// Floats per end-effector pose: `[x, y, z, qw, qx, qy, qz]`.
pub const POSE_LEN: usize = 7;
/// Floats of a floating base's velocity: `[vx, vy, vz, wx, wy, wz]`.
pub const BASE_VELOCITY_LEN: usize = 6;

/// One observation, structured. Its flat form (see [`Observation::to_flat`]) is
/// positions, then velocities, then a floating base's pose and velocity, then the poses,
/// then the task's observation, `observation_dim` floats in all.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Observation {
    /// Measured joint positions per DOF: deg, mm, or a rotation vector in deg.
    pub joint_positions: Vec<f32>,
    /// Measured joint velocities per DOF: deg/s or mm/s.
    pub joint_velocities: Vec<f32>,
    /// A floating base's pose, as an end effector's (centre of mass in world mm, then the
    /// world orientation quaternion); empty when the first instance is grounded.
    pub base_pose: Vec<f32>,
    /// A floating base's velocity: its centre of mass's (world mm/s), then its angular
    /// velocity (world deg/s); empty when the first instance is grounded.
    pub base_velocity: Vec<f32>,
    /// Per end effector: centre of mass in world mm, then the world orientation quaternion.
    pub end_effector_poses: Vec<[f32; POSE_LEN]>,
    /// What the task adds (a reach task: its target, world mm); empty without a task.
    pub task: Vec<f32>,
}

/// One named run of floats of the flat observation, in order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ObservationSegment {
    /// `joint_positions`, `joint_velocities`, `base_pose`, `base_velocity`,
    /// `end_effector_poses` or `target`.
    pub name: &'static str,
    /// Floats in it.
    pub size: usize,
}

impl Observation {
    /// Splits a flat observation of `dof` DOFs, a floating base or not, and `poses` end
    /// effectors into its parts (the rest is the task's).
    pub fn from_flat(flat: &[f32], dof: usize, floating_base: bool, poses: usize) -> Self {
        let (positions, rest) = flat.split_at(dof);
        let (velocities, rest) = rest.split_at(dof);
        let base = if floating_base { POSE_LEN } else { 0 };
        let (base_pose, rest) = rest.split_at(base);
        let (base_velocity, rest) =
            rest.split_at(if floating_base { BASE_VELOCITY_LEN } else { 0 });
        let (poses, task) = rest.split_at(poses * POSE_LEN);
        Observation {
            joint_positions: positions.to_vec(),
            joint_velocities: velocities.to_vec(),
            base_pose: base_pose.to_vec(),
            base_velocity: base_velocity.to_vec(),
            end_effector_poses: poses
                .chunks_exact(POSE_LEN)
                .map(|c| {
                    let mut pose = [0.0; POSE_LEN];
                    pose.copy_from_slice(c);
                    pose
                })
                .collect(),
            task: task.to_vec(),
        }
    }

    /// The flat form: positions, velocities, the base's pose and velocity, poses, the
    /// task's part.
    pub fn to_flat(&self) -> Vec<f32> {
        let mut out = Vec::with_capacity(
            2 * self.joint_positions.len()
                + self.base_pose.len()
                + self.base_velocity.len()
                + POSE_LEN * self.end_effector_poses.len()
                + self.task.len(),
        );
        out.extend_from_slice(&self.joint_positions);
        out.extend_from_slice(&self.joint_velocities);
        out.extend_from_slice(&self.base_pose);
        out.extend_from_slice(&self.base_velocity);
        for pose in &self.end_effector_poses {
            out.extend_from_slice(pose);
        }
        out.extend_from_slice(&self.task);
        out
    }
}
