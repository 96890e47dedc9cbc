//! The observation: measured joint state, a floating base's state and end-effector poses.

/// Floats per end-effector pose: `[x, y, z, qw, qx, qy, qz]`.
pub const POSE_LEN: usize = 7;
/// Floats of a floating base's velocity: `[vx, vy, vz, wx, wy, wz]`.
pub const BASE_VELOCITY_LEN: usize = 6;

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
    /// One pose per end effector.
    pub const END_EFFECTOR_POSES: &str = "end_effector_poses";
}

/// The flat observation's segments, in order: the one place the order is written.
/// `task`: the task's segment (its name and size), if it has one.
pub fn layout(
    dofs: usize,
    floating_base: bool,
    end_effectors: usize,
    task: Option<(&'static str, usize)>,
) -> Vec<ObservationSegment> {
    let segment = |name, size| ObservationSegment { name, size };
    let mut out = vec![
        segment(segment::JOINT_POSITIONS, dofs),
        segment(segment::JOINT_VELOCITIES, dofs),
    ];
    if floating_base {
        out.push(segment(segment::BASE_POSE, POSE_LEN));
        out.push(segment(segment::BASE_VELOCITY, BASE_VELOCITY_LEN));
    }
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
        let floating_base = !self.base_pose.is_empty();
        let task = Some(("task", self.task.len()));
        let layout = layout(
            self.joint_positions.len(),
            floating_base,
            self.end_effector_poses.len(),
            task,
        );
        let mut out = Vec::with_capacity(layout.iter().map(|s| s.size).sum());
        for s in &layout {
            out.extend_from_slice(match s.name {
                segment::JOINT_POSITIONS => &self.joint_positions,
                segment::JOINT_VELOCITIES => &self.joint_velocities,
                segment::BASE_POSE => &self.base_pose,
                segment::BASE_VELOCITY => &self.base_velocity,
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
        let layout = layout(2, true, 1, Some(("target", 3)));
        let names: Vec<_> = layout.iter().map(|s| s.name).collect();
        assert_eq!(
            names,
            [
                "joint_positions",
                "joint_velocities",
                "base_pose",
                "base_velocity",
                "end_effector_poses",
                "target"
            ]
        );
        let flat: Vec<f32> = (0..(2 + 2 + 7 + 6 + 7 + 3)).map(|i| i as f32).collect();
        let parts = ObservationParts::split(&layout, &flat);
        assert_eq!(parts.joint_velocities, [2.0, 3.0]);
        assert_eq!(parts.base_pose[0], 4.0);
        assert_eq!(parts.base_velocity[0], 11.0);
        assert_eq!(parts.end_effector_poses[0], 17.0);
        assert_eq!(parts.task, [24.0, 25.0, 26.0]);
        let o = Observation::from_flat(&flat, &layout);
        assert_eq!(
            o.end_effector_poses,
            [[17.0, 18.0, 19.0, 20.0, 21.0, 22.0, 23.0]]
        );
        assert_eq!(o.to_flat(), flat);
    }

    #[test]
    fn a_grounded_observation_without_a_task_has_no_base_or_task_part() {
        let layout = layout(1, false, 0, None);
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
