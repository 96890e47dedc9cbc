//! [`RobotEnv`]: one episode-driven robot.

use gymfleet_assembly::Assembly;
use gymfleet_physics::{
    Draws, RobotWorld, SceneJoint, ScenePart, Units, WorldOptions, BASE_NOISE_LEN, BASE_STATE_LEN,
    FREE_POSE_LEN, FREE_VELOCITY_LEN,
};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

use crate::action::{self, ActionType};
use crate::config::{EnvConfig, EnvSpec, Randomization};
use crate::episode::{StepFlags, StepResult, Termination};
use crate::error::{EnvError, Result};
use crate::observation::{Observation, POSE_LEN};
use crate::setup::EndEffector;
use crate::task::ActiveTask;
use crate::terms::{ActiveSet, Context, Dist};

/// The document and options an env was built from: what its saved states carry. Shared by
/// the copies of a batch.
#[derive(Debug)]
pub(crate) struct Origin {
    pub(crate) document: std::sync::Arc<str>,
    pub(crate) config: EnvConfig,
}

/// A robot environment: reset, step, observe.
///
/// Cloning gives an independent environment in the same state, without re-parsing.
#[derive(Clone)]
pub struct RobotEnv {
    pub(crate) world: RobotWorld,
    pub(crate) spec: EnvSpec,
    /// Each end effector: an instance (its centre of mass), or a site (the instance and
    /// the point, mm in its frame).
    end_effectors: Vec<EndEffector>,
    pub(crate) elapsed: u32,
    pub(crate) seed: u64,
    /// The episode random stream: seeded from `seed`, drawn from by each reset.
    pub(crate) rng: Xoshiro256PlusPlus,
    /// The units of observations and terms.
    pub(crate) units: Units,
    /// Each reset's position offsets, in `units` (`EnvConfig::reset_noise` is in the
    /// document's: its draws are converted), and velocity offsets.
    pub(crate) position_noise: Option<(Dist, Units)>,
    pub(crate) velocity_noise: Option<Dist>,
    /// The floating base's noise: position (and orientation) and velocity distributions,
    /// and this episode's draws.
    pub(crate) base_noise: Option<(Option<Dist>, Option<Dist>)>,
    pub(crate) base_draws: [f64; BASE_NOISE_LEN],
    /// Joints set to drawn positions at each reset (a terms task's `reset_noise.set`).
    pub(crate) sets: Vec<ActiveSet>,
    /// World steps run with a zero action after each reset's draws (a terms task's
    /// `reset_noise.settle_substeps`, in whole steps).
    pub(crate) settle_steps: u32,
    /// Whether a floating base starts at a random orientation, and whether a start is
    /// drawn again while colliders overlap (a terms task's `reset_noise`).
    pub(crate) turn_base: bool,
    pub(crate) reject_contacts: bool,
    /// This episode's base orientation draw, with `turn_base`.
    pub(crate) base_turn: Option<[f64; 4]>,
    /// Where mocap bodies start (a terms task's `reset_noise.mocap`), and this episode's
    /// draws (SI positions).
    pub(crate) mocap_draws: Vec<crate::terms::ActiveMocapDraw>,
    pub(crate) mocap_starts: Vec<crate::terms::MocapStart>,
    /// Joints placed by one of several options, and this episode's draw; DOF pairs that
    /// start equal (`reset_noise.choice`, `reset_noise.equal`).
    pub(crate) choice: Option<crate::terms::ChoiceDraw>,
    pub(crate) equal: Vec<(usize, usize)>,
    /// Scratch for the per-DOF reset offsets (deg or mm) and velocities (`units`).
    pub(crate) offsets: Vec<f64>,
    pub(crate) start_velocities: Vec<f64>,
    /// A terms task's values of the last step (zeros after a reset).
    term_values: Vec<f32>,
    /// The last finite observation, returned if the physics diverges.
    pub(crate) last_obs: Vec<f32>,
    pub(crate) diverged: bool,
    /// The task, if any.
    pub(crate) task: Option<ActiveTask>,
    /// Domain randomisation, and this episode's draws.
    pub(crate) randomize: Option<Randomization>,
    pub(crate) draws: Option<Draws>,
    /// The document and options it was built from, for its saved states.
    pub(crate) origin: std::sync::Arc<Origin>,
    /// Instance and joint names (document order), to report the draws by name.
    pub(crate) names: std::sync::Arc<(Vec<String>, Vec<String>)>,
    /// The document's sites by name (document order), for [`RobotEnv::bodies`].
    pub(crate) sites: std::sync::Arc<[(String, EndEffector)]>,
    /// The document's keyframes, and the one resets start from unless they name another.
    pub(crate) keyframes: std::sync::Arc<[crate::keyframe::StartKey]>,
    pub(crate) initial_keyframe: Option<usize>,
    /// Scratch for a keyframe's start: `offsets` and `start_velocities` with its values.
    pub(crate) keyed_offsets: Vec<f64>,
    pub(crate) keyed_velocities: Vec<f64>,
}

