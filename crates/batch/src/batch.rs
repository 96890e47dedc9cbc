//! [`EnvBatch`]: `n_envs` copies of one environment, stepped together on a [`StepPool`].

use std::collections::BTreeMap;
use std::fmt;
use std::num::NonZeroUsize;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use gymfleet_env::{ActionType, EnvSpec, RobotEnv, SavedState, Termination};

use crate::chunk::{Chunk, ChunkOp};
use crate::error::{BatchError, Result};
use crate::pool::StepPool;

/// What happens to an env whose episode ends (`terminated || truncated`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Autoreset {
    /// Nothing: the env keeps stepping. An env whose physics diverged keeps reporting
    /// `terminated` (reason `physics_diverged`) with its last finite observation, and
    /// ignores its actions, until the batch is reset; the rest of the batch steps on.
    #[default]
    Disabled,
    /// The env is reset within the step that ended it. Its final observation is
    /// returned in [`BatchStepOutput::final_observations`]; `observations` holds the
    /// first observation of the new episode.
    SameStep,
    /// Gymnasium's default: the env is reset on the *next* step, whose action it
    /// ignores; that step returns the reset observation, reward 0 and no flags.
    NextStep,
}

/// The result of one [`EnvBatch::step`]. A caller that keeps it between steps reuses
/// its buffers; the server does not: its reply takes them (moved into the protobuf
/// message), and the next step allocates each at its exact size
/// (`BatchStepOutput::clear_for`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BatchStepOutput {
    /// `n_envs × observation_dim` floats, row-major per env.
    pub observations: Vec<f32>,
    /// One per env.
    pub rewards: Vec<f32>,
    /// A terms task's values: `n_envs × term_names.len()`, row-major per env (see
    /// [`gymfleet_env::RobotEnv::term_values`]).
    pub terms: Vec<f32>,
    /// One per env.
    pub terminated: Vec<bool>,
    /// One per env.
    pub truncated: Vec<bool>,
    /// [`Autoreset::SameStep`]: the envs that finished this step and were reset, in
    /// ascending order.
    pub final_env_indices: Vec<u32>,
    /// Their final observations, `observation_dim` floats each, in the same order.
    pub final_observations: Vec<f32>,
    /// Env index → why it terminated, for envs terminated for a reason (typed up to the
    /// edges: [`gymfleet_env::Termination::as_str`] is the wire form).
    pub termination_reasons: BTreeMap<u32, Termination>,
}

impl BatchStepOutput {
    /// Empties every field and makes room for a whole step of `n_envs` envs, so an
    /// empty output (one whose buffers a caller took) is filled with one allocation per
    /// field rather than grown in doublings; an output reused across steps allocates
    /// nothing.
    pub(crate) fn clear_for(&mut self, n_envs: usize, observation_dim: usize, n_terms: usize) {
        fn empty_with_room<T>(v: &mut Vec<T>, room: usize) {
            v.clear();
            v.reserve(room);
        }
        empty_with_room(&mut self.observations, n_envs * observation_dim);
        empty_with_room(&mut self.rewards, n_envs);
        empty_with_room(&mut self.terms, n_envs * n_terms);
        empty_with_room(&mut self.terminated, n_envs);
        empty_with_room(&mut self.truncated, n_envs);
        self.final_env_indices.clear();
        self.final_observations.clear();
        self.termination_reasons.clear();
    }
}

/// Most envs per chunk under the default rule.
pub const MAX_DEFAULT_CHUNK_SIZE: usize = 16;

/// Envs a pool thread steps in turn above which a step prefetches each env's state while
/// the env before it steps (`RobotEnv::prefetch`; BENCHMARKS S6: one thread kept the
/// HalfCheetah's step cost up to 128 envs, and two share the last-level cache).
pub(crate) const PREFETCH_ABOVE_ENVS_PER_THREAD: usize = 64;

/// The default chunk size for `n_envs` envs on a machine with `threads` cores:
/// `ceil(n_envs / (4 × threads))`, clamped to `1..=MAX_DEFAULT_CHUNK_SIZE`.
///
/// Four chunks per thread let the threads even out. The cap keeps one chunk short
/// (about 0.9 ms for 16 seed arms at ~55 µs per env step), because a small batch
/// queued behind a big one waits for about one chunk per thread. Scheduling a chunk
/// costs a lock or two and no allocation; measured on 256 arms, chunks of 1, 4, 16
/// and 64 envs step equally fast within noise, so the cap costs no throughput.
pub fn default_chunk_size(n_envs: usize, threads: usize) -> usize {
    n_envs
        .div_ceil(4 * threads.max(1))
        .clamp(1, MAX_DEFAULT_CHUNK_SIZE)
}

