//! Body-level quantities as MuJoCo defines them (`engine_core_smooth.c`), for a group of
//! instances that make up one MuJoCo body, in the frame MuJoCo uses for them: origin at
//! a given point (the root's subtree centre of mass), world axes. All SI.
//! - `cinert`: the group's inertia about that point (Ixx, Iyy, Izz, Ixy, Ixz, Iyz), its
//!   mass times its centre's offset from the point (3), and its mass;
//! - `cvel`: the group's angular velocity, then the linear velocity of the group-fixed
//!   point at that point;
//! - `qfrc_actuator`: the generalized force the command applies to a DOF.

use rapier3d::math::{Real, Vector};

use crate::command::ActionMode;
use crate::world::RobotWorld;

/// Floats in [`RobotWorld::group_inertia`].
pub const INERTIA_LEN: usize = 10;
/// Floats in [`RobotWorld::group_velocity`].
pub const VELOCITY_LEN: usize = 6;

impl RobotWorld {
    /// MuJoCo's `cinert` of the group of instances `group` about `about` (world m):
    /// summed over the instances, each with the parallel-axis shift of its own centre.
    pub fn group_inertia(&self, group: &[usize], about: [f64; 3]) -> [f64; INERTIA_LEN] {
        let mut out = [0.0; INERTIA_LEN];
        for &instance in group {
            let body = self.body_frame(instance);
            // The instance's own mass (a body may carry folded instances' too).
            let props = &self.own_mass_properties(instance);
            let m = f64::from(props.mass());
            if !(m > 0.0 && m.is_finite()) {
                continue;
            }
            // R·diag(I)·Rᵀ: the principal inertia turned into world axes.
            let axes = body.rotation * props.principal_inertia_local_frame;
            let principal = props.principal_inertia();
            let mut rotated = [[0.0f64; 3]; 3];
            let columns: [Vector; 3] = [axes * Vector::X, axes * Vector::Y, axes * Vector::Z];
            let moments = [principal.x, principal.y, principal.z];
            for (col, moment) in columns.iter().zip(moments) {
                let c = [col.x, col.y, col.z].map(f64::from);
                for i in 0..3 {
                    for j in 0..3 {
                        rotated[i][j] += f64::from(moment) * c[i] * c[j];
                    }
                }
            }
            let com = self.own_center_of_mass(instance);
            let d = [
                f64::from(com.x) - about[0],
                f64::from(com.y) - about[1],
                f64::from(com.z) - about[2],
            ];
            out[0] += rotated[0][0] + m * (d[1] * d[1] + d[2] * d[2]);
            out[1] += rotated[1][1] + m * (d[0] * d[0] + d[2] * d[2]);
            out[2] += rotated[2][2] + m * (d[0] * d[0] + d[1] * d[1]);
            out[3] += rotated[0][1] - m * d[0] * d[1];
            out[4] += rotated[0][2] - m * d[0] * d[2];
            out[5] += rotated[1][2] - m * d[1] * d[2];
            for k in 0..3 {
                out[6 + k] += m * d[k];
            }
            out[9] += m;
        }
        out
    }

    /// MuJoCo's `cvel` of the group (rigid: its first instance's motion): angular velocity
    /// (rad/s), then the velocity (m/s) of the group-fixed point at `about` (world m).
    pub fn group_velocity(&self, group: &[usize], about: [f64; 3]) -> [f64; VELOCITY_LEN] {
        let Some(&first) = group.first() else {
            return [0.0; VELOCITY_LEN];
        };
        if let Some(helper) = self.planar_helper(first) {
            // A fused planar root's helper slides without turning.
            let v = self.helper_motion(helper).1;
            return [0.0, 0.0, 0.0, v.x, v.y, v.z].map(f64::from);
        }
        let rb = &self.live.bodies[self.bodies[first]];
        let w = rb.angvel();
        let arm =
            Vector::new(about[0] as Real, about[1] as Real, about[2] as Real) - rb.center_of_mass();
        let v = rb.linvel() + w.cross(arm);
        [w.x, w.y, w.z, v.x, v.y, v.z].map(f64::from)
    }

    /// The generalized force (N·m or N) the held command applies to DOF `dof` (MuJoCo's
    /// `qfrc_actuator`): a torque-mode value's gear × value, clamped by `max_effort`, plus
    /// every actuator's moment × force on it now. A direct value under position or velocity
    /// targets counts 0 (Rapier's motors do not report their force).
    pub fn dof_actuator_force(&self, dof: usize) -> f64 {
        let d = &self.dofs[dof];
        let direct = if self.command.mode != ActionMode::Torque || !d.actuated {
            0.0
        } else {
            crate::actuation::clamp_effort(
                d.gear * f64::from(self.command.values[dof]),
                d.max_effort,
            )
        };
        if self.actuators.is_empty() {
            direct
        } else {
            direct + self.actuators_on_dof(dof)
        }
    }
}
