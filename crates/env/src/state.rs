//! Saved env states (docs/design.md §6.4): everything that determines an env's future, as
//! opaque, versioned, checksummed bytes that rebuild the env on any server.
//!
//! A state holds the document text and the options the env was built from, the episode
//! (seed, the seeded generator's state, step count, the last finite observation, the
//! randomisation draws, the task's target) and the world's [`DynamicState`] (joint
//! coordinates and velocities, body motion, the held command) in Rapier's own `f32`s.
//!
//! **Exactness.** Loading rebuilds the env's Rapier sets from the document, as a reset
//! does, and puts the dynamic state back. What a step caches beyond that state (contact
//! pairs and their solver warm-start impulses) is not carried: so that an env and the
//! envs loaded from its state continue bitwise alike, [`RobotEnv::save`] *re-seats* the
//! saved env from the state it returns, exactly as a load does. The one effect a save has
//! on an env's own trajectory is therefore that contacts touching at that moment are
//! solved afresh at the next step, without the previous step's impulses as a first guess
//! (a hand resting against a post sits up to 0.009° deeper for a few dozen steps). An env
//! without contacts continues bit for bit as if it had not been saved (`tests/state.rs`).
//!
//! **Never trusted.** A state is decoded from bytes anyone can forge: the header and a
//! CRC-32 catch accidents (truncation, corruption, another format's bytes), and every
//! field is checked against the env the document builds (counts, finite values within
//! bounds, limits, unit quaternions, draws within their ranges, a target the task could
//! have drawn) before anything is changed. Errors name the field.
//!
//! **Layout**: `"GFST"`, the format version (`u32`, little-endian), the CRC-32 of the rest,
//! then the fields in `postcard`'s encoding. Any change to a serialised type (here, in
//! [`EnvConfig`] and its parts, or in `gymfleet_physics::DynamicState`) changes the format:
//! bump [`STATE_VERSION`].

use gymfleet_physics::{Draws, DynamicState};
use rand::rngs::Xoshiro256PlusPlus;
use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::config::EnvConfig;
use crate::env::RobotEnv;
use crate::error::{EnvError, Result};

/// The saved-state format this build writes and reads.
pub const STATE_VERSION: u32 = 6;
/// The first bytes of every saved state.
const MAGIC: [u8; 4] = *b"GFST";
/// Magic, version, checksum.
const HEADER_LEN: usize = 12;

/// What a state holds (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Saved {
    document: String,
    config: EnvConfig,
    seed: u64,
    rng: Xoshiro256PlusPlus,
    elapsed: u32,
    last_obs: Vec<f32>,
    draws: Option<Draws>,
    task_target: [f64; 3],
    world: DynamicState,
}

/// A decoded env state: from [`RobotEnv::save`] or [`SavedState::decode`]; its bytes from
/// [`SavedState::encode`]. Decoding checks the format only; the content is checked against
/// an env by [`RobotEnv::load`] and [`RobotEnv::from_state`].
#[derive(Debug, Clone, PartialEq)]
pub struct SavedState(Saved);

fn format_error(reason: String) -> EnvError {
    EnvError::StateFormat { reason }
}

fn bad(path: impl Into<String>, reason: impl Into<String>) -> EnvError {
    EnvError::BadState {
        path: path.into(),
        reason: reason.into(),
    }
}

