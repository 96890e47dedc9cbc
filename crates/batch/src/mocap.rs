//! Every env's mocap targets, set with a batch step ([`EnvBatch::step_with_mocap`]):
//! `n_envs × mocap bodies × 7` values, row-major per env, as each env takes its own
//! ([`gymfleet_env::RobotEnv::set_mocap_poses`]). They are checked, with the actions,
//! before any env is changed.

use gymfleet_env::{ActionType, FREE_POSE_LEN};

use crate::batch::{lock, BatchStepOutput, EnvBatch};
use crate::error::{BatchError, Result};
use crate::pool::StepPool;

impl EnvBatch {
    /// [`EnvBatch::step`], with every env's mocap bodies moved to `mocap_poses` by the end
    /// of the step (`n_envs × mocap bodies × 7` values, row-major per env, each
    /// `[x, y, z, qw, qx, qy, qz]` in the envs' units; empty: the targets stay). The
    /// actions and the targets are all checked before any env is changed.
    pub fn step_with_mocap(
        &mut self,
        pool: &StepPool,
        action_type: ActionType,
        actions: &[f32],
        mocap_poses: &[f32],
        out: &mut BatchStepOutput,
    ) -> Result<()> {
        if !mocap_poses.is_empty() {
            self.validate(actions)?;
            self.set_mocap_poses(mocap_poses)?;
        }
        self.step(pool, action_type, actions, out)
    }

    /// Sets every env's mocap targets (see [`EnvBatch::step_with_mocap`]); all are checked
    /// before any is set. Empty: nothing changes.
    pub fn set_mocap_poses(&mut self, poses: &[f32]) -> Result<()> {
        if poses.is_empty() {
            return Ok(());
        }
        let bodies = self.spec().mocap_bodies.len();
        let row = FREE_POSE_LEN * bodies;
        let expected = self.n_envs() * row;
        if poses.len() != expected {
            return Err(BatchError::MocapPosesLength {
                expected,
                got: poses.len(),
                n_envs: self.n_envs(),
                bodies,
            });
        }
        for set in [false, true] {
            for chunk in self.chunks.iter() {
                let mut chunk = lock(chunk);
                let first = chunk.first_env;
                for i in 0..chunk.len() {
                    let env = first + i;
                    let own = &poses[env * row..(env + 1) * row];
                    let result = if set {
                        chunk.env_mut(i).set_mocap_poses(own)
                    } else {
                        chunk.env(i).check_mocap_poses(own)
                    };
                    result.map_err(|source| BatchError::Env { env, source })?;
                }
            }
        }
        Ok(())
    }
}
