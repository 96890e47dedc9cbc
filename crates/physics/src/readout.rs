//! Measured state in user units: joint positions and velocities per DOF, body poses.
//!
//! Everything here is read from the simulated bodies and the multibody's generalized
//! coordinates; motor targets are never reported.

use rapier3d::math::{Pose, Real, Rotation, Vector};
use rapier3d::parry::mass_properties::MassProperties;

use crate::units::{to_m, Units};
use crate::world::{planar_slides, JointSlot, PlanarHelper, RobotWorld};
use gymfleet_assembly::JointType;

/// Floats in [`RobotWorld::base_state`]: a pose (7) and a velocity (6).
pub const BASE_STATE_LEN: usize = 13;

impl RobotWorld {
    /// Writes the measured position (deg or mm, or rad or m in [`Units::Si`]; a rotation
    /// vector for ball joints) and velocity (their rates) of every DOF, in document joint
    /// order. A joint's `reference` is added to its position.
    pub fn joint_state(&self, units: Units, positions: &mut [f32], velocities: &mut [f32]) {
        for slot in &self.joints {
            let first = slot.first_dof;
            let n = slot.observed_dofs;
            if n == 0 {
                continue;
            }
            let (pos, vel) = (
                &mut positions[first..first + n],
                &mut velocities[first..first + n],
            );
            if let Some(handle) = slot.closing {
                self.loop_joint_state(slot, handle, units, pos, vel);
                continue;
            }
            if slot.kind == JointType::Ball {
                let (rotation, w) = self.ball_state(slot);
                let rv = rotation.to_scaled_axis();
                let rv = [f64::from(rv.x), f64::from(rv.y), f64::from(rv.z)];
                for k in 0..3 {
                    pos[k] = units.angle(rv[k]) as f32;
                    vel[k] = units.angle(w[k]) as f32;
                }
                continue;
            }
            let Some(mb) = self.live.multibody_joints.get_multibody(slot.multibody) else {
                continue;
            };
            let Some(link) = mb.link(slot.link) else {
                continue;
            };
            let coords = link.joint().coords();
            let gen_vel = mb.joint_velocity(link);
            let q = |k: usize| f64::from(coords[slot.coord(k)]);
            let v = |k: usize| f64::from(gen_vel[slot.in_link(k)]);
            let dof = &self.dofs[first];
            let reference = units.from_document(dof.kind, dof.reference);
            match slot.kind {
                JointType::Revolute => {
                    pos[0] = (units.angle(q(0)) + reference) as f32;
                    vel[0] = units.angle(v(0)) as f32;
                }
                JointType::Prismatic => {
                    pos[0] = (units.length(q(0)) + reference) as f32;
                    vel[0] = units.length(v(0)) as f32;
                }
                JointType::Cylindrical => {
                    pos[0] = units.length(q(0)) as f32;
                    pos[1] = units.angle(q(1)) as f32;
                    vel[0] = units.length(v(0)) as f32;
                    vel[1] = units.angle(v(1)) as f32;
                }
                JointType::Ball | JointType::Fixed => {}
            }
        }
    }

    /// The generalized force the joint's limits applied to DOF `dof` over the last step
    /// (its mean: the limits' impulse over `dt`), N on a linear DOF and N·m on an angular
    /// one in every unit system; negative at an upper limit. MuJoCo's `qfrc_constraint` of a
    /// limited joint in a robot with no contacts on that DOF's bodies. Zero for ball joints
    /// (their cones are not hard stops) and after a reset.
    pub fn limit_force(&self, dof: usize) -> f64 {
        let Some(slot) = self
            .joints
            .iter()
            .find(|s| s.first_dof <= dof && dof < s.first_dof + s.observed_dofs)
        else {
            return 0.0;
        };
        if slot.closing.is_some() {
            return 0.0; // A loop's constraint force is not a limit's.
        }
        if slot.kind == JointType::Ball {
            return 0.0;
        }
        let Some(mb) = self.live.multibody_joints.get_multibody(slot.multibody) else {
            return 0.0;
        };
        let Some(link) = mb.link(slot.link) else {
            return 0.0;
        };
        let impulse = mb
            .hard_limit_impulses(link)
            .nth(slot.in_link(dof - slot.first_dof))
            .unwrap_or(0.0);
        f64::from(impulse) / self.dt()
    }

    /// An instance's own mass properties in its body's frame: the body's, when the body is
    /// its alone; else its collider's and its given ones (a body that folded instances
    /// share carries all of theirs).
    pub(crate) fn own_mass_properties(&self, instance: usize) -> MassProperties {
        if !self.shared[instance] {
            let rb = &self.live.bodies[self.bodies[instance]];
            return rb.mass_properties().local_mprops;
        }
        self.own_props[instance]
    }

