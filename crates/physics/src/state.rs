//! The dynamic state of a world: what a step changes (joint coordinates, generalized
//! velocities, body motion) and the held command, read out and put back exactly. With the
//! document, the options and the episode's own state (in `gymfleet-env`) it is everything
//! that determines a world's future; `gymfleet-env` serialises it in its saved states.
//!
//! Values are Rapier's own `f32`s in SI (rad, m, rad/s, m/s), not the user's units, so that
//! a round trip is bit for bit. A state is checked against its world before it is restored
//! (`check`).

use rapier3d::prelude::*;
use serde::{Deserialize, Serialize};

use crate::command::ActionMode;
use crate::world::{kind_axes, RobotWorld};

mod check;

/// One joint's generalized coordinates (Rapier's six, locked axes zero) and, for a ball
/// joint, the rotation they stand for (integrated apart from the coordinates).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointCoords {
    /// Linear x, y, z (m) then angular x, y, z (rad) in the joint's frame.
    pub coords: [f32; 6],
    /// Ball joints: the rotation as a quaternion `[x, y, z, w]`; `None` for the others
    /// (their rotation follows from their one angle).
    pub rotation: Option<[f32; 4]>,
}

/// One instance body's motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BodyMotion {
    /// World position of the body's frame, m. (Bodies moved by joints are placed from the
    /// joint coordinates on restore; this is used for the others.)
    pub translation: [f32; 3],
    /// World orientation, quaternion `[x, y, z, w]`.
    pub rotation: [f32; 4],
    /// Linear velocity of the centre of mass, m/s.
    pub linvel: [f32; 3],
    /// Angular velocity, rad/s.
    pub angvel: [f32; 3],
}

/// A world's dynamic state (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DynamicState {
    /// The held command's mode.
    pub mode: ActionMode,
    /// The held command, one value per DOF in DOF order (0 for passive DOFs).
    pub command: Vec<f32>,
    /// Every joint with at least one DOF, in document order.
    pub joints: Vec<JointCoords>,
    /// Generalized velocity of every DOF, in DOF order (rad/s or m/s; a ball joint's three
    /// are its angular velocity).
    pub velocities: Vec<f32>,
    /// Every instance's body, in document order.
    pub bodies: Vec<BodyMotion>,
    /// The generalized velocity of every tree with a free root (a floating base), in
    /// document order of the roots: linear (m/s, of the root body's frame origin), then
    /// angular (rad/s), world frame. The root's pose is its body's.
    pub roots: Vec<[f32; 6]>,
    /// Every mocap body's target, in document order: where its body is to be (world m,
    /// then the quaternion `[x, y, z, w]`), or `None` while it stays where the document
    /// put it. Its pose now is in `bodies`.
    pub mocap_targets: Vec<Option<[f32; 7]>>,
    /// The held control of every actuator, in document order (as given, unclamped).
    pub controls: Vec<f32>,
    /// Every actuator's activation (MuJoCo's `act`; 0 for one without dynamics).
    pub activations: Vec<f64>,
    /// Every heightfield's heights, in document order, where they are no longer the
    /// document's (`RobotWorld::set_heightfield`); `None` where they are.
    pub terrains: Vec<Option<Vec<f32>>>,
}

fn quat(q: [f32; 4]) -> Rotation {
    Rotation::from_xyzw(q[0], q[1], q[2], q[3])
}

impl RobotWorld {
    /// Joints with at least one DOF and the multibody link each one moves.
    fn moving_joints(&self) -> impl Iterator<Item = &crate::world::JointSlot> {
        self.joints
            .iter()
            .filter(|slot| slot.kind.dof() > 0 && slot.closing.is_none())
    }

