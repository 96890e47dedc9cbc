//! Actuation: real torques and forces, and force-based PD motors for targets.
//!
//! - **Torque** mode applies the effort as a joint-space (generalized) force on the DOF:
//!   what a motor at the joint exerts, equal and opposite on the joint's two bodies, along
//!   the joint's current axis at every substep, so momentum is conserved and the sign is
//!   kept.
//! - **Position** and **velocity** modes use Rapier's force-based joint motors, which are
//!   integrated implicitly and clamped by `max_effort`. Ball joints, whose Rapier motors
//!   work on non-geometric coordinates, get an explicit PD torque in the joint frame,
//!   recomputed every substep.
//! - Limits are hard stops in every mode: Rapier puts a DOF found past its limit back on it
//!   after every substep (the multibody's hard limits, `vendor/rapier3d/PATCHES.md`).
//!
//! Default gains: for each DOF the apparent inertia `I = 1 / diag(M⁻¹)` at the initial
//! configuration (MuJoCo's `dof_invweight0`, from Rapier's `dof_inverse_inertia`), then
//! `kp = I·ω²` and `kd = 2·I·ω` (critical damping) with `ω = 2π·20 Hz`; velocity targets use
//! `kv`, at least `kd` and enough that the DOF's gravity load bends them by at most 0.05 rad/s
//! (5 mm/s). `I` and the load count what the DOF drives through kinematic loops (`loads.rs`).
//! Given gains (`pd_gains`) drive velocity targets with `kd` alone. Explicit ball PD caps `ω`
//! at `0.2 / substep_dt` for stability.

use gymfleet_assembly::{DofKind, JointType};
use rapier3d::prelude::*;

use crate::command::{ActionMode, PdGains, DEFAULT_PD_FREQUENCY_HZ};
use crate::error::{PhysicsError, Result};
use crate::loads::DofLoad;
use crate::units::to_si;
use crate::world::{JointDof, JointSlot, RobotWorld};

/// The most gravity may bend a velocity target by under the default gains, rad/s for an
/// angular DOF (about 3 °/s) and m/s for a linear one (issue F).
pub const GRAVITY_SAG_ANGULAR: f64 = 0.05;
/// See [`GRAVITY_SAG_ANGULAR`]; m/s.
pub const GRAVITY_SAG_LINEAR: f64 = 0.005;
/// The default gains `(kp, kd, kv)` of a DOF that drives `load` (`loads.rs`): position
/// targets critically damped at [`DEFAULT_PD_FREQUENCY_HZ`] (`kp = I·ω²`, `kd = 2·I·ω`), and
/// velocity targets with `kv = max(kd, hold / sag)`, so that the gravity load bends them by
/// at most [`GRAVITY_SAG_ANGULAR`] (`_LINEAR`).
///
/// A 20 mm crank driving a 60 mm coupler and a 50 mm rocker (2 mm rods) holds up to 2e-4 N·m
/// at an inertia of 6e-7 kg·m²: with `kd`'s 1.5e-4 N·m·s/rad gravity stalled it. A velocity
/// servo's kick is `I·Δω` however stiff it is; a position servo's grows with its bandwidth
/// (stiffened the same way, `kp ≥ hold / 0.01 rad`, a floating robot's arm under alternating
/// position targets threw its 200 g base off the floor), so position targets keep 20 Hz.
pub(crate) fn pd_gains_from_load(load: DofLoad, kind: DofKind) -> (f64, f64, f64) {
    let omega = 2.0 * std::f64::consts::PI * DEFAULT_PD_FREQUENCY_HZ;
    let sag = match kind {
        DofKind::Angular => GRAVITY_SAG_ANGULAR,
        DofKind::Linear => GRAVITY_SAG_LINEAR,
    };
    let i = load.inertia;
    let (kp, kd) = (i * omega * omega, 2.0 * i * omega);
    (kp, kd, kd.max(load.hold / sag))
}

/// Fills `kp`/`kd`/`kv` of each DOF from overrides or from what it drives.
pub(crate) fn resolve_gains(
    dofs: &mut [JointDof],
    loads: &[DofLoad],
    overrides: Option<&PdGains>,
) -> Result<bool> {
    for (dof, &load) in dofs.iter_mut().zip(loads) {
        (dof.kp, dof.kd, dof.kv) = pd_gains_from_load(load, dof.kind);
    }
    let Some(gains) = overrides else {
        return Ok(false);
    };
    for (field, values) in [("pd_gains.kp", &gains.kp), ("pd_gains.kd", &gains.kd)] {
        if values.is_empty() {
            continue;
        }
        if values.len() != dofs.len() {
            return Err(PhysicsError::BadGains {
                field,
                reason: format!(
                    "expected {} values (one per DOF), got {}",
                    dofs.len(),
                    values.len()
                ),
            });
        }
        if let Some((i, v)) = values
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(PhysicsError::BadGains {
                field,
                reason: format!("expected finite gains >= 0, got {v} at index {i}"),
            });
        }
    }
    for (i, dof) in dofs.iter_mut().enumerate() {
        if let Some(&kp) = gains.kp.get(i) {
            dof.kp = kp;
        }
        if let Some(&kd) = gains.kd.get(i) {
            // Given gains drive velocity targets with `kd` alone.
            dof.kd = kd;
            dof.kv = kd;
        }
    }
    Ok(!(gains.kp.is_empty() && gains.kd.is_empty()))
}

