//! The dynamic state of a world: what a step changes (joint coordinates, generalized
//! velocities, body motion) and the held command, read out and put back exactly. With the
//! document, the options and the episode's own state (in `gymfleet-env`) it is everything
//! that determines a world's future; `gymfleet-env` serialises it in its saved states.
//!
//! Values are Rapier's own `f32`s in SI (rad, m, rad/s, m/s), not the user's units, so that
//! a round trip is bit for bit.

use gymfleet_assembly::{DofKind, JointType};
use rapier3d::prelude::*;
use serde::{Deserialize, Serialize};

use crate::command::ActionMode;
use crate::error::{PhysicsError, Result};
use crate::units::to_si;
use crate::world::{kind_axes, JointDof, RobotWorld};

/// Largest magnitude accepted for a coordinate (rad or m) or a velocity (rad/s or m/s) in
/// a state: far beyond anything a healthy step produces (the env reports divergence long
/// before), and far from where `f32` arithmetic on it stops meaning anything.
const MAX_MAGNITUDE: f32 = 1.0e9;
/// How far a limited DOF may sit past its limit in a state, in deg or mm: hard stops put a
/// DOF back on its limit (at most 0.001° past it, `f32` rounding included).
const LIMIT_TOLERANCE: f64 = 0.01;
/// How far a quaternion's norm may be from 1.
const UNIT_TOLERANCE: f32 = 1.0e-4;

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

fn bad(path: String, reason: String) -> PhysicsError {
    PhysicsError::BadState { path, reason }
}

fn check_values(path: &str, values: &[f32], max: f32) -> Result<()> {
    match values
        .iter()
        .position(|v| !(v.is_finite() && v.abs() <= max))
    {
        Some(k) => Err(bad(
            format!("{path}[{k}]"),
            format!("expected a finite value within ±{max:e}, got {}", values[k]),
        )),
        None => Ok(()),
    }
}

fn check_unit(path: &str, q: &[f32; 4]) -> Result<()> {
    check_values(path, q, 1.0 + UNIT_TOLERANCE)?;
    let norm = q.iter().map(|c| c * c).sum::<f32>().sqrt();
    if (norm - 1.0).abs() > UNIT_TOLERANCE {
        return Err(bad(
            path.to_string(),
            format!("expected a unit quaternion, got one of norm {norm}"),
        ));
    }
    Ok(())
}

fn check_len(path: &str, got: usize, expected: usize, what: &str) -> Result<()> {
    if got == expected {
        Ok(())
    } else {
        Err(bad(
            path.to_string(),
            format!("expected {expected} {what}, got {got}"),
        ))
    }
}