    /// Recomputes [`RobotWorld::own_props`] from the colliders and the given masses.
    pub(crate) fn update_own_props(&mut self) {
        self.own_props = (0..self.colliders.len())
            .map(|i| {
                let mut props = MassProperties::default();
                if !self.shared[i] {
                    return props;
                }
                if let Some(co) = self.live.colliders.get(self.colliders[i]) {
                    let at = co.position_wrt_parent().copied().unwrap_or(Pose::IDENTITY);
                    props += co.mass_properties().transform_by(&at);
                }
                if let Some(given) = &self.given_now[i] {
                    props += given.transform_by(&self.placements[i]);
                }
                props
            })
            .collect();
    }

    /// An instance's own centre of mass, world m.
    pub(crate) fn own_center_of_mass(&self, instance: usize) -> Vector {
        if !self.shared[instance] {
            return self.live.bodies[self.bodies[instance]].center_of_mass();
        }
        self.body_frame(instance)
            .transform_point(self.own_mass_properties(instance).local_com)
    }

    /// An instance's frame in the world: its body's, placed by its placement.
    pub(crate) fn instance_frame(&self, instance: usize) -> Pose {
        self.body_frame(instance) * self.placements[instance]
    }

    /// The world frame an instance's placement is on: its body's pose; for a fused planar
    /// root's helper, the pose that puts the helper where the chain would hold it.
    pub(crate) fn body_frame(&self, instance: usize) -> Pose {
        match self.planar_helper(instance) {
            Some(helper) => self.helper_motion(helper).0 * self.placements[instance].inverse(),
            None => *self.live.bodies[self.bodies[instance]].position(),
        }
    }

    /// The fused planar root's helper that `instance` is, if it is one.
    pub(crate) fn planar_helper(&self, instance: usize) -> Option<&PlanarHelper> {
        self.planar_helpers.iter().find(|h| h.instance == instance)
    }

    /// A fused planar root's helper's frame in the world and its velocity (world m/s; it
    /// does not turn): its rest frame moved along the slides above it.
    pub(crate) fn helper_motion(&self, helper: &PlanarHelper) -> (Pose, Vector) {
        let slot = &self.joints[helper.slot];
        let (mut coords, mut rates) = ([0.0; 6], [0.0; 6]);
        let mb = self.live.multibody_joints.get_multibody(slot.multibody);
        if let Some((mb, link)) = mb.and_then(|mb| Some((mb, mb.link(slot.link)?))) {
            coords = link.joint().coords();
            // The fused joint's DOFs are linear X, linear Z, angular Y: laid out as
            // coordinates, the two slides' rates are where their positions are.
            let v = mb.joint_velocity(link);
            (rates[0], rates[2]) = (v[0], v[1]);
        }
        let shift = Pose::from_parts(planar_slides(&coords, helper.slides), Rotation::IDENTITY);
        let velocity = helper.frame.rotation * planar_slides(&rates, helper.slides);
        (helper.frame * shift * helper.rest, velocity)
    }

    /// The pose of an instance's centre of mass: `[x, y, z]` in world mm (m in
    /// [`Units::Si`]) and the world orientation as `[qw, qx, qy, qz]`.
    pub fn body_pose(&self, units: Units, instance: usize) -> [f32; 7] {
        let c = self.own_center_of_mass(instance);
        let q = self.instance_frame(instance).rotation;
        let l = units.length(1.0) as f32;
        [c.x * l, c.y * l, c.z * l, q.w, q.x, q.y, q.z]
    }

    /// Whether the first instance is a floating base, observed by
    /// [`RobotWorld::base_state`].
    pub fn has_floating_base(&self) -> bool {
        self.floating_base
    }

    /// A floating base's state, [`BASE_STATE_LEN`] floats: its pose as
    /// [`RobotWorld::body_pose`] gives it (centre of mass in world mm, orientation
    /// `[qw, qx, qy, qz]`), then the velocity of its centre of mass (world mm/s) and its
    /// angular velocity (world deg/s), read from the tree's generalized velocities (m,
    /// m/s and rad/s in [`Units::Si`]). Zeros without a floating base.
    pub fn base_state(&self, units: Units) -> [f32; BASE_STATE_LEN] {
        let mut out = [0.0; BASE_STATE_LEN];
        if !self.floating_base {
            return out;
        }
        out[..7].copy_from_slice(&self.body_pose(units, 0));
        let rb = &self.live.bodies[self.bodies[0]];
        let tree = self
            .free_roots
            .first()
            .filter(|r| r.instance == 0)
            .and_then(|r| self.live.multibody_joints.get_multibody(r.multibody));
        let (v, w) = match tree {
            // The generalized linear velocity is the body frame origin's.
            Some(mb) => {
                let q = mb.generalized_velocity();
                let w = Vector::new(q[3], q[4], q[5]);
                let arm = self.own_center_of_mass(0) - rb.position().translation;
                (Vector::new(q[0], q[1], q[2]) + w.cross(arm), w)
            }
            // A base nothing is jointed to is a plain rigid body.
            None => {
                let arm = self.own_center_of_mass(0) - rb.center_of_mass();
                (rb.linvel() + rb.angvel().cross(arm), rb.angvel())
            }
        };
        for k in 0..3 {
            out[7 + k] = units.length(f64::from(v[k])) as f32;
            out[10 + k] = units.angle(f64::from(w[k])) as f32;
        }
        out
    }