/// The Rapier axis of each DOF of a joint whose Rapier motors are used.
fn motor_axes(slot: &JointSlot) -> &'static [JointAxis] {
    match slot.kind {
        JointType::Ball | JointType::Fixed => &[],
        _ => slot.axes(),
    }
}

pub(crate) fn clamp_effort(value: f64, max_effort: Option<f64>) -> f64 {
    match max_effort {
        Some(m) => value.clamp(-m, m),
        None => value,
    }
}

impl RobotWorld {
    /// Writes the held command into the Rapier motors of every non-ball joint.
    pub(crate) fn configure_motors(&mut self) {
        let mode = self.command.mode;
        for slot in &self.joints {
            if slot.closing.is_some() {
                continue; // A loop-closing joint (`loops.rs`).
            }
            let axes = motor_axes(slot);
            if axes.is_empty() {
                continue;
            }
            // A joint that is to have no motor and has none is left untouched: a mutable
            // access to a link makes Rapier redo its multibody's forward kinematics at the next
            // step (`vendor/rapier3d/PATCHES.md` 14), and under torques nothing changes.
            let motorless = mode == ActionMode::Torque
                || (0..axes.len()).all(|k| !self.dofs[slot.first_dof + k].actuated);
            if motorless && !self.has_motor(slot, axes) {
                continue;
            }
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(link) = mb.link_mut(slot.link) else {
                continue;
            };
            let data = &mut link.joint.data;
            for (k, &axis) in axes.iter().enumerate() {
                let dof = &self.dofs[slot.first_dof + k];
                let value = f64::from(self.command.values[slot.first_dof + k]);
                let mask = JointAxesMask::from(axis);
                match mode {
                    // A passive DOF never has a motor.
                    _ if !dof.actuated => data.motor_axes.remove(mask),
                    ActionMode::Torque => data.motor_axes.remove(mask),
                    ActionMode::Position => {
                        // A target beyond a hard stop would only make the motor fight
                        // the limit constraint; aim at the stop instead.
                        let value = match dof.limits {
                            Some([min, max]) => value.clamp(min, max),
                            None => value,
                        };
                        let _ = data
                            .set_motor(
                                axis,
                                to_si(dof.kind, value) as Real,
                                0.0,
                                dof.kp as Real,
                                dof.kd as Real,
                            )
                            .set_motor_model(axis, MotorModel::ForceBased)
                            .set_motor_max_force(
                                axis,
                                dof.max_effort.map_or(Real::MAX, |m| m as Real),
                            );
                    }
                    ActionMode::Velocity => {
                        let _ = data
                            .set_motor(
                                axis,
                                0.0,
                                to_si(dof.kind, value) as Real,
                                0.0,
                                dof.kv as Real,
                            )
                            .set_motor_model(axis, MotorModel::ForceBased)
                            .set_motor_max_force(
                                axis,
                                dof.max_effort.map_or(Real::MAX, |m| m as Real),
                            );
                    }
                }
            }
        }
    }

    /// Whether any of `axes` of the joint in `slot` has a Rapier motor.
    fn has_motor(&self, slot: &JointSlot, axes: &[JointAxis]) -> bool {
        self.live
            .multibody_joints
            .get_multibody(slot.multibody)
            .and_then(|mb| mb.link(slot.link))
            .is_some_and(|link| {
                axes.iter().any(|&axis| {
                    link.joint
                        .data
                        .motor_axes
                        .contains(JointAxesMask::from(axis))
                })
            })
    }

    /// Whether some effort depends on the state within a step (the explicit PD of ball
    /// joints under targets, a fluid's drag, a tendon's spring, an actuator's bias, gain or
    /// activation), so that it must be recomputed every substep.
    pub(crate) fn has_state_dependent_efforts(&self) -> bool {
        (self.command.mode != ActionMode::Torque && self.has_ball_joints)
            || self.fluid.is_some()
            || self.tendons.iter().any(|t| t.has_force())
            || self.has_state_dependent_actuators()
    }

