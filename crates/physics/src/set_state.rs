//! Setting the robot's state to given values, as MuJoCo's `set_state(qpos, qvel)` does:
//! every DOF's position and velocity, and a floating base's pose and velocity, in the
//! layouts [`RobotWorld::joint_state`] and [`RobotWorld::base_state`] read them out in.
//! Nothing else moves: free and mocap bodies, actuator activations and the held command
//! stay as they are.

use rapier3d::prelude::*;

use gymfleet_assembly::JointType;

use crate::units::{from_si, to_si, Units};
use crate::world::RobotWorld;
use crate::BASE_STATE_LEN;

/// What [`RobotWorld::set_joint_state`] did not set as given.
#[derive(Debug, Clone, PartialEq)]
pub enum StateAdjustment {
    /// A position past the DOF's hard limit was put at the limit (MuJoCo's limits are soft:
    /// its recorded states sit slightly past them).
    Clamped {
        /// The DOF, in [`RobotWorld::dofs`] order.
        dof: usize,
        /// Its joint's name.
        joint: String,
        /// The value given, in the units given.
        given: f64,
        /// The value set (the limit), in the units given.
        set: f64,
    },
    /// A joint whose position cannot be set from values kept its own: one on a kinematic
    /// loop (moved alone, it would open the loop), or a ball joint.
    Kept {
        /// The joint's name.
        joint: String,
        /// Why it kept its position.
        reason: &'static str,
    },
}

impl std::fmt::Display for StateAdjustment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StateAdjustment::Clamped {
                dof,
                joint,
                given,
                set,
            } => write!(
                f,
                "joint_positions[{dof}] ({joint}): {given} is past the joint's limit; set to {set}"
            ),
            StateAdjustment::Kept { joint, reason } => {
                write!(f, "joint {joint} keeps its position: {reason}")
            }
        }
    }
}

/// How far (in the units given) a kept joint's position may be from the one asked for
/// before [`StateAdjustment::Kept`] says so: float32 readout noise.
const KEPT_TOLERANCE: f64 = 1e-5;

impl RobotWorld {
    /// Sets every DOF's position and velocity (in [`RobotWorld::dofs`] order, observed
    /// positions as [`RobotWorld::joint_state`] reads them, reference included, in
    /// `units`) and, with `base`, the floating base's state ([`BASE_STATE_LEN`] floats as
    /// [`RobotWorld::base_state`] reads it). Positions past a hard limit are set at the
    /// limit (a compliant one, MuJoCo's, takes them as given); joints on a kinematic loop and ball joints keep their positions (their
    /// velocities are set where [`RobotWorld::set_dof_velocities`] sets them). Returns
    /// what was not set as given.
    ///
    /// # Panics
    ///
    /// If `positions` or `velocities` has not one value per DOF.
    pub fn set_joint_state(
        &mut self,
        units: Units,
        positions: &[f64],
        velocities: &[f64],
        base: Option<&[f64; BASE_STATE_LEN]>,
    ) -> Vec<StateAdjustment> {
        self.forget_motion();
        assert_eq!(positions.len(), self.dofs.len(), "one position per DOF");
        let mut notes = Vec::new();
        if let Some(base) = base {
            self.set_base_state(units, base);
        }
        let mut now = vec![0.0f32; self.dofs.len()];
        let mut scratch = vec![0.0f32; self.dofs.len()];
        self.joint_state(units, &mut now, &mut scratch);
        let mut touched = Vec::new();
        for slot in &self.joints {
            let n = slot.observed_dofs;
            if n == 0 {
                continue;
            }
            let first = slot.first_dof;
            let moves = (first..first + n)
                .any(|k| (positions[k] - f64::from(now[k])).abs() > KEPT_TOLERANCE);
            let kept = if slot.on_loop || slot.closing.is_some() {
                Some("it is on a kinematic loop, which stays closed")
            } else if slot.kind == JointType::Ball {
                Some("a ball joint's rotation is not set from values yet")
            } else {
                None
            };
            if let Some(reason) = kept {
                if moves {
                    let joint = self.dofs[first].joint_name.clone();
                    notes.push(StateAdjustment::Kept { joint, reason });
                }
                continue;
            }
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(link) = mb.link(slot.link) else {
                continue;
            };
            let link_first = link.assembly_id();
            let coords = link.joint().coords();
            // A compliant limit (vendored patch 44) may be pushed past: positions stand.
            let hard = link.joint().limit_compliance().is_none();
            let mut disp = vec![0.0; mb.ndofs()];
            for k in 0..n {
                let dof = &self.dofs[first + k];
                // The observed position less the reference: the joint's coordinate, deg or mm.
                let reference = match slot.kind {
                    JointType::Revolute | JointType::Prismatic => dof.reference,
                    _ => 0.0,
                };
                let given = positions[first + k];
                let wanted = units.to_document(dof.kind, given) - reference;
                let target = match dof.limits {
                    Some([min, max]) if hard && (wanted < min || wanted > max) => {
                        let set = wanted.clamp(min, max);
                        notes.push(StateAdjustment::Clamped {
                            dof: first + k,
                            joint: dof.joint_name.clone(),
                            given,
                            set: units.from_document(dof.kind, set + reference),
                        });
                        set
                    }
                    _ => wanted,
                };
                let current = from_si(dof.kind, f64::from(coords[slot.coord(k)]));
                disp[slot.link_dof(link_first, k)] = to_si(dof.kind, target - current) as Real;
            }
            mb.apply_displacements(&disp);
            if !touched.contains(&slot.multibody) {
                touched.push(slot.multibody);
            }
        }
        self.sync_bodies(&touched);
        self.set_dof_velocities(units, velocities);
        self.sync_velocities();
        notes
    }