impl SavedState {
    /// The state as bytes: header, checksum, fields.
    pub fn encode(&self) -> Vec<u8> {
        let payload = postcard::to_allocvec(&self.0).expect("a state always serialises");
        let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&STATE_VERSION.to_le_bytes());
        out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
        out.extend_from_slice(&payload);
        out
    }

    /// Reads a state's bytes: the header (magic, this format's version), the checksum, and
    /// the fields' encoding, with nothing left over. Allocates no more than the bytes hold.
    pub fn decode(bytes: &[u8]) -> Result<SavedState> {
        if bytes.len() < HEADER_LEN {
            return Err(format_error(format!(
                "{} bytes is shorter than a state's {HEADER_LEN}-byte header (empty or truncated)",
                bytes.len()
            )));
        }
        if bytes[..4] != MAGIC {
            return Err(format_error(format!(
                "not a gymfleet env state: it starts with {:02x?}, not \"GFST\"",
                &bytes[..4]
            )));
        }
        let version = u32::from_le_bytes(bytes[4..8].try_into().expect("4 bytes"));
        if version != STATE_VERSION {
            return Err(format_error(format!(
                "the state has format version {version}; this server reads version {STATE_VERSION} only"
            )));
        }
        let stored = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
        let payload = &bytes[HEADER_LEN..];
        let computed = crc32fast::hash(payload);
        if stored != computed {
            return Err(format_error(format!(
                "checksum mismatch (stored {stored:08x}, computed {computed:08x}): the state is corrupted or truncated"
            )));
        }
        let (saved, rest) = postcard::take_from_bytes::<Saved>(payload)
            .map_err(|e| format_error(format!("malformed state fields: {e}")))?;
        if !rest.is_empty() {
            return Err(format_error(format!(
                "{} unexpected bytes after the state's fields",
                rest.len()
            )));
        }
        Ok(SavedState(saved))
    }

    /// The document text the state's env was built from.
    pub fn document(&self) -> &str {
        &self.0.document
    }

    /// The options the state's env was built with (its `seed` is the creation seed; the
    /// state's own episode seed is [`SavedState::seed`]).
    pub fn config(&self) -> &EnvConfig {
        &self.0.config
    }

    /// The episode seed at saving.
    pub fn seed(&self) -> u64 {
        self.0.seed
    }

    /// Steps taken in the saved episode.
    pub fn elapsed_steps(&self) -> u32 {
        self.0.elapsed
    }
}

/// The first option (by name) in which two configurations differ, the creation seed aside.
fn config_difference(a: &EnvConfig, b: &EnvConfig) -> Option<&'static str> {
    let EnvConfig {
        end_effector_ids,
        dt,
        substeps,
        max_steps,
        seed: _,
        pd_gains,
        reset_noise,
        task,
        randomize,
        units,
    } = a;
    [
        ("end_effector_ids", *end_effector_ids == b.end_effector_ids),
        ("dt", dt.to_bits() == b.dt.to_bits()),
        ("substeps", *substeps == b.substeps),
        ("max_steps", *max_steps == b.max_steps),
        ("pd_gains", *pd_gains == b.pd_gains),
        (
            "reset_noise",
            reset_noise.to_bits() == b.reset_noise.to_bits(),
        ),
        ("task", *task == b.task),
        ("randomize", *randomize == b.randomize),
        ("units", *units == b.units),
    ]
    .into_iter()
    .find_map(|(name, same)| (!same).then_some(name))
}

/// Checks that every factor lies in its range (or is 1 where the quantity is not randomised).
fn check_factors(path: &str, factors: &[f64], count: usize, range: Option<[f64; 2]>) -> Result<()> {
    if factors.len() != count {
        return Err(bad(
            path,
            format!("expected {count} factors, got {}", factors.len()),
        ));
    }
    let [lo, hi] = range.unwrap_or([1.0, 1.0]);
    match factors.iter().position(|f| !(*f >= lo && *f <= hi)) {
        Some(k) => Err(bad(
            format!("{path}[{k}]"),
            format!("expected a factor in [{lo}, {hi}], got {}", factors[k]),
        )),
        None => Ok(()),
    }
}