    /// The world's dynamic state now.
    pub fn dynamic_state(&self) -> DynamicState {
        let (joints, velocities) = self.joint_states();
        let bodies = self
            .bodies
            .iter()
            .map(|&h| {
                let rb = &self.live.bodies[h];
                let (p, v, w) = (rb.position(), rb.linvel(), rb.angvel());
                BodyMotion {
                    translation: [p.translation.x, p.translation.y, p.translation.z],
                    rotation: [p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w],
                    linvel: [v.x, v.y, v.z],
                    angvel: [w.x, w.y, w.z],
                }
            })
            .collect();
        let roots = self
            .free_roots
            .iter()
            .map(|root| {
                let mut v = [0.0; 6];
                if let Some(mb) = self.live.multibody_joints.get_multibody(root.multibody) {
                    let all = mb.generalized_velocity();
                    for (k, value) in v.iter_mut().enumerate() {
                        *value = all[k];
                    }
                }
                v
            })
            .collect();
        let mocap_targets = self
            .mocaps
            .iter()
            .map(|m| {
                m.target.map(|t| {
                    let (p, q) = (t.translation, t.rotation);
                    [p.x, p.y, p.z, q.x, q.y, q.z, q.w]
                })
            })
            .collect();
        DynamicState {
            mode: self.command.mode,
            command: self.command.values.clone(),
            joints,
            velocities,
            bodies,
            roots,
            mocap_targets,
            controls: self.command.controls.clone(),
            activations: self.activations.clone(),
            terrains: self.terrain_state(),
        }
    }

    /// Every moving joint's coordinates (and a ball joint's rotation), and every DOF's
    /// velocity.
    fn joint_states(&self) -> (Vec<JointCoords>, Vec<f32>) {
        let mut joints = Vec::new();
        let mut velocities = vec![0.0; self.dofs.len()];
        for slot in self.moving_joints() {
            let Some(mb) = self.live.multibody_joints.get_multibody(slot.multibody) else {
                continue;
            };
            let Some(link) = mb.link(slot.link) else {
                continue;
            };
            let joint = link.joint();
            let c = joint.coords();
            let rotation = (free_angular_dofs(joint) == 3).then(|| {
                let r = joint.joint_rot();
                [r.x, r.y, r.z, r.w]
            });
            let coords = match slot.lane {
                // One DOF of a fused planar root: saved where its joint alone keeps it, so
                // that a state reads the same whether the root is fused or not.
                Some(_) => {
                    let mut own = [0.0; 6];
                    own[kind_axes(slot.kind)[0] as usize] = c[slot.coord(0)];
                    own
                }
                None => [c[0], c[1], c[2], c[3], c[4], c[5]],
            };
            joints.push(JointCoords { coords, rotation });
            let first = link.assembly_id();
            let all = mb.generalized_velocity();
            for k in 0..slot.kind.dof() {
                velocities[slot.first_dof + k] = all[slot.link_dof(first, k)];
            }
        }
        (joints, velocities)
    }

    /// Puts `state` back: from the world as it is after [`RobotWorld::reset`] (and the
    /// episode's randomisation draws), sets every joint's coordinates and velocities, places
    /// the bodies (from the joints; bodies no joint moves from `state`), sets every body's
    /// velocities and the command. Two worlds of one document restored from one state are
    /// bitwise alike. Check the state with [`RobotWorld::check_dynamic_state`] first.
    ///
    /// # Panics
    ///
    /// If the state's counts do not fit this world.
    pub fn restore_dynamic_state(&mut self, state: &DynamicState) {
        assert_eq!(state.command.len(), self.dofs.len(), "one command per DOF");
        let terrains = self
            .saved_terrains(&state.terrains)
            .expect("a checked state's heightfields fit");
        self.restore_terrains(terrains);
        self.forget_motion();
        let mut touched = Vec::new();
        self.restore_joints(state, &mut touched);
        self.restore_free_roots(state, &mut touched);
        self.sync_bodies(&touched);
        // A loop's constraint starts afresh, as contacts do: without the last step's
        // impulses as a first guess, so that every world restored from `state` is alike.
        for (_, joint) in self.live.impulse_joints.iter_mut() {
            joint.impulses = Default::default();
        }
        self.restore_mocaps(state);
        self.restore_bodies(state);
        self.command.mode = state.mode;
        self.command.values.copy_from_slice(&state.command);
        self.command.controls.copy_from_slice(&state.controls);
        self.activations.copy_from_slice(&state.activations);
        self.configure_motors();
    }