/// This episode's randomisation factors, by name.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawReport {
    /// `(instance, mass factor, friction factor)`, in document order.
    pub instances: Vec<(String, f64, f64)>,
    /// `(joint, damping factor, gain factor)`, in document order (fixed joints included).
    pub joints: Vec<(String, f64, f64)>,
}

/// Any observed value beyond this magnitude (mm, deg, deg/s) counts as divergence.
const DIVERGENCE_LIMIT: f32 = 1.0e9;

impl RobotEnv {
    /// Builds an environment from a validated assembly. A `dt` of 0 becomes the
    /// document's `simulation.dt`, else [`crate::DEFAULT_DT`].
    pub fn new(assembly: &Assembly, mut config: EnvConfig) -> Result<Self> {
        if config.dt == 0.0 {
            config.dt = assembly.dt.unwrap_or(crate::DEFAULT_DT);
        }
        config.validate()?;
        let origin = std::sync::Arc::new(Origin {
            document: std::sync::Arc::clone(&assembly.source),
            config: config.clone(),
        });
        let end_effectors = crate::setup::end_effectors(assembly, &config.end_effector_ids)?;
        let options = WorldOptions {
            dt: config.dt,
            substeps: config.substeps,
            gains: config.pd_gains.clone(),
        };
        let world = RobotWorld::new(assembly, &options)?;
        let cx = Context {
            assembly,
            dofs: world.dofs(),
            action_dim: world.action_dim(),
            units: config.units,
            dt: config.dt,
            groups: Default::default(),
        };
        let task = config.task.as_ref().map(|t| t.resolve(&cx)).transpose()?;
        let terms = task.as_ref().and_then(|t| t.terms());
        let position_noise = crate::setup::position_noise(&config, terms)?;
        let velocity_noise = terms.and_then(|t| t.velocity_noise);
        let base_noise = terms
            .filter(|t| t.base_noise)
            .map(|t| (t.position_noise, t.velocity_noise));
        let sets = terms.map(|t| t.sets.clone()).unwrap_or_default();
        let settle_steps = terms.map_or(0, |t| t.settle_substeps.div_ceil(config.substeps.max(1)));
        let mocap_draws = terms.map(|t| t.mocap_draws.clone()).unwrap_or_default();
        let choice = terms
            .and_then(|t| t.choice.clone())
            .map(crate::terms::ChoiceDraw::new);
        let equal = terms.map(|t| t.equal.clone()).unwrap_or_default();
        let spec = crate::setup::env_spec(assembly, &config, &world, task.as_ref());
        let mut env = RobotEnv {
            world,
            end_effectors,
            elapsed: 0,
            seed: config.seed,
            rng: Xoshiro256PlusPlus::seed_from_u64(config.seed),
            units: config.units,
            position_noise,
            velocity_noise,
            base_noise,
            base_draws: [0.0; BASE_NOISE_LEN],
            sets,
            settle_steps,
            turn_base: terms.is_some_and(|t| t.turn_base),
            reject_contacts: terms.is_some_and(|t| t.reject_contacts),
            base_turn: None,
            mocap_starts: vec![([0.0; 3], None); mocap_draws.len()],
            choice,
            equal,
            mocap_draws,
            offsets: vec![0.0; spec.num_dofs],
            start_velocities: vec![0.0; spec.num_dofs],
            keyed_offsets: vec![0.0; spec.num_dofs],
            keyed_velocities: vec![0.0; spec.num_dofs],
            keyframes: crate::keyframe::resolve(assembly, &spec.dofs).into(),
            initial_keyframe: assembly.initial_keyframe,
            term_values: vec![0.0; spec.term_names.len()],
            last_obs: vec![0.0; spec.observation_dim],
            spec,
            diverged: false,
            task,
            randomize: config.randomize.clone(),
            draws: None,
            origin,
            names: crate::setup::names(assembly),
            sites: crate::setup::sites(assembly),
        };
        env.reset(None);
        Ok(env)
    }

    /// Parses, validates and builds in one go.
    pub fn from_json(document: &str, config: EnvConfig) -> Result<Self> {
        let assembly = gymfleet_assembly::parse(document)?;
        Self::new(&assembly, config)
    }

    /// The environment's metadata.
    pub fn spec(&self) -> &EnvSpec {
        &self.spec
    }

