//! Kinematic loops: a loop-closing joint (`gymfleet_assembly::Joint::closes_loop`) is a
//! Rapier impulse joint between two bodies of the multibody trees, a constraint of its own
//! type (revolute, prismatic, cylindrical, ball, fixed) with its limits, solved with the
//! contacts at every substep. Its bodies do not collide. It is passive: a spring and
//! damping, if the document gives them, act through the constraint's force-based motor.
//!
//! It is observed like a tree joint, from the two bodies' relative pose: a revolute
//! joint's angle is the rotation of the child's joint frame about the parent's joint axis.

use gymfleet_assembly::{Assembly, Joint, JointType};
use rapier3d::prelude::*;

use crate::units::Units;
use crate::world::{JointSlot, RobotWorld, Sets};

/// Adds every loop-closing joint of `assembly` as an impulse joint, with the joint frames
/// `frames` (parent's, child's) computed at the document's pose, its locked axes and limits
/// as `describe` gives them (the tree's own joint description, `build.rs`); returns each
/// joint's handle (`None` for tree joints).
pub(crate) fn add_loop_joints(
    sets: &mut Sets,
    assembly: &Assembly,
    bodies: &[RigidBodyHandle],
    frames: &[(Pose, Pose)],
    describe: impl Fn(&Joint, Pose, Pose) -> GenericJoint,
) -> Vec<Option<ImpulseJointHandle>> {
    assembly
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            if !joint.closes_loop {
                return None;
            }
            let (f1, f2) = frames[j];
            let mut data = describe(joint, f1, f2);
            let axis = match joint.kind {
                JointType::Revolute => Some(JointAxis::AngX),
                JointType::Prismatic => Some(JointAxis::LinX),
                _ => None,
            };
            if let (Some(axis), true) = (axis, joint.stiffness > 0.0 || joint.damping > 0.0) {
                data.set_motor_model(axis, MotorModel::ForceBased);
                data.set_motor(
                    axis,
                    joint.spring_rest as Real,
                    0.0,
                    joint.stiffness as Real,
                    joint.damping as Real,
                );
            }
            let (parent, child) = (bodies[joint.parent], bodies[joint.child]);
            // Rapier solves a joint whose second body is fixed (the ground, a multibody's
            // root) wrongly: a weld from a link to the ground let the link spin. With the
            // fixed body first it holds, so such a joint is inserted the other way round
            // (`loop_frames` reads it back).
            if !sets.bodies[child].is_dynamic() {
                data.local_frame1 = f2;
                data.local_frame2 = f1;
                return Some(sets.impulse_joints.insert(child, parent, data, true));
            }
            Some(sets.impulse_joints.insert(parent, child, data, true))
        })
        .collect()
}

impl RobotWorld {
    /// The joint frames of a loop-closing joint in the world: (the parent's, the child's).
    fn loop_frames(&self, slot: &JointSlot, handle: ImpulseJointHandle) -> Option<(Pose, Pose)> {
        let joint = self.live.impulse_joints.get(handle)?;
        let p = self.live.bodies.get(slot.parent)?;
        let c = self.live.bodies.get(slot.child)?;
        // Inserted the other way round when the child is fixed (`add_loop_joints`).
        let (f1, f2) = if joint.body1() == slot.parent {
            (joint.data.local_frame1, joint.data.local_frame2)
        } else {
            (joint.data.local_frame2, joint.data.local_frame1)
        };
        Some((*p.position() * f1, *c.position() * f2))
    }

    /// Writes a loop-closing joint's observed position and velocity (as
    /// [`RobotWorld::joint_state`] does for tree joints), measured from its two bodies.
    pub(crate) fn loop_joint_state(
        &self,
        slot: &JointSlot,
        handle: ImpulseJointHandle,
        units: Units,
        pos: &mut [f32],
        vel: &mut [f32],
    ) {
        let Some((f1, f2)) = self.loop_frames(slot, handle) else {
            return;
        };
        let (p, c) = (
            &self.live.bodies[slot.parent],
            &self.live.bodies[slot.child],
        );
        // The child's frame in the parent's: X is the joint axis.
        let relative = f1.inverse() * f2;
        let axis = f1.rotation * Vector::X;
        let omega = c.angvel() - p.angvel();
        // Each body's velocity at the child frame's origin.
        let at = f2.translation;
        let v = (c.linvel() + c.angvel().cross(at - c.center_of_mass()))
            - (p.linvel() + p.angvel().cross(at - p.center_of_mass()));
        let angle = || {
            // The twist of the relative rotation about X (its swing is locked).
            let q = relative.rotation;
            let a = 2.0 * q.x.atan2(q.w);
            // Into (−π, π].
            let a = if a > std::f32::consts::PI {
                a - 2.0 * std::f32::consts::PI
            } else if a <= -std::f32::consts::PI {
                a + 2.0 * std::f32::consts::PI
            } else {
                a
            };
            f64::from(a)
        };
        let dof = |k: usize| &self.dofs[slot.first_dof + k];
        let reference = |k: usize| units.from_document(dof(k).kind, dof(k).reference);
        match slot.kind {
            JointType::Revolute => {
                pos[0] = (units.angle(angle()) + reference(0)) as f32;
                vel[0] = units.angle(f64::from(omega.dot(axis))) as f32;
            }
            JointType::Prismatic => {
                pos[0] = (units.length(f64::from(relative.translation.x)) + reference(0)) as f32;
                vel[0] = units.length(f64::from(v.dot(axis))) as f32;
            }
            JointType::Cylindrical => {
                pos[0] = units.length(f64::from(relative.translation.x)) as f32;
                pos[1] = units.angle(angle()) as f32;
                vel[0] = units.length(f64::from(v.dot(axis))) as f32;
                vel[1] = units.angle(f64::from(omega.dot(axis))) as f32;
            }
            JointType::Ball => {
                let rv = relative.rotation.normalize().to_scaled_axis();
                // The relative angular velocity in the parent's joint frame.
                let w = f1.rotation.inverse() * omega;
                for k in 0..3 {
                    pos[k] = units.angle(f64::from(rv[k])) as f32;
                    vel[k] = units.angle(f64::from(w[k])) as f32;
                }
            }
            JointType::Fixed => {}
        }
    }

    /// How far each loop-closing joint is from closed: the distance between its two joint
    /// frames' origins (m) and the angle between their locked rotations (rad, the whole
    /// relative rotation for a fixed joint, its swing off the axis for revolute and
    /// cylindrical joints, 0 for a ball joint), in document order of the loop joints.
    pub fn loop_gaps(&self) -> Vec<(f64, f64)> {
        self.joints
            .iter()
            .filter_map(|slot| {
                let (f1, f2) = self.loop_frames(slot, slot.closing?)?;
                let relative = f1.inverse() * f2;
                let mut distance = relative.translation;
                if matches!(slot.kind, JointType::Prismatic | JointType::Cylindrical) {
                    distance.x = 0.0; // The free axis.
                }
                let angle = match slot.kind {
                    JointType::Ball => 0.0,
                    JointType::Fixed | JointType::Prismatic => relative.rotation.to_axis_angle().1,
                    JointType::Revolute | JointType::Cylindrical => {
                        let x = relative.rotation * Vector::X;
                        x.angle_between(Vector::X)
                    }
                };
                Some((f64::from(distance.length()), f64::from(angle)))
            })
            .collect()
    }
}
