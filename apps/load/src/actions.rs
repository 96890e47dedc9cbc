//! [`ActionPlan`]: the deterministic actions of a run. Every DOF of every env follows
//! its own slow sinusoid (phase and period drawn from the seed, the env's global index
//! and the DOF), so in-process and remote runs of one configuration send identical
//! values, and the arms keep moving instead of settling.

use crate::model::DEFAULT_TORQUE_AMPLITUDE;
use serde::Serialize;

/// How action values are interpreted; the same three modes as the server's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum ActionKind {
    /// Efforts in N·m (or N).
    Torque,
    /// Position targets in deg (or mm), kept within the DOF's limits.
    Position,
    /// Velocity targets in deg/s (or mm/s).
    Velocity,
}

impl ActionKind {
    /// The lowercase name, as on the command line.
    pub fn as_str(self) -> &'static str {
        match self {
            ActionKind::Torque => "torque",
            ActionKind::Position => "position",
            ActionKind::Velocity => "velocity",
        }
    }

    /// The default amplitude: none for torque actions (each DOF swings within its own
    /// action bound), 30° for position targets and 45°/s for velocity targets.
    pub fn default_amplitude(self) -> Option<f32> {
        match self {
            ActionKind::Torque => None,
            ActionKind::Position => Some(30.0),
            ActionKind::Velocity => Some(45.0),
        }
    }

    /// The client's action type.
    pub fn to_client(self) -> gymfleet_client::ActionType {
        match self {
            ActionKind::Torque => gymfleet_client::ActionType::Torque,
            ActionKind::Position => gymfleet_client::ActionType::Position,
            ActionKind::Velocity => gymfleet_client::ActionType::Velocity,
        }
    }
}

/// One DOF's wave: `centre + amplitude · sin(phase + 2π·step/period)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct DofWave {
    centre: f64,
    amplitude: f64,
}

/// Deterministic actions for every env and step of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct ActionPlan {
    waves: Vec<DofWave>,
    seed: u64,
}

impl ActionPlan {
    /// A plan for DOFs with these hard limits (deg or mm, `None` where unlimited) and
    /// torque action bounds (one per DOF; empty where the server reports none). Position
    /// targets stay inside `[min, max]`, centred in the range, with at most `amplitude` and
    /// at most 80 % of the half-range; other modes swing `±amplitude`, and without one each
    /// DOF swings within its bound ([`DEFAULT_TORQUE_AMPLITUDE`] where there is none).
    pub fn new(
        kind: ActionKind,
        amplitude: Option<f32>,
        limits: &[Option<(f64, f64)>],
        bounds: &[f64],
        seed: u64,
    ) -> Self {
        let waves = limits
            .iter()
            .enumerate()
            .map(|(dof, limit)| {
                let amplitude = amplitude.map_or_else(
                    || {
                        bounds
                            .get(dof)
                            .copied()
                            .unwrap_or(f64::from(DEFAULT_TORQUE_AMPLITUDE))
                    },
                    f64::from,
                );
                (amplitude, limit)
            })
            .map(|(amplitude, limit)| match (kind, limit) {
                (ActionKind::Position, Some((min, max))) => DofWave {
                    centre: (min + max) / 2.0,
                    amplitude: amplitude.min(0.8 * (max - min) / 2.0),
                },
                _ => DofWave {
                    centre: 0.0,
                    amplitude,
                },
            })
            .collect();
        ActionPlan { waves, seed }
    }

    /// Values per env action.
    pub fn action_dim(&self) -> usize {
        self.waves.len()
    }

    /// Writes the actions of call `step` for envs `first_env..first_env + n` into `out`
    /// (`n × action_dim` values, row-major), where `n = out.len() / action_dim`.
    pub fn fill(&self, step: u64, first_env: u64, out: &mut [f32]) {
        let dim = self.waves.len().max(1);
        for (row, values) in out.chunks_exact_mut(dim).enumerate() {
            let env = first_env + row as u64;
            for ((dof, value), wave) in values.iter_mut().enumerate().zip(&self.waves) {
                let h = mix(self.seed ^ mix(env.wrapping_mul(64).wrapping_add(dof as u64)));
                let phase = (h >> 11) as f64 / (1u64 << 53) as f64 * std::f64::consts::TAU;
                // Periods of 60 to 250 steps: a quarter to one second at 240 Hz.
                let period = 60.0 + (h % 191) as f64;
                let angle = phase + std::f64::consts::TAU * step as f64 / period;
                *value = (wave.centre + wave.amplitude * angle.sin()) as f32;
            }
        }
    }
}

/// SplitMix64's finaliser: a cheap, well-mixed hash of one word.
fn mix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn position_targets_stay_within_limits() {
        let limits = [Some((-120.0, 0.0)), None];
        let plan = ActionPlan::new(ActionKind::Position, Some(90.0), &limits, &[], 7);
        let mut out = vec![0.0; 2 * 50];
        for step in 0..300 {
            plan.fill(step, 0, &mut out);
            for pair in out.chunks_exact(2) {
                assert!((-120.0..=0.0).contains(&pair[0]), "{pair:?}");
                assert!(pair[1].abs() <= 90.0, "{pair:?}");
            }
        }
    }

    #[test]
    fn actions_depend_on_global_env_index_only() {
        let plan = ActionPlan::new(ActionKind::Torque, Some(1e-3), &[None, None], &[], 3);
        let mut whole = vec![0.0; 2 * 8];
        plan.fill(5, 0, &mut whole);
        let mut tail = vec![0.0; 2 * 4];
        plan.fill(5, 4, &mut tail);
        assert_eq!(whole[8..], tail[..]);
        assert!(whole.iter().all(|v| v.abs() <= 1e-3));
        assert_ne!(whole[0], whole[2], "envs differ");
    }

    #[test]
    fn torque_actions_without_an_amplitude_swing_within_each_dofs_bound() {
        let plan = ActionPlan::new(ActionKind::Torque, None, &[None, None], &[2.0, 0.01], 3);
        let mut out = vec![0.0; 2 * 16];
        let mut largest = [0.0f32; 2];
        for step in 0..300 {
            plan.fill(step, 0, &mut out);
            for pair in out.chunks_exact(2) {
                largest[0] = largest[0].max(pair[0].abs());
                largest[1] = largest[1].max(pair[1].abs());
            }
        }
        assert!(largest[0] <= 2.0 && largest[0] > 1.9, "{largest:?}");
        assert!(largest[1] <= 0.01 && largest[1] > 0.0095, "{largest:?}");
        // Without bounds (a server before them): the default amplitude.
        let plan = ActionPlan::new(ActionKind::Torque, None, &[None], &[], 3);
        let mut one = vec![0.0; 16];
        plan.fill(7, 0, &mut one);
        assert!(one.iter().all(|v| v.abs() <= DEFAULT_TORQUE_AMPLITUDE));
    }
}
