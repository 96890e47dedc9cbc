//! Free bodies and mocap bodies, as MuJoCo has them.
//!
//! A free body (`gymfleet_assembly::Assembly::free_bodies`: an object on a table, a second
//! robot) moves freely with nothing above it; it is observed as MuJoCo observes a free
//! joint: the pose of its reference frame (the instance's `body_frame`, else its centre of
//! mass with its axes), then the velocity of that frame's origin in the world and its
//! angular velocity in its own axes (MuJoCo's `qvel` of a free joint).
//!
//! A mocap body is a kinematic Rapier body that a pose target moves: the target, set by a
//! client, is where its reference frame is to be at the end of the next step; Rapier moves
//! the body there over the step at constant velocity, so that what it touches, or what a
//! constraint joins to it, is pushed and pulled along. Targets persist until changed and
//! go back to the document's poses at a reset.

use rapier3d::math::{Pose, Real, Rotation, Vector};

use crate::units::Units;
use crate::world::{BodyRef, RobotWorld};

/// Floats of one free body's pose: `[x, y, z, qw, qx, qy, qz]`.
pub const FREE_POSE_LEN: usize = 7;
/// Floats of one free body's velocity: `[vx, vy, vz, wx, wy, wz]`.
pub const FREE_VELOCITY_LEN: usize = 6;

/// A pose from a document-frame `[x, y, z]` (m) and Euler angles (rad, X then Y then Z).
pub(crate) fn local_pose(position: [f64; 3], rotation: [f64; 3]) -> Pose {
    let [x, y, z] = position.map(|c| c as Real);
    let [rx, ry, rz] = rotation.map(|c| c as Real);
    Pose::from_parts(
        Vector::new(x, y, z),
        Rotation::from_rotation_z(rz)
            * Rotation::from_rotation_y(ry)
            * Rotation::from_rotation_x(rx),
    )
}

/// A keyframe's pose as a Rapier pose.
fn key_pose(key: &gymfleet_assembly::BaseKey) -> Pose {
    let [x, y, z] = key.position.map(|c| c as Real);
    let q = key.orientation.map(|c| c as Real);
    Pose::from_parts(
        Vector::new(x, y, z),
        Rotation::from_xyzw(q[1], q[2], q[3], q[0]),
    )
}

impl RobotWorld {
    /// The world pose of a free or mocap body's reference frame.
    fn reference_frame(&self, body: &BodyRef) -> Pose {
        let instance = self.instance_frame(body.instance);
        match body.frame {
            Some(frame) => instance * frame,
            None => Pose::from_parts(self.own_center_of_mass(body.instance), instance.rotation),
        }
    }