/// `n_envs` independent copies of one environment, stepped in parallel.
///
/// The envs are split at creation into fixed chunks of consecutive envs, the unit of
/// scheduling on the [`StepPool`]. Each env evolves independently of the others and
/// of the chunking, so results are bitwise identical whatever the pool's thread count
/// or the chunk size.
pub struct EnvBatch {
    spec: EnvSpec,
    n_envs: usize,
    chunk_size: usize,
    autoreset: Autoreset,
    pub(crate) chunks: Arc<[Mutex<Chunk>]>,
}

impl EnvBatch {
    /// Clones `template` `n_envs` times (no re-parse) and resets every copy. The chunk
    /// size follows [`default_chunk_size`] for this machine's core count.
    pub fn new(template: &RobotEnv, n_envs: usize, autoreset: Autoreset) -> Result<Self> {
        Self::with_chunk_size(template, n_envs, autoreset, 0)
    }

    /// [`EnvBatch::new`] with the chunk size chosen for `pool`'s thread count rather
    /// than the machine's core count.
    pub fn for_pool(
        template: &RobotEnv,
        n_envs: usize,
        autoreset: Autoreset,
        pool: &StepPool,
    ) -> Result<Self> {
        let chunk_size = default_chunk_size(n_envs, pool.threads());
        Self::with_chunk_size(template, n_envs, autoreset, chunk_size)
    }

    /// [`EnvBatch::new`] with `chunk_size` envs per chunk (the last may be shorter);
    /// 0 means the default rule.
    pub fn with_chunk_size(
        template: &RobotEnv,
        n_envs: usize,
        autoreset: Autoreset,
        chunk_size: usize,
    ) -> Result<Self> {
        Self::build(template, n_envs, autoreset, chunk_size, true)
    }

    /// `n_envs` exact copies of `template` in its current state (not reset: a fork of a
    /// loaded state), with the chunk size of [`EnvBatch::for_pool`]. Given the same
    /// actions, every copy continues bitwise as `template` would.
    pub fn copies_of(
        template: &RobotEnv,
        n_envs: usize,
        autoreset: Autoreset,
        pool: &StepPool,
    ) -> Result<Self> {
        let chunk_size = default_chunk_size(n_envs, pool.threads());
        Self::build(template, n_envs, autoreset, chunk_size, false)
    }

    fn build(
        template: &RobotEnv,
        n_envs: usize,
        autoreset: Autoreset,
        chunk_size: usize,
        reset: bool,
    ) -> Result<Self> {
        if n_envs == 0 {
            return Err(BatchError::NoEnvs);
        }
        if u32::try_from(n_envs).is_err() {
            return Err(BatchError::TooManyEnvs {
                n_envs,
                max: u64::from(u32::MAX),
            });
        }
        let chunk_size = if chunk_size == 0 {
            let cores = std::thread::available_parallelism().map_or(1, NonZeroUsize::get);
            default_chunk_size(n_envs, cores)
        } else {
            chunk_size.min(n_envs)
        };
        let mut scratch = vec![0.0; template.spec().observation_dim];
        let chunks: Vec<Mutex<Chunk>> = (0..n_envs)
            .step_by(chunk_size)
            .map(|first| {
                let envs = (first..n_envs.min(first + chunk_size))
                    .map(|_| {
                        let mut env = template.clone();
                        if reset {
                            env.reset_into(None, &mut scratch);
                        }
                        env
                    })
                    .collect();
                Mutex::new(Chunk::new(first, envs))
            })
            .collect();
        Ok(EnvBatch {
            spec: template.spec().clone(),
            n_envs,
            chunk_size,
            autoreset,
            chunks: chunks.into(),
        })
    }

    /// The number of envs.
    pub fn n_envs(&self) -> usize {
        self.n_envs
    }

    /// The spec every env shares.
    pub fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    /// What happens to finished envs.
    pub fn autoreset(&self) -> Autoreset {
        self.autoreset
    }

    /// Envs per chunk (the last chunk may hold fewer).
    pub fn chunk_size(&self) -> usize {
        self.chunk_size
    }

