//! Mocap bodies' pose targets ([`crate::EnvSpec::mocap_bodies`]): set one by name, or all
//! at once (what a step request carries), in the env's units. A target is where the body's
//! reference frame is to be at the end of the next step, and stays until changed; a reset
//! puts every mocap body back where the document put it.

use gymfleet_assembly::quoted_list;
use gymfleet_physics::FREE_POSE_LEN;

use crate::env::RobotEnv;
use crate::error::{EnvError, Result};

/// Farthest a mocap target may lie from the origin, in metres (10 km: far past any scene,
/// near enough that nothing overflows).
const MAX_TARGET_M: f64 = 1e4;

impl RobotEnv {
    /// The position of mocap body `name` among [`crate::EnvSpec::mocap_bodies`].
    pub fn mocap_index(&self, name: &str) -> Result<usize> {
        let names = &self.spec().mocap_bodies;
        names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| EnvError::UnknownMocapBody {
                name: gymfleet_assembly::quoted(name),
                known: if names.is_empty() {
                    "none: the document has no mocap body".to_string()
                } else {
                    quoted_list(names)
                },
            })
    }

    /// Sets mocap body `name`'s target: `[x, y, z, qw, qx, qy, qz]`, world position in the
    /// env's units (mm, or m with SI units) and orientation (normalised).
    pub fn set_mocap_pose(&mut self, name: &str, pose: [f32; FREE_POSE_LEN]) -> Result<()> {
        let k = self.mocap_index(name)?;
        self.check_mocap_pose(
            &format!("mocap body {}", gymfleet_assembly::quoted(name)),
            &pose,
        )?;
        self.world.set_mocap_target(self.units, k, pose);
        Ok(())
    }

    /// Sets every mocap body's target at once: [`FREE_POSE_LEN`] floats each, in
    /// [`crate::EnvSpec::mocap_bodies`] order. Empty: every target stays as it is. All are
    /// checked before any is set.
    pub fn set_mocap_poses(&mut self, poses: &[f32]) -> Result<()> {
        self.check_mocap_poses(poses)?;
        self.apply_mocap_poses(poses);
        Ok(())
    }

    /// [`RobotEnv::step_into`] that first moves the mocap targets to `mocap_poses` (as
    /// [`RobotEnv::set_mocap_poses`] takes them; empty: they stay). The action and the
    /// targets are both checked before either is used: a bad one changes nothing.
    pub fn step_with_mocap_into(
        &mut self,
        action_type: crate::ActionType,
        values: &[f32],
        mocap_poses: &[f32],
        out: &mut [f32],
    ) -> Result<crate::StepFlags> {
        crate::action::validate(values, self.spec().action_dim)?;
        self.check_mocap_poses(mocap_poses)?;
        if !self.diverged {
            self.apply_mocap_poses(mocap_poses);
        }
        self.step_into(action_type, values, out)
    }

    /// Checks a step's mocap targets, as [`RobotEnv::set_mocap_poses`] would, changing
    /// nothing: none, or [`FREE_POSE_LEN`] usable floats per mocap body.
    pub fn check_mocap_poses(&self, poses: &[f32]) -> Result<()> {
        if poses.is_empty() {
            return Ok(());
        }
        let n = self.spec().mocap_bodies.len();
        if poses.len() != n * FREE_POSE_LEN {
            return Err(EnvError::MocapPosesLength {
                expected: n * FREE_POSE_LEN,
                got: poses.len(),
                bodies: n,
            });
        }
        for (k, pose) in poses.chunks_exact(FREE_POSE_LEN).enumerate() {
            let name = &self.spec().mocap_bodies[k];
            self.check_mocap_pose(
                &format!(
                    "mocap_poses[{}..{}] ({name})",
                    k * FREE_POSE_LEN,
                    (k + 1) * FREE_POSE_LEN
                ),
                pose,
            )?;
        }
        Ok(())
    }

    /// Sets the targets of checked `poses` (see [`RobotEnv::check_mocap_poses`]).
    pub(crate) fn apply_mocap_poses(&mut self, poses: &[f32]) {
        let units = self.units;
        for (k, pose) in poses.chunks_exact(FREE_POSE_LEN).enumerate() {
            let pose: [f32; FREE_POSE_LEN] = std::array::from_fn(|i| pose[i]);
            self.world.set_mocap_target(units, k, pose);
        }
    }

    /// Every mocap body's pose now, [`FREE_POSE_LEN`] floats each, in the env's units.
    pub fn mocap_poses(&self) -> Vec<f32> {
        let units = self.units;
        (0..self.spec().mocap_bodies.len())
            .flat_map(|k| self.world.mocap_pose(units, k))
            .collect()
    }

    /// A target is finite, within [`MAX_TARGET_M`] of the origin, and its quaternion is
    /// not zero.
    fn check_mocap_pose(&self, what: &str, pose: &[f32]) -> Result<()> {
        let bad = |reason: String| EnvError::BadMocapPose {
            what: what.to_string(),
            reason,
        };
        if let Some((i, v)) = pose.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(bad(format!("value {i} is {v}, expected a finite number")));
        }
        let max = self.units.length(MAX_TARGET_M);
        if let Some(v) = pose[..3].iter().find(|v| f64::from(v.abs()) > max) {
            return Err(bad(format!(
                "position {v} is more than {max} ({MAX_TARGET_M} m) from the origin"
            )));
        }
        let norm: f32 = pose[3..].iter().map(|q| q * q).sum::<f32>().sqrt();
        if norm < 1e-6 {
            return Err(bad(
                "the quaternion [qw, qx, qy, qz] is zero: no orientation".to_string(),
            ));
        }
        Ok(())
    }
}