    /// The free bodies' instances, in document order.
    pub fn free_body_instances(&self) -> impl Iterator<Item = usize> + '_ {
        self.free_bodies.iter().map(|b| b.instance)
    }

    /// Writes each free body's pose ([`FREE_POSE_LEN`] floats: its reference frame's origin
    /// in world mm, m in [`Units::Si`], and its orientation `[qw, qx, qy, qz]`) into `poses`,
    /// and its velocity ([`FREE_VELOCITY_LEN`] floats: the origin's in world mm/s, then the
    /// angular velocity in the frame's own axes, deg/s; m/s and rad/s in [`Units::Si`]) into
    /// `velocities`, in document order: MuJoCo's `qpos` and `qvel` of a free joint.
    pub fn free_body_state(&self, units: Units, poses: &mut [f32], velocities: &mut [f32]) {
        let l = units.length(1.0);
        for (k, body) in self.free_bodies.iter().enumerate() {
            let frame = self.reference_frame(body);
            let rb = &self.live.bodies[self.bodies[body.instance]];
            let arm = frame.translation - rb.center_of_mass();
            let v = rb.linvel() + rb.angvel().cross(arm);
            let w = frame.rotation.inverse() * rb.angvel();
            let (p, q) = (frame.translation, frame.rotation);
            let pose = &mut poses[k * FREE_POSE_LEN..(k + 1) * FREE_POSE_LEN];
            for (slot, value) in pose.iter_mut().zip([
                f64::from(p.x) * l,
                f64::from(p.y) * l,
                f64::from(p.z) * l,
                f64::from(q.w),
                f64::from(q.x),
                f64::from(q.y),
                f64::from(q.z),
            ]) {
                *slot = value as f32;
            }
            let velocity = &mut velocities[k * FREE_VELOCITY_LEN..(k + 1) * FREE_VELOCITY_LEN];
            for i in 0..3 {
                velocity[i] = units.length(f64::from(v[i])) as f32;
                velocity[3 + i] = units.angle(f64::from(w[i])) as f32;
            }
        }
    }

    /// How many mocap bodies the world has (document order).
    pub fn num_mocap_bodies(&self) -> usize {
        self.mocaps.len()
    }

    /// Mocap body `k`'s reference frame now: `[x, y, z, qw, qx, qy, qz]`, world mm (m in
    /// [`Units::Si`]).
    pub fn mocap_pose(&self, units: Units, k: usize) -> [f32; FREE_POSE_LEN] {
        let frame = self.reference_frame(&self.mocaps[k].body);
        let (p, q) = (frame.translation, frame.rotation);
        let l = units.length(1.0) as f32;
        [p.x * l, p.y * l, p.z * l, q.w, q.x, q.y, q.z]
    }

    /// Sets where mocap body `k`'s reference frame is to be at the end of the next step
    /// (and stay): `[x, y, z, qw, qx, qy, qz]`, world mm (m in [`Units::Si`]); the
    /// quaternion is normalised. The caller checks that it is finite and not zero.
    pub fn set_mocap_target(&mut self, units: Units, k: usize, pose: [f32; FREE_POSE_LEN]) {
        let to_m = 1.0 / units.length(1.0) as Real;
        let rotation = Rotation::from_xyzw(pose[4], pose[5], pose[6], pose[3]).normalize();
        let wanted = Pose::from_parts(
            Vector::new(pose[0] * to_m, pose[1] * to_m, pose[2] * to_m),
            rotation,
        );
        let slot = &self.mocaps[k];
        // The body's pose that puts the reference frame there.
        let now = self.reference_frame(&slot.body);
        let body = *self.live.bodies[self.bodies[slot.body.instance]].position();
        let frame_in_body = body.inverse() * now;
        self.mocaps[k].target = Some(wanted * frame_in_body.inverse());
    }

    /// Puts free body `instance`'s reference frame at a keyframe's pose (SI, world), moving
    /// with its velocity: the origin's (world) and the angular velocity in the frame's own
    /// axes, as [`RobotWorld::free_body_state`] reads them. Nothing happens for an instance
    /// that is not a free body.
    pub fn place_free_body(&mut self, instance: usize, key: &gymfleet_assembly::BaseKey) {
        let Some(body) = self
            .free_bodies
            .iter()
            .find(|b| b.instance == instance)
            .copied()
        else {
            return;
        };
        let wanted = key_pose(key);
        let pose = self.body_pose_for(&body, wanted);
        let handle = self.bodies[instance];
        let rb = &mut self.live.bodies[handle];
        rb.set_position(pose, true);
        let real = |v: [f64; 3]| Vector::new(v[0] as Real, v[1] as Real, v[2] as Real);
        let w = wanted.rotation * real(key.angular_velocity);
        let com = pose.transform_point(rb.mass_properties().local_mprops.local_com);
        rb.set_linvel(
            real(key.linear_velocity) + w.cross(com - wanted.translation),
            true,
        );
        rb.set_angvel(w, true);
    }

    /// Puts mocap body `k`'s reference frame at a keyframe's pose (SI, world) and holds it
    /// there (its target) until a new target moves it.
    pub fn place_mocap(&mut self, k: usize, key: &gymfleet_assembly::BaseKey) {
        let Some(slot) = self.mocaps.get(k).copied() else {
            return;
        };
        let pose = self.body_pose_for(&slot.body, key_pose(key));
        let handle = self.bodies[slot.body.instance];
        self.live.bodies[handle].set_position(pose, true);
        self.mocaps[k].target = Some(pose);
    }

    /// The pose of `body`'s Rapier body that puts its reference frame at `wanted`.
    fn body_pose_for(&self, body: &BodyRef, wanted: Pose) -> Pose {
        let now = self.reference_frame(body);
        let current = *self.live.bodies[self.bodies[body.instance]].position();
        wanted * (current.inverse() * now).inverse()
    }

    /// Tells Rapier where each mocap body with a target is to be at the end of the next
    /// pipeline step: the target itself when it ends the env step (`pipeline_steps_left`
    /// is 1), else the share of the way there that keeps its velocity constant over the
    /// env step's remaining pipeline steps.
    pub(crate) fn move_mocap_bodies(&mut self, pipeline_steps_left: u32) {
        let share = 1.0 / pipeline_steps_left.max(1) as Real;
        for slot in &self.mocaps {
            if let Some(target) = slot.target {
                let handle = self.bodies[slot.body.instance];
                if let Some(rb) = self.live.bodies.get_mut(handle) {
                    let now = *rb.position();
                    let next = if pipeline_steps_left <= 1 {
                        target
                    } else {
                        Pose::from_parts(
                            now.translation.lerp(target.translation, share),
                            now.rotation.slerp(target.rotation, share),
                        )
                    };
                    rb.set_next_kinematic_position(next);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cube turned 90° about x, spinning about the world's y: its observed angular
    /// velocity is in its own axes, where the world's y is its −z (MuJoCo's qvel of a free
    /// joint); the origin's velocity, in the world, gains ω × r from the spin.
    #[test]
    fn a_free_bodys_angular_velocity_is_given_in_its_own_axes() {
        let doc = r#"{
            "parts": [{"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}}],
            "assembly": {"instances": [
                {"part": "Cube", "name": "ground"},
                {"part": "Cube", "name": "a", "position": {"x": 0, "y": 0, "z": 500},
                 "rotation": {"x": 90, "y": 0, "z": 0},
                 "body_frame": {"position": {"x": 0, "y": 0, "z": 0}}}
            ], "joints": []}
        }"#;
        let assembly = gymfleet_assembly::parse(doc).unwrap();
        let mut world = RobotWorld::new(&assembly, &crate::WorldOptions::default()).unwrap();
        let handle = world.bodies[1];
        world.live.bodies[handle].set_angvel(Vector::new(0.0, 1.0, 0.0), true);
        let (mut pose, mut velocity) = ([0.0; 7], [0.0; 6]);
        world.free_body_state(Units::Si, &mut pose, &mut velocity);
        let w = &velocity[3..];
        assert!(
            w[0].abs() < 1e-6 && w[1].abs() < 1e-6 && (w[2] + 1.0).abs() < 1e-6,
            "{w:?}"
        );
        // The frame's origin is the cube's corner: 10 mm from its centre along each of its
        // axes, so the spin moves it at ω × r.
        let rb = &world.live.bodies[handle];
        let r = Vector::new(pose[0], pose[1], pose[2]) - rb.center_of_mass();
        let expected = Vector::new(0.0, 1.0, 0.0).cross(r);
        for k in 0..3 {
            assert!(
                (velocity[k] - expected[k]).abs() < 1e-6,
                "{velocity:?} vs {expected:?}"
            );
        }
    }
}
