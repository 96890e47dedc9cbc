//! The observation: measured joint state and end-effector poses.

/// Floats per end-effector pose: `[x, y, z, qw, qx, qy, qz]`.
pub const POSE_LEN: usize = 7;

/// One observation, structured. Its flat form (see [`Observation::to_flat`]) is
/// positions, then velocities, then the poses, then the task's observation,
/// `observation_dim` floats in all.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Observation {
    /// Measured joint positions per DOF: deg, mm, or a rotation vector in deg.
    pub joint_positions: Vec<f32>,
    /// Measured joint velocities per DOF: deg/s or mm/s.
    pub joint_velocities: Vec<f32>,
    /// Per end effector: centre of mass in world mm, then the world orientation quaternion.
    pub end_effector_poses: Vec<[f32; POSE_LEN]>,
    /// What the task adds (a reach task: its target, world mm); empty without a task.
    pub task: Vec<f32>,
}

/// One named run of floats of the flat observation, in order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ObservationSegment {
    /// `joint_positions`, `joint_velocities`, `end_effector_poses` or `target`.
    pub name: &'static str,
    /// Floats in it.
    pub size: usize,
}

impl Observation {
    /// Splits a flat observation of `dof` DOFs and `poses` end effectors into its parts
    /// (the rest is the task's).
    pub fn from_flat(flat: &[f32], dof: usize, poses: usize) -> Self {
        let (positions, rest) = flat.split_at(dof);
        let (velocities, rest) = rest.split_at(dof);
        let (poses, task) = rest.split_at(poses * POSE_LEN);
        Observation {
            joint_positions: positions.to_vec(),
            joint_velocities: velocities.to_vec(),
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

    /// The flat form: positions, velocities, poses, the task's part.
    pub fn to_flat(&self) -> Vec<f32> {
        let mut out = Vec::with_capacity(
            2 * self.joint_positions.len()
                + POSE_LEN * self.end_effector_poses.len()
                + self.task.len(),
        );
        out.extend_from_slice(&self.joint_positions);
        out.extend_from_slice(&self.joint_velocities);
        for pose in &self.end_effector_poses {
            out.extend_from_slice(pose);
        }
        out.extend_from_slice(&self.task);
        out
    }
}