impl RobotEnv {
    /// Saves the env's state, and re-seats the env from it (see the module documentation),
    /// so that the env and every env loaded from the state continue bitwise alike.
    ///
    /// A diverged env has no state worth saving: [`EnvError::NeedsReset`].
    pub fn save(&mut self) -> Result<SavedState> {
        if self.diverged {
            return Err(EnvError::NeedsReset);
        }
        let saved = Saved {
            document: self.origin.document.to_string(),
            config: self.origin.config.clone(),
            seed: self.seed,
            rng: self.rng.clone(),
            elapsed: self.elapsed,
            last_obs: self.last_obs.clone(),
            draws: self.draws.clone(),
            task_target: self.task.as_ref().map_or([0.0; 3], |t| t.target()),
            world: self.world.dynamic_state(),
        };
        self.check(&saved)?;
        self.apply(&saved);
        Ok(SavedState(saved))
    }

    /// Loads a state saved from an env of the same document and options (the creation seed
    /// may differ): checks every field, then puts it in place. A state that does not fit
    /// changes nothing.
    pub fn load(&mut self, state: &SavedState) -> Result<()> {
        let saved = &state.0;
        if *saved.document != *self.origin.document {
            return Err(bad(
                "document",
                "the state was saved from an env of another document",
            ));
        }
        if let Some(field) = config_difference(&saved.config, &self.origin.config) {
            return Err(bad(
                format!("config.{field}"),
                format!("the state was saved from an env with another {field}"),
            ));
        }
        self.check(saved)?;
        self.apply(saved);
        Ok(())
    }

    /// Builds the env a state was saved from, in that state.
    pub fn from_state(state: &SavedState) -> Result<RobotEnv> {
        let assembly = gymfleet_assembly::parse(state.document())?;
        let mut env = RobotEnv::new(&assembly, state.config().clone())?;
        env.load(state)?;
        Ok(env)
    }

    /// Checks a state's episode and world against this env.
    fn check(&self, saved: &Saved) -> Result<()> {
        let dim = self.spec.observation_dim;
        if saved.last_obs.len() != dim {
            return Err(bad(
                "last_obs",
                format!(
                    "expected {dim} values (the observation), got {}",
                    saved.last_obs.len()
                ),
            ));
        }
        if let Some(k) = saved.last_obs.iter().position(|v| !v.is_finite()) {
            return Err(bad(
                format!("last_obs[{k}]"),
                format!("expected a finite value, got {}", saved.last_obs[k]),
            ));
        }
        // The all-zero state is Xoshiro's one fixed point: it draws zeros for ever.
        let mut probe = saved.rng.clone();
        if (0..4).all(|_| probe.next_u64() == 0) {
            return Err(bad("rng", "the generator's state is all zeros (unusable)"));
        }
        match (&self.randomize, &saved.draws) {
            (None, None) => {}
            (Some(r), Some(d)) => {
                let (bodies, joints) = (self.world.num_bodies(), self.world.num_joints());
                check_factors("draws.mass", &d.mass, bodies, r.mass_scale)?;
                check_factors("draws.friction", &d.friction, bodies, r.friction_scale)?;
                check_factors("draws.damping", &d.damping, joints, r.damping_scale)?;
                check_factors("draws.gain", &d.gain, joints, r.gain_scale)?;
            }
            (None, Some(_)) => return Err(bad("draws", "this env is not randomised")),
            (Some(_), None) => return Err(bad("draws", "this env is randomised: draws needed")),
        }
        match &self.task {
            Some(task) => task.clone().restore_target(saved.task_target)?,
            None if saved.task_target == [0.0; 3] => {}
            None => {
                return Err(bad(
                    "task_target",
                    "this env has no task: expected [0, 0, 0]",
                ))
            }
        }
        self.world.check_dynamic_state(&saved.world)?;
        Ok(())
    }

