//! Models and helpers shared by the batch tests.
#![allow(dead_code, unreachable_pub)]

use gymfleet_batch::BatchStepOutput;
use gymfleet_env::{ActionType, EnvConfig, RobotEnv};

pub const ARM2: &str = include_str!("../../../../models/arm2.json");
pub const PENDULUM: &str = include_str!("../../../../models/pendulum.json");

/// The seed 2-DOF arm observing "forearm": action_dim 2, observation_dim 11.
pub fn arm2(max_steps: u32) -> RobotEnv {
    let config = EnvConfig {
        max_steps,
        ..EnvConfig::with_end_effectors(["forearm"])
    };
    RobotEnv::from_json(ARM2, config).expect("arm2 is valid")
}

/// [`arm2`] whose resets start each joint up to `noise` degrees off its initial angle.
pub fn noisy_arm2(max_steps: u32, noise: f64) -> RobotEnv {
    let config = EnvConfig {
        max_steps,
        reset_noise: noise,
        ..EnvConfig::with_end_effectors(["forearm"])
    };
    RobotEnv::from_json(ARM2, config).expect("arm2 is valid")
}

/// The seed pendulum observing "arm": action_dim 1, observation_dim 9.
pub fn pendulum(max_steps: u32, substeps: u32) -> RobotEnv {
    let config = EnvConfig {
        max_steps,
        substeps,
        ..EnvConfig::with_end_effectors(["arm"])
    };
    RobotEnv::from_json(PENDULUM, config).expect("pendulum is valid")
}

/// A deterministic, varied action sequence: step `t` of `n_envs` envs of `dim` DOF.
/// Cycles through the three action types with per-env, per-DOF values.
pub fn actions(t: usize, n_envs: usize, dim: usize) -> (ActionType, Vec<f32>) {
    let action_type = [
        ActionType::Position,
        ActionType::Torque,
        ActionType::Velocity,
    ][t % 3];
    let scale = match action_type {
        ActionType::Position => 60.0,
        ActionType::Torque => 2e-3,
        ActionType::Velocity => 90.0,
    };
    let values = (0..n_envs * dim)
        .map(|k| scale * ((k * 7 + t * 13) as f32 * 0.37).sin())
        .collect();
    (action_type, values)
}

pub fn bits(values: &[f32]) -> Vec<u32> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// Everything of an output, floats as bits, for exact comparison.
pub fn output_bits(out: &BatchStepOutput) -> impl PartialEq + std::fmt::Debug {
    (
        bits(&out.observations),
        bits(&out.rewards),
        out.terminated.clone(),
        out.truncated.clone(),
        out.final_env_indices.clone(),
        bits(&out.final_observations),
        out.termination_reasons.clone(),
    )
}
