//! [`Chunk`]: a fixed run of consecutive envs of a batch, with their action and output
//! rows, stepped as one unit of scheduling. Autoreset happens here.

use gymfleet_env::{ActionType, EnvError, RobotEnv, StepFlags, Termination};

use crate::Autoreset;

/// What a chunk does when the scheduler runs it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum ChunkOp {
    /// Reset every env (or, with `marked`, those of [`Chunk::reset_marks`]); env `i`
    /// gets `seed + offset + i` when a seed is given.
    Reset {
        seed: Option<u64>,
        offset: u64,
        marked: bool,
        /// The keyframe to start from, by index (`None`: the document's initial one).
        keyframe: Option<usize>,
    },
    /// Step every env (or, with `marked`, those of [`Chunk::step_marks`]) with the chunk's
    /// action rows; with `prefetch`, hint each env's state into the caches while the env
    /// before it steps.
    Step {
        action_type: ActionType,
        prefetch: bool,
        marked: bool,
    },
}

/// Where an env is between steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum EnvState {
    Running,
    /// `Autoreset::NextStep`: the last step finished the episode; reset on the next.
    ResetNext,
    /// `Autoreset::Disabled`: the physics diverged. The env reports `terminated` with
    /// its last finite observation on every step until the batch is reset.
    Diverged {
        truncated: bool,
    },
}

/// Consecutive envs `first_env..first_env + envs.len()` and their rows.
pub(crate) struct Chunk {
    pub(crate) first_env: usize,
    envs: Vec<RobotEnv>,
    states: Vec<EnvState>,
    obs_dim: usize,
    action_dim: usize,
    /// A terms task's values per env.
    terms_dim: usize,
    /// Filled by the caller before a step.
    pub(crate) actions: Vec<f32>,
    /// Filled by the caller before a partial reset: which envs to reset.
    pub(crate) reset_marks: Vec<bool>,
    /// Filled by the caller before a step of some envs: which envs step.
    pub(crate) step_marks: Vec<bool>,
    pub(crate) observations: Vec<f32>,
    pub(crate) rewards: Vec<f32>,
    /// `len × terms_dim`: each env's term values of its step.
    pub(crate) terms: Vec<f32>,
    pub(crate) terminated: Vec<bool>,
    pub(crate) truncated: Vec<bool>,
    pub(crate) terminations: Vec<Option<Termination>>,
    /// `Autoreset::SameStep`: the envs reset in this step, and their final observations.
    pub(crate) final_env_indices: Vec<u32>,
    pub(crate) final_observations: Vec<f32>,
    /// The first env error of the last operation.
    pub(crate) error: Option<(usize, EnvError)>,
}