    /// Puts a checked state in place: the world as a reset leaves it, the draws, the
    /// dynamic state, then the episode.
    fn apply(&mut self, saved: &Saved) {
        self.world.reset();
        if let Some(draws) = &saved.draws {
            self.world.apply_draws(draws);
        }
        self.world.restore_dynamic_state(&saved.world);
        if let Some(task) = &mut self.task {
            task.restore_target(saved.task_target)
                .expect("the target was checked");
        }
        self.seed = saved.seed;
        self.rng = saved.rng.clone();
        self.elapsed = saved.elapsed;
        self.diverged = false;
        self.last_obs.copy_from_slice(&saved.last_obs);
        self.draws = saved.draws.clone();
        let mut obs = vec![0.0; self.spec.observation_dim];
        self.observe_into(&mut obs);
        self.start_task(&obs);
    }
}

#[cfg(test)]
mod tests {
    //! Forged states: each field is checked, with an error naming it, and nothing changes.
    use super::*;
    use crate::config::Randomization;
    use crate::task::{ReachTarget, TaskKind, TaskSpec};
    use crate::ActionType;

    const ARM2: &str = include_str!("../../../models/arm2.json");

    fn env() -> RobotEnv {
        let config = EnvConfig {
            task: Some(TaskSpec {
                kind: TaskKind::Reach {
                    end_effector: "forearm".into(),
                    point: None,
                    target: ReachTarget::Box {
                        min: [0.0, 0.0, 0.0],
                        max: [10.0, 10.0, 10.0],
                    },
                    success_radius: 0.0,
                    terminate_on_success: false,
                },
                action_cost: 0.0,
            }),
            randomize: Some(Randomization {
                mass_scale: Some([0.5, 2.0]),
                ..Randomization::default()
            }),
            ..EnvConfig::with_end_effectors(["forearm"])
        };
        let mut env = RobotEnv::from_json(ARM2, config).expect("arm2 builds");
        for k in 0..20 {
            env.step(ActionType::Torque, &[0.01 * (k as f32).sin(), -0.01])
                .expect("valid");
        }
        env
    }

    /// Forges `env`'s state with `edit`, re-encodes it (a valid checksum: a deliberate
    /// forgery, not an accident) and returns the load error's message, checking that the
    /// env it was loaded into did not change.
    fn forged(edit: impl FnOnce(&mut Saved)) -> String {
        forged_in(env, edit)
    }

    /// [`forged`], for envs that `make` builds.
    fn forged_in(make: fn() -> RobotEnv, edit: impl FnOnce(&mut Saved)) -> String {
        let env = make;
        let mut source = env();
        let SavedState(mut saved) = source.save().expect("saves");
        edit(&mut saved);
        let bytes = SavedState(saved).encode();
        let state = SavedState::decode(&bytes).expect("a forgery decodes");
        let mut target = env();
        let before = target.observe().to_flat();
        let message = target
            .load(&state)
            .expect_err("a forgery is refused")
            .to_string();
        assert_eq!(
            target.observe().to_flat(),
            before,
            "{message}: the env changed"
        );
        assert!(
            RobotEnv::from_state(&state).is_err(),
            "{message}: from_state accepted it"
        );
        message
    }