    /// After generalized velocities were set outside a step: every multibody's links'
    /// velocities into their rigid bodies (vendored Rapier patch 41), as a step leaves them.
    fn sync_velocities(&mut self) {
        let mut trees: Vec<MultibodyIndex> = self.joints.iter().map(|s| s.multibody).collect();
        trees.extend(self.free_roots.iter().map(|r| r.multibody));
        trees.sort_unstable_by_key(|i| i.0.into_raw_parts());
        trees.dedup();
        for index in trees {
            if let Some(mb) = self.live.multibody_joints.get_multibody_mut(index) {
                mb.update_velocities(&mut self.live.bodies);
            }
        }
    }

    /// Puts a floating base's state ([`RobotWorld::base_state`]'s layout: its centre of
    /// mass, its orientation `[qw, qx, qy, qz]` (normalised here), its centre of mass's
    /// velocity and its angular velocity, world) where given; the tree's joints keep their
    /// coordinates and follow. Nothing happens without a floating base.
    fn set_base_state(&mut self, units: Units, state: &[f64; BASE_STATE_LEN]) {
        if !self.floating_base {
            return;
        }
        let handle = self.bodies[0];
        let length = |v: f64| units.to_si(gymfleet_assembly::DofKind::Linear, v) as Real;
        let angle = |v: f64| units.to_si(gymfleet_assembly::DofKind::Angular, v) as Real;
        let norm = state[3..7].iter().map(|v| v * v).sum::<f64>().sqrt();
        let q: [f64; 4] = std::array::from_fn(|k| state[3 + k] / norm);
        let wanted = Rotation::from_xyzw(q[1] as Real, q[2] as Real, q[3] as Real, q[0] as Real);
        // The instance's frame is its body's times its placement; its centre of mass is a
        // fixed point of its body.
        let body = *self.live.bodies[handle].position();
        let placement = self.placements[0];
        let rotation = wanted * placement.rotation.inverse();
        let arm_local = body.rotation.inverse() * (self.own_center_of_mass(0) - body.translation);
        let com = Vector::new(length(state[0]), length(state[1]), length(state[2]));
        let arm = rotation * arm_local;
        let linear = Vector::new(length(state[7]), length(state[8]), length(state[9]));
        let angular = Vector::new(angle(state[10]), angle(state[11]), angle(state[12]));
        self.live.bodies[handle].set_position(Pose::from_parts(com - arm, rotation), true);
        // The generalized linear velocity is the body frame origin's.
        self.set_base_velocity(linear - angular.cross(arm), angular);
    }

    /// Puts a floating base's instance frame at a keyframe's pose, moving with its velocity
    /// (its origin's and its angular velocity, world); the tree's joints keep their
    /// coordinates and follow. Nothing happens without a floating base.
    pub fn place_base(&mut self, key: &gymfleet_assembly::BaseKey) {
        if !self.floating_base {
            return;
        }
        let real = |v: [f64; 3]| Vector::new(v[0] as Real, v[1] as Real, v[2] as Real);
        let q = key.orientation;
        let rotation = Rotation::from_xyzw(q[1] as Real, q[2] as Real, q[3] as Real, q[0] as Real);
        let instance = Pose::from_parts(real(key.position), rotation);
        // The instance's frame is its body's times its placement.
        let body = instance * self.placements[0].inverse();
        self.live.bodies[self.bodies[0]].set_position(body, true);
        let angular = real(key.angular_velocity);
        let arm = body.translation - instance.translation;
        self.set_base_velocity(real(key.linear_velocity) + angular.cross(arm), angular);
    }

    /// An instance's own mass, kg (as randomised now; a folded instance's, not its
    /// body's).
    pub fn instance_mass(&self, instance: usize) -> f64 {
        f64::from(self.own_mass_properties(instance).mass())
    }
}