    /// Every moving joint's coordinates and velocities; the multibodies changed go to
    /// `touched`.
    fn restore_joints(&mut self, state: &DynamicState, touched: &mut Vec<MultibodyIndex>) {
        let slots: Vec<_> = self.moving_joints().cloned().collect();
        assert_eq!(
            slots.len(),
            state.joints.len(),
            "one entry per moving joint"
        );
        for (slot, saved) in slots.iter().zip(&state.joints) {
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(first) = mb.link(slot.link).map(|l| l.assembly_id()) else {
                continue;
            };
            if let Some(link) = mb.link_mut(slot.link) {
                let c = match slot.lane {
                    // One DOF of a fused planar root: its own coordinate, the others kept.
                    Some(_) => {
                        let mut c = link.joint.coords();
                        c[slot.coord(0)] = saved.coords[kind_axes(slot.kind)[0] as usize];
                        c
                    }
                    None => saved.coords,
                };
                let rotation = saved.rotation.map_or(Rotation::IDENTITY, quat);
                link.joint.set_coords(c, rotation);
            }
            let mut velocities = mb.generalized_velocity_mut();
            for k in 0..slot.kind.dof() {
                velocities[slot.link_dof(first, k)] = state.velocities[slot.first_dof + k];
            }
            if !touched.contains(&slot.multibody) {
                touched.push(slot.multibody);
            }
        }
    }

    /// A free root is placed from its body's pose (read by the kinematics that
    /// `sync_bodies` runs) and moves with its six generalized velocities.
    fn restore_free_roots(&mut self, state: &DynamicState, touched: &mut Vec<MultibodyIndex>) {
        assert_eq!(
            state.roots.len(),
            self.free_roots.len(),
            "one entry per free root"
        );
        for (root, saved) in self.free_roots.clone().iter().zip(&state.roots) {
            let motion = &state.bodies[root.instance];
            let t = motion.translation;
            let pose = Pose::from_parts(Vector::new(t[0], t[1], t[2]), quat(motion.rotation));
            self.live.bodies[self.bodies[root.instance]].set_position(pose, false);
            if let Some(mb) = self.live.multibody_joints.get_multibody_mut(root.multibody) {
                let mut all = mb.generalized_velocity_mut();
                for (k, &value) in saved.iter().enumerate() {
                    all[k] = value;
                }
            }
            if !touched.contains(&root.multibody) {
                touched.push(root.multibody);
            }
        }
    }

    /// Each mocap body's pose and its target.
    fn restore_mocaps(&mut self, state: &DynamicState) {
        for (mocap, target) in self.mocaps.iter_mut().zip(&state.mocap_targets) {
            let h = self.bodies[mocap.body.instance];
            let saved = &state.bodies[mocap.body.instance];
            let t = saved.translation;
            let pose = Pose::from_parts(Vector::new(t[0], t[1], t[2]), quat(saved.rotation));
            self.live.bodies[h].set_position(pose, false);
            mocap.target = target.map(|t| {
                Pose::from_parts(
                    Vector::new(t[0], t[1], t[2]),
                    quat([t[3], t[4], t[5], t[6]]),
                )
            });
        }
    }

    /// Each dynamic body's velocities, and the pose of those outside a multibody.
    fn restore_bodies(&mut self, state: &DynamicState) {
        for (&h, saved) in self.bodies.iter().zip(&state.bodies) {
            let in_multibody = self.live.multibody_joints.rigid_body_link(h).is_some();
            let rb = &mut self.live.bodies[h];
            if !rb.is_dynamic() {
                continue;
            }
            if !in_multibody {
                let t = saved.translation;
                let pose = Pose::from_parts(Vector::new(t[0], t[1], t[2]), quat(saved.rotation));
                rb.set_position(pose, false);
            }
            let (v, w) = (saved.linvel, saved.angvel);
            rb.set_linvel(Vector::new(v[0], v[1], v[2]), false);
            rb.set_angvel(AngVector::new(w[0], w[1], w[2]), false);
        }
    }
}

/// How many of a joint's angular axes are free.
fn free_angular_dofs(joint: &MultibodyJoint) -> u32 {
    3 - (joint.data.locked_axes.bits() >> 3).count_ones()
}
