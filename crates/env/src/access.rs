//! State access as MuJoCo's users have it: setting the robot's joint state from values
//! (`set_state(qpos, qvel)`), and reading every instance's and site's body-level
//! quantities (`xpos`, `xipos`, `cinert`, `cvel`, `cfrc_ext`, `qfrc_actuator`, ...).

use gymfleet_physics::{
    StateAdjustment, Units, BASE_STATE_LEN, INERTIA_LEN, VELOCITY_LEN, WRENCH_LEN,
};

use crate::env::RobotEnv;
use crate::error::{EnvError, Result};

/// Every instance's and site's state now ([`RobotEnv::bodies`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Bodies {
    /// The instances' names, in document order; the per-instance fields follow it.
    pub instances: Vec<String>,
    /// Each instance's own mass, kg (as randomised this episode).
    pub masses: Vec<f64>,
    /// Each instance's centre of mass, world, in the env's units.
    pub centers_of_mass: Vec<[f64; 3]>,
    /// Each instance's MuJoCo `cinert` about [`Bodies::about`] (SI: Ixx, Iyy, Izz, Ixy,
    /// Ixz, Iyz, mass × offset, mass). Sums over instances give a group's.
    pub inertias: Vec<[f64; INERTIA_LEN]>,
    /// Each instance's MuJoCo `cvel` at [`Bodies::about`] (SI: angular, then linear).
    pub velocities: Vec<[f64; VELOCITY_LEN]>,
    /// The wrench the last step's contacts applied to each instance, about
    /// [`Bodies::about`] (SI: torque, then force; MuJoCo's `cfrc_ext`). Zeros after a reset.
    pub contact_wrenches: Vec<[f64; WRENCH_LEN]>,
    /// The point the c-frame quantities are taken about: the robot's centre of mass, m
    /// (MuJoCo's root subtree centre of mass).
    pub about: [f64; 3],
    /// The document's sites' names, in document order (an MJCF body's origin is one).
    pub sites: Vec<String>,
    /// Each site's pose: position (world, env units), then orientation `[qw, qx, qy, qz]`.
    pub site_poses: Vec<[f32; 7]>,
    /// The generalized force the command applies to each DOF (MuJoCo's `qfrc_actuator`).
    pub actuator_forces: Vec<f64>,
    /// The document's sensors: name, type (its MJCF element name) and how many floats it
    /// reports, in document order.
    pub sensors: Vec<(String, &'static str, usize)>,
    /// Every sensor's reading, SI, in that order (MuJoCo's `sensordata`).
    pub sensor_data: Vec<f64>,
}

impl RobotEnv {
    /// Every instance's and site's state now (reads only).
    pub fn bodies(&self) -> Bodies {
        let world = &self.world;
        let about = world.robot_center_of_mass(Units::Si);
        let n = world.num_bodies();
        let mut contact_wrenches = Vec::with_capacity(n);
        world.contact_wrenches(about, &mut contact_wrenches);
        Bodies {
            instances: self.names.0.clone(),
            masses: (0..n).map(|i| world.instance_mass(i)).collect(),
            centers_of_mass: (0..n)
                .map(|i| world.center_of_mass(self.units, i))
                .collect(),
            inertias: (0..n).map(|i| world.group_inertia(&[i], about)).collect(),
            velocities: (0..n).map(|i| world.group_velocity(&[i], about)).collect(),
            contact_wrenches,
            about,
            sites: self.sites.iter().map(|(name, _)| name.clone()).collect(),
            site_poses: self
                .sites
                .iter()
                .map(|(_, site)| self.end_effector_pose(self.units, *site))
                .collect(),
            actuator_forces: (0..world.dofs().len())
                .map(|k| world.dof_actuator_force(k))
                .collect(),
            sensors: self.spec.sensors.clone(),
            sensor_data: self.sensor_data(),
        }
    }

    /// Every sensor's reading now, SI ([`Bodies::sensor_data`]).
    pub fn sensor_data(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.world.sensor_dim()];
        self.world.sensor_data(&mut out);
        out
    }

    /// Sets the robot's joint state, as MuJoCo's `set_state(qpos, qvel)` does, and writes
    /// the observation there into `out`: every DOF's position and velocity (the
    /// observation's layout and units) and, for a floating base, its state `base`
    /// ([`BASE_STATE_LEN`] floats: the observation's `base_pose` then `base_velocity`;
    /// empty without one). The episode goes on: its step count, seed, task and draws stay.
    /// Positions past a hard limit are set at the limit, and joints on a kinematic loop
    /// keep theirs; the returned adjustments say which (see
    /// [`gymfleet_physics::RobotWorld::set_joint_state`]).
    ///
    /// # Errors
    ///
    /// [`EnvError::BadJointState`] for a wrong count, a non-finite value or a zero
    /// orientation; the env is unchanged then.
    pub fn set_joint_state(
        &mut self,
        positions: &[f64],
        velocities: &[f64],
        base: &[f64],
        out: &mut [f32],
    ) -> Result<Vec<StateAdjustment>> {
        let dofs = self.spec.num_dofs;
        check_values("joint_positions", positions, dofs, "one per DOF")?;
        check_values("joint_velocities", velocities, dofs, "one per DOF")?;
        let base: Option<[f64; BASE_STATE_LEN]> = if self.spec.floating_base {
            check_values(
                "base_state",
                base,
                BASE_STATE_LEN,
                "the base's pose x, y, z, qw, qx, qy, qz, then its velocity vx, vy, vz, wx, wy, wz",
            )?;
            if base[3..7].iter().all(|&v| v == 0.0) {
                return Err(EnvError::BadJointState {
                    field: "base_state[3..7]".into(),
                    reason: "the orientation quaternion (qw, qx, qy, qz) is all zeros".into(),
                });
            }
            base.try_into().ok()
        } else {
            if !base.is_empty() {
                return Err(EnvError::BadJointState {
                    field: "base_state".into(),
                    reason: format!(
                        "the env has no floating base: give no values, got {}",
                        base.len()
                    ),
                });
            }
            None
        };
        let notes = self
            .world
            .set_joint_state(self.units, positions, velocities, base.as_ref());
        self.diverged = false;
        self.observe_into(out);
        self.start_task(out);
        self.observe_task_into(out);
        self.last_obs.copy_from_slice(out);
        Ok(notes)
    }
}

/// `values` must hold `expected` finite numbers (`what` says which).
fn check_values(field: &str, values: &[f64], expected: usize, what: &str) -> Result<()> {
    if values.len() != expected {
        return Err(EnvError::BadJointState {
            field: field.into(),
            reason: format!("expected {expected} values ({what}), got {}", values.len()),
        });
    }
    match values.iter().position(|v| !v.is_finite()) {
        Some(k) => Err(EnvError::BadJointState {
            field: format!("{field}[{k}]"),
            reason: format!("expected a finite number, got {}", values[k]),
        }),
        None => Ok(()),
    }
}