    /// Resets every env: env `i` gets seed `seed + seed_offset + i` (wrapping) when
    /// `seed` is given, else keeps its own. Writes `n_envs × observation_dim` floats into
    /// `out` (cleared and resized). Pending [`Autoreset::NextStep`] resets and
    /// diverged envs are cleared.
    ///
    /// A [`BatchError::Panicked`] error means resetting an env panicked on the pool (a bug
    /// in the physics); `out` is then left empty.
    pub fn reset(
        &mut self,
        pool: &StepPool,
        seed: Option<u64>,
        seed_offset: u64,
        out: &mut Vec<f32>,
    ) -> Result<()> {
        self.reset_envs(pool, seed, seed_offset, None, out)
    }

    /// [`EnvBatch::reset`] of the envs in `env_indices` only (ascending, distinct, below
    /// `n_envs`; `None`: every env), each reseeded as `reset` would. `out` still gets every
    /// env's observation: the others' current ones, and they keep their state (a pending
    /// [`Autoreset::NextStep`] reset included). A bad list resets nothing.
    pub fn reset_envs(
        &mut self,
        pool: &StepPool,
        seed: Option<u64>,
        seed_offset: u64,
        env_indices: Option<&[u32]>,
        out: &mut Vec<f32>,
    ) -> Result<()> {
        self.reset_to(pool, seed, seed_offset, env_indices, None, out)
    }

    /// [`EnvBatch::reset_envs`] from the document's keyframe named `keyframe` (`None`:
    /// its `initial_keyframe`, if any), the reset's noise on top. An unknown name
    /// ([`BatchError::Keyframe`]) or a bad list resets nothing.
    pub fn reset_to(
        &mut self,
        pool: &StepPool,
        seed: Option<u64>,
        seed_offset: u64,
        env_indices: Option<&[u32]>,
        keyframe: Option<&str>,
        out: &mut Vec<f32>,
    ) -> Result<()> {
        let keyframe = match keyframe {
            Some(name) => Some(
                lock(&self.chunks[0])
                    .env(0)
                    .keyframe_index(name)
                    .map_err(BatchError::Keyframe)?,
            ),
            None => None,
        };
        if let Some(indices) = env_indices {
            self.check_indices(indices)?;
            for chunk in self.chunks.iter() {
                let mut chunk = lock(chunk);
                let first = chunk.first_env;
                let len = chunk.len();
                chunk.reset_marks.fill(false);
                for &i in indices {
                    let i = i as usize;
                    if (first..first + len).contains(&i) {
                        chunk.reset_marks[i - first] = true;
                    }
                }
            }
        }
        let op = ChunkOp::Reset {
            seed,
            offset: seed_offset,
            marked: env_indices.is_some(),
            keyframe,
        };
        out.clear();
        self.run(pool, op)?;
        for chunk in self.chunks.iter() {
            out.extend_from_slice(&lock(chunk).observations);
        }
        Ok(())
    }

    /// Validates all actions (`n_envs × action_dim` values, row-major per env, all
    /// finite), then steps every env in parallel on `pool` and writes the results into
    /// `out`, reusing its buffers. Invalid actions step nothing.
    ///
    /// Blocks until done. Safe from any thread, a pool thread included: the caller runs
    /// chunks itself while it waits, so this cannot deadlock even if every pool thread
    /// is such a caller.
    ///
    /// An [`BatchError::Env`] error names the lowest failing env; every env was
    /// stepped and `out` is filled regardless. A [`BatchError::Panicked`] error means a step
    /// panicked: reset the batch before using it again.
    pub fn step(
        &mut self,
        pool: &StepPool,
        action_type: ActionType,
        actions: &[f32],
        out: &mut BatchStepOutput,
    ) -> Result<()> {
        self.validate(actions)?;
        let action_dim = self.spec.action_dim;
        for chunk in self.chunks.iter() {
            let mut chunk = lock(chunk);
            let start = chunk.first_env * action_dim;
            let end = start + chunk.len() * action_dim;
            chunk.actions.copy_from_slice(&actions[start..end]);
        }
        // Past this many envs a thread, their states stop fitting in the caches between two
        // of their steps, and each chunk prefetches its next env's (BENCHMARKS S6); below
        // it the hints would only cost their own issue (about 1 % at 32 envs a thread).
        let prefetch = self.n_envs > PREFETCH_ABOVE_ENVS_PER_THREAD * pool.threads();
        self.run(
            pool,
            ChunkOp::Step {
                action_type,
                prefetch,
                marked: false,
            },
        )?;

        out.clear_for(
            self.n_envs,
            self.spec.observation_dim,
            self.spec.term_names.len(),
        );
        let mut error = None;
        for chunk in self.chunks.iter() {
            let mut chunk = lock(chunk);
            out.observations.extend_from_slice(&chunk.observations);
            out.rewards.extend_from_slice(&chunk.rewards);
            out.terms.extend_from_slice(&chunk.terms);
            out.terminated.extend_from_slice(&chunk.terminated);
            out.truncated.extend_from_slice(&chunk.truncated);
            out.final_env_indices
                .extend_from_slice(&chunk.final_env_indices);
            out.final_observations
                .extend_from_slice(&chunk.final_observations);
            for (i, termination) in chunk.terminations.iter().enumerate() {
                if let Some(termination) = termination {
                    let env = (chunk.first_env + i) as u32;
                    out.termination_reasons.insert(env, *termination);
                }
            }
            if error.is_none() {
                error = chunk.error.take();
            }
        }
        match error {
            Some((env, source)) => Err(BatchError::Env { env, source }),
            None => Ok(()),
        }
    }