    /// Steps taken since the last reset.
    pub fn elapsed_steps(&self) -> u32 {
        self.elapsed
    }

    /// Bounds each step's contact work to `max` contact point-substeps (contact points
    /// × substeps; 0: no limit). A step over it fails with [`EnvError::ContactWork`] and
    /// leaves the env where its last step left it. Copies made afterwards keep the limit.
    pub fn set_contact_work_limit(&mut self, max: usize) {
        self.world.set_contact_work_limit(max);
    }

    /// The contact work of the first step from the initial state, estimated by one
    /// collision detection on a copy: the contacts found and their point-substeps.
    pub fn initial_contact_work(&self) -> (gymfleet_physics::ContactLoad, usize) {
        self.world.initial_contact_work()
    }

    /// The seed of the current episode.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// A terms task's velocity terms start from the observation `obs`; the term values
    /// are zero until the next step.
    pub(crate) fn start_task(&mut self, obs: &[f32]) {
        self.term_values.iter_mut().for_each(|v| *v = 0.0);
        let dof = self.spec.num_dofs;
        if let Some(task) = &mut self.task {
            task.start(&self.world, &obs[..dof], &obs[dof..2 * dof]);
        }
    }

    /// A terms task's values after the last step, in the order of
    /// [`EnvSpec::term_names`] (zeros after a reset or a diverged step; empty without a
    /// terms task).
    pub fn term_values(&self) -> &[f32] {
        &self.term_values
    }

    /// Validates and applies an action for one step of `dt` seconds.
    pub fn step(&mut self, action_type: ActionType, values: &[f32]) -> Result<StepResult> {
        let mut flat = vec![0.0; self.spec.observation_dim];
        let flags = self.step_into(action_type, values, &mut flat)?;
        Ok(StepResult {
            observation: self.structured(&flat),
            flags,
        })
    }

    /// [`RobotEnv::step`], writing the flat observation into `out`
    /// (`observation_dim` floats). Allocation-free.
    pub fn step_into(
        &mut self,
        action_type: ActionType,
        values: &[f32],
        out: &mut [f32],
    ) -> Result<StepFlags> {
        action::validate(values, self.spec.action_dim)?;
        if self.diverged {
            return Err(EnvError::NeedsReset);
        }
        self.world.set_command(action_type.mode(), values);
        if let Err(overload) = self.world.step() {
            // Left as the last step left it, but for a step stopped within its substeps.
            self.diverged = overload.substeps_done > 0;
            return Err(EnvError::ContactWork(overload));
        }
        self.elapsed = self.elapsed.saturating_add(1);
        let truncated = self.elapsed >= self.spec.max_steps;

        self.observe_into(out);
        let healthy = self.world.is_finite()
            && out
                .iter()
                .all(|v| v.is_finite() && v.abs() < DIVERGENCE_LIMIT);
        if !healthy {
            self.diverged = true;
            out.copy_from_slice(&self.last_obs);
            self.term_values.iter_mut().for_each(|v| *v = 0.0);
            return Ok(StepFlags {
                reward: 0.0,
                terminated: true,
                truncated,
                termination: Some(Termination::PhysicsDiverged),
            });
        }
        self.last_obs.copy_from_slice(out);
        let dof = self.spec.num_dofs;
        let (reward, termination) = match &mut self.task {
            Some(task) => task.evaluate(
                &self.world,
                &out[..dof],
                &out[dof..2 * dof],
                values,
                &mut self.term_values,
            ),
            None => (0.0, None),
        };
        self.observe_task_into(out);
        self.last_obs.copy_from_slice(out);
        Ok(StepFlags {
            reward: reward as f32,
            terminated: termination.is_some(),
            truncated,
            termination,
        })
    }

    /// This episode's domain-randomisation factors by name; `None` without
    /// randomisation.
    pub fn draws(&self) -> Option<DrawReport> {
        let draws = self.draws.as_ref()?;
        let (instances, joints) = &*self.names;
        Some(DrawReport {
            instances: instances
                .iter()
                .zip(draws.mass.iter().zip(&draws.friction))
                .map(|(n, (&m, &f))| (n.clone(), m, f))
                .collect(),
            joints: joints
                .iter()
                .zip(draws.damping.iter().zip(&draws.gain))
                .map(|(n, (&d, &g))| (n.clone(), d, g))
                .collect(),
        })
    }

    pub(crate) fn structured(&self, flat: &[f32]) -> Observation {
        Observation::from_flat(flat, &self.spec.observation_layout)
    }

    /// Hints the processor to bring this env's physics state into the core's caches ahead
    /// of its next step ([`RobotWorld::prefetch`]): a batch shard calls it for the next env
    /// before stepping the current one. Changes nothing.
    pub fn prefetch(&self) {
        self.world.prefetch();
    }