/// A saved coordinate inside its DOF's hard limits (in the document's units, with the
/// tolerance a settled solver leaves).
fn check_within(
    dof: &JointDof,
    [min, max]: [f64; 2],
    value: f32,
    path: &str,
    axis: usize,
) -> Result<()> {
    let lo = to_si(dof.kind, min - LIMIT_TOLERANCE) as f32;
    let hi = to_si(dof.kind, max + LIMIT_TOLERANCE) as f32;
    if (lo..=hi).contains(&value) {
        return Ok(());
    }
    let (si, user) = match dof.kind {
        DofKind::Angular => ("rad", "deg"),
        DofKind::Linear => ("m", "mm"),
    };
    Err(bad(
        format!("{path}.coords[{axis}]"),
        format!(
            "{value} {si} is outside joint {:?}'s limits [{min}, {max}] {user}",
            dof.joint_name
        ),
    ))
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

    /// Checks that `state` fits this world (counts) and holds only sane values: finite,
    /// within bounds, limited DOFs on their side of the limits, unit quaternions, no command
    /// on a passive DOF. An error names the field (`world.joints[2].coords[3]`).
    pub fn check_dynamic_state(&self, state: &DynamicState) -> Result<()> {
        let dofs = self.dofs.len();
        check_len(
            "world.command",
            state.command.len(),
            dofs,
            "values (one per DOF)",
        )?;
        check_values("world.command", &state.command, f32::MAX)?;
        if let Some(k) = (0..dofs).find(|&k| !self.dofs[k].actuated && state.command[k] != 0.0) {
            return Err(bad(
                format!("world.command[{k}]"),
                format!(
                    "DOF {k} (joint {:?}) is passive and holds no command, got {}",
                    self.dofs[k].joint_name, state.command[k]
                ),
            ));
        }
        check_len(
            "world.velocities",
            state.velocities.len(),
            dofs,
            "values (one per DOF)",
        )?;
        check_values("world.velocities", &state.velocities, MAX_MAGNITUDE)?;
        let moving = self.moving_joints().count();
        check_len(
            "world.joints",
            state.joints.len(),
            moving,
            "joints (those with a DOF)",
        )?;
        for (j, (slot, saved)) in self.moving_joints().zip(&state.joints).enumerate() {
            let path = format!("world.joints[{j}]");
            check_values(&format!("{path}.coords"), &saved.coords, MAX_MAGNITUDE)?;
            let link = self
                .live
                .multibody_joints
                .get_multibody(slot.multibody)
                .and_then(|mb| mb.link(slot.link));
            let Some(link) = link else { continue };
            let joint = link.joint();
            // The axes its kind leaves free, as a state saves them (see `dynamic_state`).
            let free = kind_axes(slot.kind)
                .iter()
                .fold(0u8, |mask, &a| mask | 1 << a as usize);
            let locked = !free & 0b11_1111;
            if let Some(axis) = (0..6).find(|&a| locked & (1 << a) != 0 && saved.coords[a] != 0.0) {
                return Err(bad(
                    format!("{path}.coords[{axis}]"),
                    format!(
                        "axis {axis} of this joint is locked: expected 0, got {}",
                        saved.coords[axis]
                    ),
                ));
            }
            // The DOFs' coordinates, in DOF order: free linear axes, then free angular ones.
            let free: Vec<usize> = (0..6).filter(|&a| locked & (1 << a) == 0).collect();
            for (k, &axis) in free.iter().enumerate() {
                let dof = &self.dofs[slot.first_dof + k];
                // A ball joint's three angles are not its rotation's: its limits (if any) are
                // not checked on them.
                // A compliant limit (MuJoCo's, vendored patch 44) is a spring a joint may be
                // pushed past: any position is a state.
                let (Some([min, max]), false, None) = (
                    dof.limits,
                    slot.kind == JointType::Ball,
                    joint.limit_compliance(),
                ) else {
                    continue;
                };
                check_within(dof, [min, max], saved.coords[axis], &path, axis)?;
            }
            match (free_angular_dofs(joint) == 3, &saved.rotation) {
                (true, Some(q)) => check_unit(&format!("{path}.rotation"), q)?,
                (true, None) => {
                    return Err(bad(
                        format!("{path}.rotation"),
                        "a ball joint's state needs its rotation".to_string(),
                    ))
                }
                (false, Some(_)) => {
                    return Err(bad(
                        format!("{path}.rotation"),
                        "only a ball joint's state has a rotation".to_string(),
                    ))
                }
                (false, None) => {}
            }
        }
        check_len(
            "world.bodies",
            state.bodies.len(),
            self.bodies.len(),
            "bodies (one per instance)",
        )?;
        for (i, body) in state.bodies.iter().enumerate() {
            let path = format!("world.bodies[{i}]");
            check_values(
                &format!("{path}.translation"),
                &body.translation,
                MAX_MAGNITUDE,
            )?;
            check_unit(&format!("{path}.rotation"), &body.rotation)?;
            check_values(&format!("{path}.linvel"), &body.linvel, MAX_MAGNITUDE)?;
            check_values(&format!("{path}.angvel"), &body.angvel, MAX_MAGNITUDE)?;
        }
        check_len(
            "world.roots",
            state.roots.len(),
            self.free_roots.len(),
            "free roots (trees with a floating base)",
        )?;
        for (r, root) in state.roots.iter().enumerate() {
            check_values(&format!("world.roots[{r}]"), root, MAX_MAGNITUDE)?;
        }
        check_len(
            "world.mocap_targets",
            state.mocap_targets.len(),
            self.mocaps.len(),
            "mocap bodies",
        )?;
        for (k, target) in state.mocap_targets.iter().enumerate() {
            if let Some(t) = target {
                let path = format!("world.mocap_targets[{k}]");
                check_values(&path, &t[..3], MAX_MAGNITUDE)?;
                check_unit(&path, &[t[3], t[4], t[5], t[6]])?;
            }
        }
        self.check_actuator_state(state)
    }

    /// The controls and activations of `state`: one each per actuator, finite, and an
    /// activation within its range (0 where there is none).
    fn check_actuator_state(&self, state: &DynamicState) -> Result<()> {
        let n = self.actuators.len();
        check_len(
            "world.controls",
            state.controls.len(),
            n,
            "controls (one per actuator)",
        )?;
        check_values("world.controls", &state.controls, f32::MAX)?;
        check_len(
            "world.activations",
            state.activations.len(),
            n,
            "activations (one per actuator)",
        )?;
        for (k, (&act, a)) in state.activations.iter().zip(&self.actuators).enumerate() {
            let path = format!("world.activations[{k}]");
            if !(act.is_finite() && act.abs() <= f64::from(MAX_MAGNITUDE)) {
                return Err(bad(
                    path,
                    format!("expected a finite value within ±{MAX_MAGNITUDE:e}, got {act}"),
                ));
            }
            let stateless = a.dynamics == gymfleet_assembly::Dynamics::None;
            if stateless && act != 0.0 {
                return Err(bad(
                    path,
                    format!("actuator {k} has no activation dynamics: expected 0, got {act}"),
                ));
            }
            if let Some([lo, hi]) = a.act_range {
                if !(lo..=hi).contains(&act) {
                    return Err(bad(
                        path,
                        format!("{act} is outside actuator {k}'s activation range [{lo}, {hi}]"),
                    ));
                }
            }
        }
        self.saved_terrains(&state.terrains)?;
        Ok(())
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
        // A free root is placed from its body's pose (read by the kinematics below) and
        // moves with its six generalized velocities.
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
        self.sync_bodies(&touched);
        // A loop's constraint starts afresh, as contacts do: without the last step's
        // impulses as a first guess, so that every world restored from `state` is alike.
        for (_, joint) in self.live.impulse_joints.iter_mut() {
            joint.impulses = Default::default();
        }
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
        self.command.mode = state.mode;
        self.command.values.copy_from_slice(&state.command);
        self.command.controls.copy_from_slice(&state.controls);
        self.activations.copy_from_slice(&state.activations);
        self.configure_motors();
    }
}

/// How many of a joint's angular axes are free.
fn free_angular_dofs(joint: &MultibodyJoint) -> u32 {
    3 - (joint.data.locked_axes.bits() >> 3).count_ones()
}