    #[test]
    fn every_forged_field_is_refused_by_name() {
        type Edit = Box<dyn FnOnce(&mut Saved)>;
        let cases: Vec<(Edit, &str)> = vec![
            (
                Box::new(|s| s.world.velocities[1] = f32::NAN),
                "state.world.velocities[1]: expected a finite value within ±1e9, got NaN",
            ),
            (
                Box::new(|s| s.world.velocities.push(0.0)),
                "state.world.velocities: expected 2 values (one per DOF), got 3",
            ),
            (
                Box::new(|s| s.world.joints[1].coords[3] = 3.0),
                "state.world.joints[1].coords[3]: 3 rad is outside joint \"forearm\"'s limits [-120, 0] deg",
            ),
            (
                Box::new(|s| s.world.joints[0].coords[4] = 0.5),
                "state.world.joints[0].coords[4]: axis 4 of this joint is locked: expected 0, got 0.5",
            ),
            (
                Box::new(|s| s.world.joints[0].rotation = Some([0.0, 0.0, 0.0, 1.0])),
                "state.world.joints[0].rotation: only a ball joint's state has a rotation",
            ),
            (
                Box::new(|s| s.world.joints.pop().map(drop).unwrap_or(())),
                "state.world.joints: expected 2 joints (those with a DOF), got 1",
            ),
            (
                Box::new(|s| s.world.bodies[1].rotation = [0.0, 0.0, 0.0, 2.0]),
                "state.world.bodies[1].rotation[3]: expected a finite value within ±1.0001e0, got 2",
            ),
            (
                Box::new(|s| s.world.bodies[2].rotation = [0.0, 0.0, 0.5, 0.5]),
                "state.world.bodies[2].rotation: expected a unit quaternion, got one of norm 0.70710677",
            ),
            (
                Box::new(|s| s.world.command = vec![f32::INFINITY, 0.0]),
                "state.world.command[0]: expected a finite value within ±3.4028235e38, got inf",
            ),
            (
                Box::new(|s| s.last_obs.truncate(3)),
                "state.last_obs: expected 14 values (the observation), got 3",
            ),
            (
                Box::new(|s| s.draws.as_mut().expect("randomised").mass[0] = 3.0),
                "state.draws.mass[0]: expected a factor in [0.5, 2], got 3",
            ),
            (
                Box::new(|s| s.draws.as_mut().expect("randomised").friction[0] = 1.5),
                "state.draws.friction[0]: expected a factor in [1, 1], got 1.5",
            ),
            (
                Box::new(|s| s.draws = None),
                "state.draws: this env is randomised: draws needed",
            ),
            (
                Box::new(|s| s.task_target = [5.0, 50.0, 5.0]),
                "state.task_target[1]: expected a value this task can draw, in [0, 10], got 50",
            ),
            (
                Box::new(|s| {
                    s.rng = postcard::from_bytes(&postcard::to_allocvec(&[0u64; 4]).expect("encodes"))
                        .expect("a generator decodes from four words")
                }),
                "state.rng: the generator's state is all zeros (unusable)",
            ),
        ];
        for (edit, expected) in cases {
            assert_eq!(forged(edit), expected);
        }
    }

    /// A floating slab with a hinged arm: one free root.
    fn floating() -> RobotEnv {
        let document = r#"{"floating_base": true,
            "parts": [{"name": "Slab", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 2}}},
                      {"name": "Arm", "primitive": {"type": "cube", "size": {"x": 2, "y": 2, "z": 20}}}],
            "assembly": {"instances": [{"part": "Slab", "name": "slab"},
                                       {"part": "Arm", "name": "arm", "position": {"x": 4, "y": 4, "z": 2}}],
                         "joints": [{"type": "revolute", "parent": "slab", "child": "arm",
                                     "anchor": {"x": 5, "y": 5, "z": 2}, "axis": {"x": 1, "y": 0, "z": 0}}]}}"#;
        RobotEnv::from_json(document, EnvConfig::default()).expect("valid")
    }

    #[test]
    fn a_forged_free_root_is_refused_by_name() {
        assert_eq!(
            forged(|s| s.world.roots.push([0.0; 6])),
            "state.world.roots: expected 0 free roots (trees with a floating base), got 1"
        );
        assert_eq!(
            forged_in(floating, |s| s.world.roots[0][4] = f32::NAN),
            "state.world.roots[0][4]: expected a finite value within ±1e9, got NaN"
        );
    }

    #[test]
    fn a_forged_document_goes_through_the_documents_own_checks() {
        let mut source = env();
        let SavedState(mut saved) = source.save().expect("saves");
        saved.document = "{\"parts\": []}".into();
        let state = SavedState::decode(&SavedState(saved).encode()).expect("decodes");
        match RobotEnv::from_state(&state) {
            Err(EnvError::Document(_)) => {}
            Err(other) => panic!("expected a document error, got {other}"),
            Ok(_) => panic!("a forged document was accepted"),
        }
    }
}
