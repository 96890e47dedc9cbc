//! The observation: measured joint state, a floating base's state, the free bodies' states
//! and end-effector poses.

/// Floats per end-effector pose: `[x, y, z, qw, qx, qy, qz]`.
pub const POSE_LEN: usize = 7;
/// Floats of a floating base's velocity: `[vx, vy, vz, wx, wy, wz]`.
pub const BASE_VELOCITY_LEN: usize = 6;
pub use gymfleet_physics::{FREE_POSE_LEN, FREE_VELOCITY_LEN};

/// One observation, structured. Its flat form (see [`Observation::to_flat`]) is the
/// segments of [`layout`] in order, `observation_dim` floats in all.
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
    /// Per free body ([`crate::EnvSpec::free_bodies`]), its reference frame's pose
    /// (world mm, then the orientation `[qw, qx, qy, qz]`): MuJoCo's `qpos` of its free
    /// joint.
    pub free_body_poses: Vec<f32>,
    /// Per free body, its reference frame's velocity (world mm/s), then its angular velocity
    /// in its own axes (deg/s): MuJoCo's `qvel` of its free joint.
    pub free_body_velocities: Vec<f32>,
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

/// The segment names of the flat observation, as [`ObservationSegment::name`] and the
/// wire's `observation_layout` spell them. A task's segment has its own name.
pub mod segment {
    /// Measured joint positions, one per DOF.
    pub const JOINT_POSITIONS: &str = "joint_positions";
    /// Measured joint velocities, one per DOF.
    pub const JOINT_VELOCITIES: &str = "joint_velocities";
    /// A floating base's pose ([`super::POSE_LEN`] floats).
    pub const BASE_POSE: &str = "base_pose";
    /// A floating base's velocity ([`super::BASE_VELOCITY_LEN`] floats).
    pub const BASE_VELOCITY: &str = "base_velocity";
    /// The free bodies' poses ([`super::FREE_POSE_LEN`] floats each).
    pub const FREE_BODY_POSES: &str = "free_body_poses";
    /// The free bodies' velocities ([`super::FREE_VELOCITY_LEN`] floats each).
    pub const FREE_BODY_VELOCITIES: &str = "free_body_velocities";
    /// One pose per end effector.
    pub const END_EFFECTOR_POSES: &str = "end_effector_poses";
}

/// What an observation holds, by count: the sizes [`layout`] lays out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Observed {
    /// DOFs (their positions, and their velocities).
    pub dofs: usize,
    /// Whether the first instance is a floating base.
    pub floating_base: bool,
    /// Free bodies.
    pub free_bodies: usize,
    /// End effectors.
    pub end_effectors: usize,
}

/// The flat observation's segments, in order: the one place the order is written.
/// `task`: the task's segment (its name and size), if it has one. A floating base's and
/// the free bodies' segments are left out when there are none.
pub fn layout(observed: Observed, task: Option<(&'static str, usize)>) -> Vec<ObservationSegment> {
    let segment = |name, size| ObservationSegment { name, size };
    let mut out = vec![
        segment(segment::JOINT_POSITIONS, observed.dofs),
        segment(segment::JOINT_VELOCITIES, observed.dofs),
    ];
    if observed.floating_base {
        out.push(segment(segment::BASE_POSE, POSE_LEN));
        out.push(segment(segment::BASE_VELOCITY, BASE_VELOCITY_LEN));
    }
    if observed.free_bodies > 0 {
        let n = observed.free_bodies;
        out.push(segment(segment::FREE_BODY_POSES, FREE_POSE_LEN * n));
        out.push(segment(
            segment::FREE_BODY_VELOCITIES,
            FREE_VELOCITY_LEN * n,
        ));
    }
    let end_effectors = observed.end_effectors;
    out.push(segment(
        segment::END_EFFECTOR_POSES,
        POSE_LEN * end_effectors,
    ));
    out.extend(task.map(|(name, size)| segment(name, size)));
    out
}

/// A flat observation's parts, borrowed: what [`layout`] names, read back segment by
/// segment. A part the layout lacks is empty.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ObservationParts<'a> {
    /// Joint positions per DOF.
    pub joint_positions: &'a [f32],
    /// Joint velocities per DOF.
    pub joint_velocities: &'a [f32],
    /// A floating base's pose.
    pub base_pose: &'a [f32],
    /// A floating base's velocity.
    pub base_velocity: &'a [f32],
    /// The free bodies' poses.
    pub free_body_poses: &'a [f32],
    /// The free bodies' velocities.
    pub free_body_velocities: &'a [f32],
    /// The end effectors' poses, [`POSE_LEN`] floats each.
    pub end_effector_poses: &'a [f32],
    /// The task's segment.
    pub task: &'a [f32],
}

impl<'a> ObservationParts<'a> {
    /// Splits `flat` along `layout`; a segment past the end of `flat` is cut short.
    pub fn split(layout: &[ObservationSegment], flat: &'a [f32]) -> Self {
        let mut parts = ObservationParts::default();
        let mut rest = flat;
        for s in layout {
            let (part, tail) = rest.split_at(s.size.min(rest.len()));
            rest = tail;
            *parts.slot(s.name) = part;
        }
        parts
    }