    /// An instance's centre of mass, world mm (m in [`Units::Si`]).
    pub fn center_of_mass(&self, units: Units, instance: usize) -> [f64; 3] {
        let c = self.own_center_of_mass(instance);
        [c.x, c.y, c.z].map(|v| units.length(f64::from(v)))
    }

    /// The whole robot's centre of mass: its moving instances' centres weighted by their
    /// masses (grounded instances and planes left out, as MuJoCo's world body is), world
    /// mm (m in [`Units::Si`]); the first instance's own if nothing moves.
    pub fn robot_center_of_mass(&self, units: Units) -> [f64; 3] {
        let (mut sum, mut mass) = ([0.0f64; 3], 0.0f64);
        // Each body once (folded instances share their owner's, which carries their mass).
        for (i, &h) in self.bodies.iter().enumerate() {
            if self.owners[i] != i {
                continue;
            }
            let rb = &self.live.bodies[h];
            if !rb.is_dynamic() {
                continue;
            }
            let m = f64::from(rb.mass());
            let c = rb.center_of_mass();
            for (s, v) in sum.iter_mut().zip([c.x, c.y, c.z]) {
                *s += m * f64::from(v);
            }
            mass += m;
        }
        if mass > 0.0 {
            sum.map(|s| units.length(s / mass))
        } else {
            self.center_of_mass(units, 0)
        }
    }

    /// A point given in an instance's frame (mm; the frame its document placement
    /// defines), in world mm (m in [`Units::Si`]).
    pub fn point_position(&self, units: Units, instance: usize, local_mm: [f64; 3]) -> [f64; 3] {
        let pose = self.instance_frame(instance);
        let local = local_mm.map(|v| to_m(v) as Real);
        let p = pose.transform_point(Vector::new(local[0], local[1], local[2]));
        [p.x, p.y, p.z].map(|v| units.length(f64::from(v)))
    }

    /// A site's pose: its point (given in the instance's frame, mm) in world mm (m in
    /// [`Units::Si`]), and its axes (Euler angles in the instance's frame, radians, X then
    /// Y then Z) as the world orientation `[qw, qx, qy, qz]`.
    pub fn site_pose(
        &self,
        units: Units,
        instance: usize,
        local_mm: [f64; 3],
        rotation: [f64; 3],
    ) -> [f32; 7] {
        let p = self.point_position(units, instance, local_mm);
        let [rx, ry, rz] = rotation.map(|a| a as Real);
        let local = Rotation::from_rotation_z(rz)
            * Rotation::from_rotation_y(ry)
            * Rotation::from_rotation_x(rx);
        let q = self.instance_frame(instance).rotation * local;
        [p[0] as f32, p[1] as f32, p[2] as f32, q.w, q.x, q.y, q.z]
    }

    /// A direction given in an instance's frame, in world coordinates (rotated, not
    /// rescaled).
    pub fn direction(&self, instance: usize, local: [f64; 3]) -> [f64; 3] {
        let q = self.instance_frame(instance).rotation;
        let v = q * Vector::new(local[0] as Real, local[1] as Real, local[2] as Real);
        [v.x, v.y, v.z].map(f64::from)
    }

    /// A ball joint's rotation (child joint frame relative to the parent's) and relative
    /// angular velocity (rad/s) in the parent-side joint frame, read from the multibody's
    /// generalized coordinates (the rigid bodies' own velocities lag by one substep).
    pub(crate) fn ball_state(&self, slot: &JointSlot) -> (Rotation, [f64; 3]) {
        let Some(link) = self
            .live
            .multibody_joints
            .get_multibody(slot.multibody)
            .and_then(|mb| Some((mb, mb.link(slot.link)?)))
        else {
            return (Rotation::IDENTITY, [0.0; 3]);
        };
        let (mb, link) = link;
        let w = mb.joint_velocity(link);
        (
            link.joint().joint_rot().normalize(),
            [f64::from(w[0]), f64::from(w[1]), f64::from(w[2])],
        )
    }
}
