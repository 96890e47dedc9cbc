//! Checking a dynamic state before it is restored ([`RobotWorld::check_dynamic_state`]):
//! its counts against the world's, and its values (finite, bounded, unit rotations, within
//! hard limits, no command on a passive DOF), each error naming its field.

use gymfleet_assembly::{DofKind, JointType};

use super::{free_angular_dofs, DynamicState, JointCoords};
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

/// The bodies, free roots and mocap targets of `state`: one per instance, free root and
/// mocap body of the world (`bodies`, `roots`, `mocaps`), finite, with unit rotations.
fn check_body_states(
    state: &DynamicState,
    bodies: usize,
    roots: usize,
    mocaps: usize,
) -> Result<()> {
    check_len(
        "world.bodies",
        state.bodies.len(),
        bodies,
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
        roots,
        "free roots (trees with a floating base)",
    )?;
    for (r, root) in state.roots.iter().enumerate() {
        check_values(&format!("world.roots[{r}]"), root, MAX_MAGNITUDE)?;
    }
    check_len(
        "world.mocap_targets",
        state.mocap_targets.len(),
        mocaps,
        "mocap bodies",
    )?;
    for (k, target) in state.mocap_targets.iter().enumerate() {
        if let Some(t) = target {
            let path = format!("world.mocap_targets[{k}]");
            check_values(&path, &t[..3], MAX_MAGNITUDE)?;
            check_unit(&path, &[t[3], t[4], t[5], t[6]])?;
        }
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

impl RobotWorld {
    /// Checks that `state` fits this world (counts) and holds only sane values: finite,
    /// within bounds, limited DOFs on their side of the limits, unit quaternions, no command
    /// on a passive DOF. An error names the field (`world.joints[2].coords[3]`).
    pub fn check_dynamic_state(&self, state: &DynamicState) -> Result<()> {
        self.check_dof_state(state)?;
        let moving = self.moving_joints().count();
        check_len(
            "world.joints",
            state.joints.len(),
            moving,
            "joints (those with a DOF)",
        )?;
        for (j, (slot, saved)) in self.moving_joints().zip(&state.joints).enumerate() {
            self.check_joint_state(&format!("world.joints[{j}]"), slot, saved)?;
        }
        check_body_states(
            state,
            self.bodies.len(),
            self.free_roots.len(),
            self.mocaps.len(),
        )?;
        self.check_actuator_state(state)
    }

    /// The commands and velocities of `state`: one each per DOF, finite, and no command
    /// on a passive DOF.
    fn check_dof_state(&self, state: &DynamicState) -> Result<()> {
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
        check_values("world.velocities", &state.velocities, MAX_MAGNITUDE)
    }

    /// One moving joint's saved coordinates (at `path`): finite, 0 on its locked axes,
    /// within its hard limits, and a rotation exactly where it is a ball joint.
    fn check_joint_state(
        &self,
        path: &str,
        slot: &crate::world::JointSlot,
        saved: &JointCoords,
    ) -> Result<()> {
        check_values(&format!("{path}.coords"), &saved.coords, MAX_MAGNITUDE)?;
        let link = self
            .live
            .multibody_joints
            .get_multibody(slot.multibody)
            .and_then(|mb| mb.link(slot.link));
        let Some(link) = link else { return Ok(()) };
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
            check_within(dof, [min, max], saved.coords[axis], path, axis)?;
        }
        match (free_angular_dofs(joint) == 3, &saved.rotation) {
            (true, Some(q)) => check_unit(&format!("{path}.rotation"), q),
            (true, None) => Err(bad(
                format!("{path}.rotation"),
                "a ball joint's state needs its rotation".to_string(),
            )),
            (false, Some(_)) => Err(bad(
                format!("{path}.rotation"),
                "only a ball joint's state has a rotation".to_string(),
            )),
            (false, None) => Ok(()),
        }
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
}