    /// Saves the state of the envs in `env_indices` (ascending, distinct, below `n_envs`;
    /// empty: every env), in that order. Each saved env is re-seated from its state (see
    /// [`RobotEnv::save`]). A diverged env has no state: [`BatchError::Env`] names it.
    pub fn save_states(&mut self, env_indices: &[u32]) -> Result<Vec<SavedState>> {
        let indices = self.indices_or_all(env_indices)?;
        let mut states = Vec::with_capacity(indices.len());
        for i in indices {
            let state = self
                .with_env_mut(i, RobotEnv::save)
                .expect("the index was checked");
            states.push(state.map_err(|source| BatchError::Env { env: i, source })?);
        }
        Ok(states)
    }

    /// Loads `states[k]` into env `env_indices[k]` (ascending, distinct, below `n_envs`;
    /// empty: every env, one state each). Every state must come from an env of this
    /// batch's document and options; all are checked before any is loaded, so a bad one
    /// loads nothing. A loaded env is running (a pending next-step reset is dropped).
    pub fn load_states(&mut self, env_indices: &[u32], states: &[SavedState]) -> Result<()> {
        let indices = self.indices_or_all(env_indices)?;
        if indices.len() != states.len() {
            return Err(BatchError::StateCount {
                indices: indices.len(),
                states: states.len(),
            });
        }
        let mut loaded = Vec::with_capacity(states.len());
        for (&i, state) in indices.iter().zip(states) {
            let mut env = self
                .with_env(i, RobotEnv::clone)
                .expect("the index was checked");
            env.load(state)
                .map_err(|source| BatchError::Env { env: i, source })?;
            loaded.push((i, env));
        }
        for (i, env) in loaded {
            let chunk = &self.chunks[i / self.chunk_size];
            let mut chunk = lock(chunk);
            let first = chunk.first_env;
            chunk.replace(i - first, env);
        }
        Ok(())
    }

    /// `env_indices` checked, or every index when it is empty.
    pub(crate) fn indices_or_all(&self, env_indices: &[u32]) -> Result<Vec<usize>> {
        if env_indices.is_empty() {
            return Ok((0..self.n_envs).collect());
        }
        self.check_indices(env_indices)?;
        Ok(env_indices.iter().map(|&i| i as usize).collect())
    }

    /// `write` of env `index` (`None` past the end), under its chunk's lock.
    pub(crate) fn with_env_mut<T>(
        &self,
        index: usize,
        write: impl FnOnce(&mut RobotEnv) -> T,
    ) -> Option<T> {
        let mut chunk = lock(self.chunks.get(index / self.chunk_size)?);
        let first = chunk.first_env;
        (index - first < chunk.len()).then(|| write(chunk.env_mut(index - first)))
    }

    /// Env `index`'s [`gymfleet_env::Scene`] (`None` past the end).
    pub fn scene(&self, index: usize) -> Option<gymfleet_env::Scene> {
        self.with_env(index, RobotEnv::scene)
    }