    /// Writes the held joint-space efforts into the multibodies: torque-mode efforts on
    /// every DOF (clamped by `max_effort`), and the explicit PD of ball joints in target
    /// modes. DOFs driven by Rapier's motors get none.
    pub(crate) fn apply_efforts(&mut self) {
        self.clear_body_forces();
        let mode = self.command.mode;
        for slot in &self.joints {
            if slot.closing.is_some() {
                continue; // A loop-closing joint (`loops.rs`).
            }
            let n = slot.kind.dof();
            let efforts: [Real; 3] = match (slot.kind, mode) {
                (JointType::Fixed, _) => continue,
                (JointType::Ball, _) => self.ball_torque(slot),
                (_, ActionMode::Torque) => {
                    let mut efforts = [0.0; 3];
                    for (k, effort) in efforts.iter_mut().enumerate().take(n) {
                        let dof = &self.dofs[slot.first_dof + k];
                        let value = f64::from(self.command.values[slot.first_dof + k]);
                        *effort = clamp_effort(dof.gear * value, dof.max_effort) as Real;
                    }
                    efforts
                }
                _ => [0.0; 3], // Rapier's motors do the work.
            };
            let Some(mb) = self.live.multibody_joints.get_multibody_mut(slot.multibody) else {
                continue;
            };
            let Some(first) = mb.link(slot.link).map(|link| link.assembly_id()) else {
                continue;
            };
            mb.applied_forces_mut()
                .rows_mut(slot.link_dof(first, 0), n)
                .copy_from_slice(&efforts[..n]);
        }
        self.apply_tendon_forces();
        self.apply_actuator_forces();
    }

    /// The torque a ball joint applies to its child, in the joint frame (the frame of its
    /// generalized coordinates).
    fn ball_torque(&self, slot: &JointSlot) -> [Real; 3] {
        let first = slot.first_dof;
        let values = &self.command.values;
        let dofs = &self.dofs[first..first + 3];
        if !dofs[0].actuated {
            return [0.0; 3];
        }
        let v = |k: usize| f64::from(values[first + k]);
        let local = match self.command.mode {
            ActionMode::Torque => [v(0), v(1), v(2)],
            mode => {
                let (rotation, angvel) = self.ball_state(slot);
                let error = match mode {
                    ActionMode::Position => {
                        let target = Rotation::from_scaled_axis(Vector::new(
                            v(0).to_radians() as Real,
                            v(1).to_radians() as Real,
                            v(2).to_radians() as Real,
                        ));
                        // The rotation still to go, in the parent-side joint frame.
                        let mut error = target * rotation.inverse();
                        if error.w < 0.0 {
                            error = -error;
                        }
                        let e = error.to_scaled_axis();
                        [f64::from(e.x), f64::from(e.y), f64::from(e.z)]
                    }
                    _ => [0.0; 3],
                };
                let velocity_error = match mode {
                    ActionMode::Velocity => [0, 1, 2].map(|k| v(k).to_radians() - angvel[k]),
                    _ => angvel.map(|w| -w),
                };
                if self.gains.overridden {
                    [0, 1, 2].map(|k| dofs[k].kp * error[k] + dofs[k].kd * velocity_error[k])
                } else {
                    self.ball_default_pd(slot, error, velocity_error)
                }
            }
        };
        [0, 1, 2].map(|k| clamp_effort(local[k], dofs[k].max_effort) as Real)
    }
}

impl RobotWorld {
    /// The default ball PD: a desired angular acceleration `ω²·e + 2ω·ė` shaped by the
    /// child's inertia tensor about the anchor, so every direction is critically damped
    /// at the same `ω` whatever the link's shape (per-axis gains would couple through
    /// the products of inertia and go unstable on a slender link).
    fn ball_default_pd(
        &self,
        slot: &JointSlot,
        error: [f64; 3],
        velocity_error: [f64; 3],
    ) -> [f64; 3] {
        let frame = self.joint_frame_world(slot);
        let omega =
            (2.0 * std::f64::consts::PI * DEFAULT_PD_FREQUENCY_HZ).min(self.gains.ball_omega_cap);
        let child = &self.live.bodies[slot.child];
        let mprops = &child.mass_properties().local_mprops;
        let rot = Matrix::from_quat(child.position().rotation);
        let mut inertia = rot * mprops.reconstruct_inertia_matrix() * rot.transpose();
        let r = child.center_of_mass() - frame.translation;
        let m = mprops.mass();
        inertia += (Matrix::IDENTITY * r.length_squared()
            - Matrix::from_cols(r * r.x, r * r.y, r * r.z))
            * m;
        let to_joint = Matrix::from_quat(frame.rotation);
        let inertia = to_joint.transpose() * inertia * to_joint;
        let accel = Vector::new(
            (omega * omega * error[0] + 2.0 * omega * velocity_error[0]) as Real,
            (omega * omega * error[1] + 2.0 * omega * velocity_error[1]) as Real,
            (omega * omega * error[2] + 2.0 * omega * velocity_error[2]) as Real,
        );
        let torque = inertia * accel;
        [
            f64::from(torque.x),
            f64::from(torque.y),
            f64::from(torque.z),
        ]
    }
}