impl Chunk {
    pub(crate) fn new(first_env: usize, envs: Vec<RobotEnv>) -> Self {
        let n = envs.len();
        let spec = envs[0].spec();
        let (obs_dim, action_dim) = (spec.observation_dim, spec.action_dim);
        let terms_dim = spec.term_names.len();
        Chunk {
            first_env,
            states: vec![EnvState::Running; n],
            envs,
            obs_dim,
            action_dim,
            terms_dim,
            actions: vec![0.0; n * action_dim],
            reset_marks: vec![false; n],
            step_marks: vec![false; n],
            observations: vec![0.0; n * obs_dim],
            rewards: vec![0.0; n],
            terms: vec![0.0; n * terms_dim],
            terminated: vec![false; n],
            truncated: vec![false; n],
            terminations: vec![None; n],
            final_env_indices: Vec::new(),
            final_observations: Vec::new(),
            error: None,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.envs.len()
    }

    pub(crate) fn env(&self, i: usize) -> &RobotEnv {
        &self.envs[i]
    }

    pub(crate) fn env_mut(&mut self, i: usize) -> &mut RobotEnv {
        &mut self.envs[i]
    }

    /// Puts `env` in place of env `i`, running (a pending next-step reset or a divergence
    /// mark is dropped: the env is in a live state).
    pub(crate) fn replace(&mut self, i: usize, env: RobotEnv) {
        self.envs[i] = env;
        self.states[i] = EnvState::Running;
    }

    pub(crate) fn run(&mut self, op: ChunkOp, autoreset: Autoreset) {
        self.error = None;
        self.final_env_indices.clear();
        self.final_observations.clear();
        self.rewards.fill(0.0);
        self.terms.fill(0.0);
        self.terminated.fill(false);
        self.truncated.fill(false);
        self.terminations.fill(None);
        match op {
            ChunkOp::Reset {
                seed,
                offset,
                marked,
                keyframe,
            } => self.reset(seed, offset, marked, keyframe),
            ChunkOp::Step {
                action_type,
                prefetch,
                marked,
            } => {
                for i in 0..self.envs.len() {
                    if marked && !self.step_marks[i] {
                        continue;
                    }
                    // The next env's state is fetched while this one steps (`prefetch.rs`
                    // in gymfleet-physics): with many envs per core it is out of cache.
                    if let Some(next) = self.envs.get(i + 1).filter(|_| prefetch) {
                        next.prefetch();
                    }
                    self.step_env(i, action_type, autoreset);
                }
            }
        }
    }

    /// Resets every env, or only the marked ones (the others' rows get their current
    /// observation, and they keep their state, a pending next-step reset included).
    fn reset(&mut self, seed: Option<u64>, offset: u64, marked: bool, keyframe: Option<usize>) {
        let rows = self.observations.chunks_exact_mut(self.obs_dim);
        for (i, (env, row)) in self.envs.iter_mut().zip(rows).enumerate() {
            if marked && !self.reset_marks[i] {
                env.observe_into(row);
                continue;
            }
            let index = (self.first_env + i) as u64;
            env.reset_keyed_into(
                seed.map(|s| s.wrapping_add(offset).wrapping_add(index)),
                keyframe,
                row,
            );
            self.states[i] = EnvState::Running;
        }
    }

    fn step_env(&mut self, i: usize, action_type: ActionType, autoreset: Autoreset) {
        let env = &mut self.envs[i];
        let row = &mut self.observations[i * self.obs_dim..(i + 1) * self.obs_dim];
        let flags = match self.states[i] {
            EnvState::ResetNext => {
                env.reset_into(None, row);
                self.states[i] = EnvState::Running;
                StepFlags::default()
            }
            EnvState::Diverged { truncated } => {
                env.observe_into(row);
                StepFlags {
                    reward: 0.0,
                    terminated: true,
                    truncated,
                    termination: Some(Termination::PhysicsDiverged),
                }
            }
            EnvState::Running => {
                let action = &self.actions[i * self.action_dim..(i + 1) * self.action_dim];
                match env.step_into(action_type, action, row) {
                    Ok(flags) => flags,
                    Err(source) => {
                        // Unreachable with validated actions and tracked divergence;
                        // report it and leave the env's current observation in its row.
                        env.observe_into(row);
                        if self.error.is_none() {
                            self.error = Some((self.first_env + i, source));
                        }
                        return;
                    }
                }
            }
        };
        // The step's term values, before an autoreset zeroes them.
        let k = self.terms_dim;
        self.terms[i * k..(i + 1) * k].copy_from_slice(env.term_values());
        if self.states[i] == EnvState::Running && flags.done() {
            match autoreset {
                Autoreset::Disabled => {
                    if flags.termination == Some(Termination::PhysicsDiverged) {
                        self.states[i] = EnvState::Diverged {
                            truncated: flags.truncated,
                        };
                    }
                }
                Autoreset::SameStep => {
                    let index = self.first_env + i;
                    self.final_env_indices.push(index as u32);
                    self.final_observations.extend_from_slice(row);
                    env.reset_into(None, row);
                }
                Autoreset::NextStep => self.states[i] = EnvState::ResetNext,
            }
        }
        self.rewards[i] = flags.reward;
        self.terminated[i] = flags.terminated;
        self.truncated[i] = flags.truncated;
        self.terminations[i] = flags.termination;
    }

    pub(crate) fn seeds(&self) -> impl Iterator<Item = u64> + '_ {
        self.envs.iter().map(RobotEnv::seed)
    }

    /// Writes the current observation of every env into `out` (`len × obs_dim`).
    pub(crate) fn observe_into(&self, out: &mut [f32]) {
        for (env, row) in self.envs.iter().zip(out.chunks_exact_mut(self.obs_dim)) {
            env.observe_into(row);
        }
    }
}