    /// `read` of env `index` (`None` past the end), under its chunk's lock.
    pub(crate) fn with_env<T>(&self, index: usize, read: impl FnOnce(&RobotEnv) -> T) -> Option<T> {
        let chunk = self
            .chunks
            .iter()
            .map(lock)
            .find(|chunk| (chunk.first_env..chunk.first_env + chunk.len()).contains(&index))?;
        Some(read(chunk.env(index - chunk.first_env)))
    }

    /// Env `index`'s domain-randomisation factors for its current episode (`None`
    /// without randomisation, or past the end).
    pub fn draws(&self, index: usize) -> Option<gymfleet_env::DrawReport> {
        self.with_env(index, RobotEnv::draws).flatten()
    }

    /// The current observation of every env, without stepping: `n_envs ×
    /// observation_dim` floats written into `out` (cleared and resized).
    pub fn observe(&self, out: &mut Vec<f32>) {
        out.clear();
        out.resize(self.n_envs * self.spec.observation_dim, 0.0);
        let rows_per_chunk = self.chunk_size * self.spec.observation_dim;
        for (chunk, rows) in self.chunks.iter().zip(out.chunks_mut(rows_per_chunk)) {
            lock(chunk).observe_into(rows);
        }
    }

    /// The episode seed of every env, in order.
    pub fn seeds(&self) -> Vec<u64> {
        let mut seeds = Vec::with_capacity(self.n_envs);
        for chunk in self.chunks.iter() {
            seeds.extend(lock(chunk).seeds());
        }
        seeds
    }

    pub(crate) fn check_indices(&self, indices: &[u32]) -> Result<()> {
        let mut previous = None;
        for (position, &i) in indices.iter().enumerate() {
            let reason = match previous {
                _ if i as usize >= self.n_envs => {
                    format!(
                        "env {i} is out of range: the batch has {} envs",
                        self.n_envs
                    )
                }
                Some(p) if i <= p => {
                    format!("expected ascending, distinct indices, got {i} after {p}")
                }
                _ => {
                    previous = Some(i);
                    continue;
                }
            };
            return Err(BatchError::EnvIndices { position, reason });
        }
        Ok(())
    }

    pub(crate) fn validate(&self, actions: &[f32]) -> Result<()> {
        self.validate_rows(actions, None)
    }

    /// Checks one finite action row per env of `envs` (`None`: every env), in that order.
    pub(crate) fn validate_rows(&self, actions: &[f32], envs: Option<&[u32]>) -> Result<()> {
        let action_dim = self.spec.action_dim;
        let n_envs = envs.map_or(self.n_envs, <[u32]>::len);
        let expected = n_envs * action_dim;
        if actions.len() != expected {
            return Err(BatchError::ActionLength {
                expected,
                got: actions.len(),
                n_envs,
                action_dim,
            });
        }
        match actions.iter().position(|v| !v.is_finite()) {
            Some(flat_index) => Err(BatchError::NonFiniteAction {
                env: envs.map_or(flat_index / action_dim, |e| {
                    e[flat_index / action_dim] as usize
                }),
                index: flat_index % action_dim,
                value: actions[flat_index],
                flat_index,
            }),
            None => Ok(()),
        }
    }

    /// Runs `op` on every chunk on the pool.
    pub(crate) fn run(&self, pool: &StepPool, op: ChunkOp) -> Result<()> {
        let chunks = Arc::clone(&self.chunks);
        let autoreset = self.autoreset;
        pool.run_chunked(self.chunks.len(), move |i| {
            lock(&chunks[i]).run(op, autoreset);
        })
        .map_err(|panic| {
            let first = panic.chunk * self.chunk_size;
            BatchError::Panicked {
                first,
                last: (first + self.chunk_size).min(self.n_envs) - 1,
                message: panic.message,
            }
        })
    }
}

impl fmt::Debug for EnvBatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("EnvBatch")
            .field("n_envs", &self.n_envs)
            .field("chunk_size", &self.chunk_size)
            .field("autoreset", &self.autoreset)
            .field("spec", &self.spec)
            .finish_non_exhaustive()
    }
}

/// Locks a chunk. A chunk's lock is only poisoned by a panic inside an env, which the
/// step already reported; its data is still memory-safe to use.
pub(crate) fn lock(chunk: &Mutex<Chunk>) -> MutexGuard<'_, Chunk> {
    chunk.lock().unwrap_or_else(PoisonError::into_inner)
}