    fn slot(&mut self, name: &str) -> &mut &'a [f32] {
        match name {
            segment::JOINT_POSITIONS => &mut self.joint_positions,
            segment::JOINT_VELOCITIES => &mut self.joint_velocities,
            segment::BASE_POSE => &mut self.base_pose,
            segment::BASE_VELOCITY => &mut self.base_velocity,
            segment::FREE_BODY_POSES => &mut self.free_body_poses,
            segment::FREE_BODY_VELOCITIES => &mut self.free_body_velocities,
            segment::END_EFFECTOR_POSES => &mut self.end_effector_poses,
            _ => &mut self.task,
        }
    }
}

impl Observation {
    /// Splits a flat observation into its parts along `layout`.
    pub fn from_flat(flat: &[f32], layout: &[ObservationSegment]) -> Self {
        let parts = ObservationParts::split(layout, flat);
        Observation {
            joint_positions: parts.joint_positions.to_vec(),
            joint_velocities: parts.joint_velocities.to_vec(),
            base_pose: parts.base_pose.to_vec(),
            base_velocity: parts.base_velocity.to_vec(),
            free_body_poses: parts.free_body_poses.to_vec(),
            free_body_velocities: parts.free_body_velocities.to_vec(),
            end_effector_poses: parts
                .end_effector_poses
                .chunks_exact(POSE_LEN)
                .map(|c| std::array::from_fn(|i| c[i]))
                .collect(),
            task: parts.task.to_vec(),
        }
    }

    /// The flat form, in [`layout`]'s order.
    pub fn to_flat(&self) -> Vec<f32> {
        let task = Some(("task", self.task.len()));
        let layout = layout(
            Observed {
                dofs: self.joint_positions.len(),
                floating_base: !self.base_pose.is_empty(),
                free_bodies: self.free_body_poses.len() / FREE_POSE_LEN,
                end_effectors: self.end_effector_poses.len(),
            },
            task,
        );
        let mut out = Vec::with_capacity(layout.iter().map(|s| s.size).sum());
        for s in &layout {
            out.extend_from_slice(match s.name {
                segment::JOINT_POSITIONS => &self.joint_positions,
                segment::JOINT_VELOCITIES => &self.joint_velocities,
                segment::BASE_POSE => &self.base_pose,
                segment::BASE_VELOCITY => &self.base_velocity,
                segment::FREE_BODY_POSES => &self.free_body_poses,
                segment::FREE_BODY_VELOCITIES => &self.free_body_velocities,
                segment::END_EFFECTOR_POSES => self.end_effector_poses.as_flattened(),
                _ => &self.task,
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_observation_splits_and_joins_along_the_layout() {
        let observed = Observed {
            dofs: 2,
            floating_base: true,
            free_bodies: 2,
            end_effectors: 1,
        };
        let layout = layout(observed, Some(("target", 3)));
        let names: Vec<_> = layout.iter().map(|s| s.name).collect();
        assert_eq!(
            names,
            [
                "joint_positions",
                "joint_velocities",
                "base_pose",
                "base_velocity",
                "free_body_poses",
                "free_body_velocities",
                "end_effector_poses",
                "target"
            ]
        );
        let n = 2 + 2 + 7 + 6 + 14 + 12 + 7 + 3;
        let flat: Vec<f32> = (0..n).map(|i| i as f32).collect();
        let parts = ObservationParts::split(&layout, &flat);
        assert_eq!(parts.joint_velocities, [2.0, 3.0]);
        assert_eq!(parts.base_pose[0], 4.0);
        assert_eq!(parts.base_velocity[0], 11.0);
        assert_eq!(parts.free_body_poses.len(), 14);
        assert_eq!(parts.free_body_poses[0], 17.0);
        assert_eq!(parts.free_body_velocities[0], 31.0);
        assert_eq!(parts.end_effector_poses[0], 43.0);
        assert_eq!(parts.task, [50.0, 51.0, 52.0]);
        let o = Observation::from_flat(&flat, &layout);
        assert_eq!(
            o.end_effector_poses,
            [[43.0, 44.0, 45.0, 46.0, 47.0, 48.0, 49.0]]
        );
        assert_eq!(o.to_flat(), flat);
    }

    #[test]
    fn a_grounded_observation_without_a_task_has_no_base_or_task_part() {
        let layout = layout(
            Observed {
                dofs: 1,
                ..Observed::default()
            },
            None,
        );
        let parts = ObservationParts::split(&layout, &[1.0, 2.0]);
        assert_eq!(
            (parts.joint_positions, parts.joint_velocities),
            (&[1.0][..], &[2.0][..])
        );
        assert!(parts.base_pose.is_empty() && parts.task.is_empty());
        assert_eq!(
            Observation::from_flat(&[1.0, 2.0], &layout).to_flat(),
            [1.0, 2.0]
        );
    }
}