    /// The current observation, without stepping.
    pub fn observe(&self) -> Observation {
        let mut flat = vec![0.0; self.spec.observation_dim];
        self.observe_into(&mut flat);
        self.structured(&flat)
    }

    /// [`RobotEnv::observe`], writing the flat observation into `out`.
    pub fn observe_into(&self, out: &mut [f32]) {
        if self.diverged {
            out.copy_from_slice(&self.last_obs);
            return;
        }
        let dof = self.spec.num_dofs;
        let (positions, rest) = out.split_at_mut(dof);
        let (velocities, rest) = rest.split_at_mut(dof);
        self.world.joint_state(self.units, positions, velocities);
        let rest = if self.spec.floating_base {
            let (base, rest) = rest.split_at_mut(BASE_STATE_LEN);
            base.copy_from_slice(&self.world.base_state(self.units));
            rest
        } else {
            rest
        };
        let free = self.spec.free_bodies.len();
        let (poses, rest) = rest.split_at_mut(FREE_POSE_LEN * free);
        let (velocities, rest) = rest.split_at_mut(FREE_VELOCITY_LEN * free);
        self.world.free_body_state(self.units, poses, velocities);
        let (poses, _) = rest.split_at_mut(POSE_LEN * self.end_effectors.len());
        for (pose, &ee) in poses.chunks_exact_mut(POSE_LEN).zip(&self.end_effectors) {
            pose.copy_from_slice(&self.end_effector_pose(self.units, ee));
        }
        self.observe_task_into(out);
    }

    /// Writes the task's part of the flat observation `out` (whose joint state is
    /// written): after a step's terms are evaluated and after a reset's start, so that
    /// observed contact wrenches are the step's (0 after a reset).
    pub(crate) fn observe_task_into(&self, out: &mut [f32]) {
        let Some(t) = &self.task else { return };
        let dof = self.spec.num_dofs;
        let at = out.len() - t.observation_dim();
        let (state, task) = out.split_at_mut(at);
        t.observe(&self.world, &state[..dof], &state[dof..2 * dof], task);
    }
}

/// Draws an episode's factors: every instance's mass then friction factor, then every
/// joint's damping then gain factor, each only if its range is given (else 1).
pub(crate) fn draw(
    rng: &mut Xoshiro256PlusPlus,
    r: &Randomization,
    instances: usize,
    joints: usize,
) -> Draws {
    let mut factors = |range: Option<[f64; 2]>, n: usize| -> Vec<f64> {
        match range {
            Some([min, max]) if min < max => (0..n).map(|_| rng.random_range(min..=max)).collect(),
            Some([min, _]) => vec![min; n],
            None => vec![1.0; n],
        }
    };
    let mass = factors(r.mass_scale, instances);
    let friction = factors(r.friction_scale, instances);
    let damping = factors(r.damping_scale, joints);
    let gain = factors(r.gain_scale, joints);
    Draws {
        mass,
        friction,
        damping,
        gain,
    }
}

/// What an env looks like now, for drawing it: its parts, joints, end effectors and task
/// target, in world millimetres.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Every part, each with its instance's index into `instance_names`.
    pub parts: Vec<ScenePart>,
    /// Instance names, in document order.
    pub instance_names: Vec<String>,
    /// Joints with at least one DOF, in document order.
    pub joints: Vec<SceneJoint>,
    /// Each end effector's position (its centre of mass, as observed), world mm.
    pub end_effectors: Vec<[f32; 3]>,
    /// A reach task's current target, world mm.
    pub target: Option<[f32; 3]>,
}

impl RobotEnv {
    /// An end effector's pose: its instance's centre of mass with the instance's
    /// orientation, or its site's point with the site's axes.
    pub(crate) fn end_effector_pose(
        &self,
        units: Units,
        (instance, site): EndEffector,
    ) -> [f32; 7] {
        match site {
            Some((point, rotation)) => self.world.site_pose(units, instance, point, rotation),
            None => self.world.body_pose(units, instance),
        }
    }

    /// The env's [`Scene`] as it is now.
    pub fn scene(&self) -> Scene {
        Scene {
            parts: self.world.scene_parts(),
            instance_names: self.names.0.clone(),
            joints: self.world.scene_joints(),
            end_effectors: self
                .end_effectors
                .iter()
                .map(|&ee| {
                    let p = self.end_effector_pose(Units::Document, ee);
                    [p[0], p[1], p[2]]
                })
                .collect(),
            target: self
                .task
                .as_ref()
                .and_then(|t| t.reach_target())
                .map(|t| t.map(|c| c as f32)),
        }
    }
}
