//! Environment configuration and the metadata an agent needs to drive it.

use gymfleet_physics::{JointDof, PdGains, Units};

use crate::error::{EnvError, Result};
use crate::observation::{self, ObservationSegment};
use crate::task::TaskSpec;

/// Default step length: 1/240 s.
pub const DEFAULT_DT: f64 = 1.0 / 240.0;
/// Default integration substeps per step: the fewest that keep every accuracy bound of
/// the analytic tests. Each substep is one semi-implicit Euler step of `dt / substeps`
/// (1/1200 s at the default `dt`); its energy error on an undamped pendulum swinging 40°
/// is 0.84 % over ten periods (4 substeps: 1.05 %, over the 1 % bound).
pub const DEFAULT_SUBSTEPS: u32 = 5;
/// Default episode length in steps.
pub const DEFAULT_MAX_STEPS: u32 = 1000;

/// Longest accepted step, in seconds.
const MAX_DT: f64 = 1.0;
/// Widest accepted `reset_noise`, deg or mm: far beyond any joint's range (offsets are
/// clamped into the limits), and far from where a uniform draw's width overflows.
const MAX_RESET_NOISE: f64 = 1e6;
/// Most substeps accepted per step.
const MAX_SUBSTEPS: u32 = 1000;

/// How to build an environment from a document.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EnvConfig {
    /// What is observed, in order: instance names (an instance's centre of mass and axes),
    /// or site names (a site's point and axes; an instance of the same name comes first,
    /// and `site:NAME` names the site whatever instances are called).
    pub end_effector_ids: Vec<String>,
    /// Seconds per step; 0 (the default): the document's `simulation.dt`, else
    /// [`DEFAULT_DT`].
    pub dt: f64,
    /// Physics substeps per step.
    pub substeps: u32,
    /// Steps until `truncated`.
    pub max_steps: u32,
    /// Seed of the episode random stream (used by `reset` when given none).
    pub seed: u64,
    /// PD gain overrides for position and velocity targets.
    pub pd_gains: Option<PdGains>,
    /// Initial-state noise: at every reset each DOF's position is offset by a value
    /// drawn uniformly from `[-reset_noise, +reset_noise]` (deg or mm) from the env's
    /// seeded stream, then clamped into its limits. 0 (the default): reset is exact.
    pub reset_noise: f64,
    /// The task: reward, goal and termination computed in the step. `None`: reward 0
    /// and no termination but diverged physics.
    pub task: Option<TaskSpec>,
    /// Domain randomisation: scale factors drawn at every reset. `None`: none.
    pub randomize: Option<Randomization>,
    /// The units of observations and of a terms task's values (and of its ranges and
    /// noise): the document's (mm, deg; the default) or SI (m, rad).
    pub units: Units,
}

/// Ranges `[min, max]` of scale factors, each drawn uniformly at every reset from the
/// env's seeded stream, independently per instance (mass, friction) and per joint
/// (damping, PD gains). `None`: that quantity is not randomised.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Randomization {
    /// Multiplies each instance's mass (its density; the inertia follows).
    pub mass_scale: Option<[f64; 2]>,
    /// Multiplies each instance's friction coefficient.
    pub friction_scale: Option<[f64; 2]>,
    /// Multiplies each joint's damping.
    pub damping_scale: Option<[f64; 2]>,
    /// Multiplies each joint's PD gains (default gains first follow the drawn masses).
    pub gain_scale: Option<[f64; 2]>,
}

/// Largest accepted scale factor.
const MAX_SCALE: f64 = 100.0;
/// Smallest accepted scale factor: a body scaled towards zero mass (or a joint towards
/// zero gain) makes the dynamics degenerate, not merely varied.
const MIN_SCALE: f64 = 0.01;

impl Randomization {
    pub(crate) fn validate(&self) -> Result<()> {
        for (field, range) in [
            ("randomize.mass_scale", self.mass_scale),
            ("randomize.friction_scale", self.friction_scale),
            ("randomize.damping_scale", self.damping_scale),
            ("randomize.gain_scale", self.gain_scale),
        ] {
            if let Some([min, max]) = range {
                if !(min.is_finite()
                    && max.is_finite()
                    && min >= MIN_SCALE
                    && min <= max
                    && max <= MAX_SCALE)
                {
                    return Err(EnvError::BadConfig {
                        field,
                        reason: format!(
                            "expected factors {MIN_SCALE} <= min <= max <= {MAX_SCALE}, got [{min}, {max}]"
                        ),
                    });
                }
            }
        }
        Ok(())
    }
}

impl Default for EnvConfig {
    fn default() -> Self {
        EnvConfig {
            end_effector_ids: Vec::new(),
            dt: 0.0,
            substeps: DEFAULT_SUBSTEPS,
            max_steps: DEFAULT_MAX_STEPS,
            seed: 0,
            pd_gains: None,
            reset_noise: 0.0,
            task: None,
            randomize: None,
            units: Units::Document,
        }
    }
}

impl EnvConfig {
    /// A default configuration observing these end effectors.
    pub fn with_end_effectors<S: Into<String>>(ids: impl IntoIterator<Item = S>) -> Self {
        EnvConfig {
            end_effector_ids: ids.into_iter().map(Into::into).collect(),
            ..EnvConfig::default()
        }
    }

    pub(crate) fn validate(&self) -> Result<()> {
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= MAX_DT) {
            return Err(EnvError::BadConfig {
                field: "dt",
                reason: format!("expected a step length in (0, {MAX_DT}] s, got {}", self.dt),
            });
        }
        if !(1..=MAX_SUBSTEPS).contains(&self.substeps) {
            return Err(EnvError::BadConfig {
                field: "substeps",
                reason: format!(
                    "expected 1 to {MAX_SUBSTEPS} substeps, got {}",
                    self.substeps
                ),
            });
        }
        if !(self.reset_noise.is_finite() && self.reset_noise >= 0.0) {
            return Err(EnvError::BadConfig {
                field: "reset_noise",
                reason: format!(
                    "expected a finite half-width >= 0 (deg or mm), got {}",
                    self.reset_noise
                ),
            });
        }
        if self.reset_noise > MAX_RESET_NOISE {
            // Wider ranges overflow the uniform draw (its width must be finite).
            return Err(EnvError::BadConfig {
                field: "reset_noise",
                reason: format!(
                    "expected a half-width of at most {MAX_RESET_NOISE} (deg or mm), got {:e}",
                    self.reset_noise
                ),
            });
        }
        if let Some(r) = &self.randomize {
            r.validate()?;
        }
        if self.max_steps == 0 {
            return Err(EnvError::BadConfig {
                field: "max_steps",
                reason: "expected at least 1 step, got 0".to_string(),
            });
        }
        Ok(())
    }
}

/// The bodies an env observes or moves besides its joints: whether the first instance is
/// a floating base, and the free and mocap bodies' instance names.
#[derive(Debug, Clone, Default)]
pub(crate) struct ObservedBodies {
    pub(crate) floating_base: bool,
    pub(crate) free_bodies: Vec<String>,
    pub(crate) mocap_bodies: Vec<String>,
    pub(crate) moving_mass: f64,
}

/// *(ext)* One actuator of the document (MJCF's `<actuator>` elements): its control is
/// one action value, after the actuated DOFs' values, whatever the action type.
#[derive(Debug, Clone, PartialEq)]
pub struct ActuatorSpec {
    /// Its name.
    pub name: String,
    /// Its kind as written: `motor`, `position`, `velocity`, `intvelocity`, `damper`,
    /// `cylinder` or `general`.
    pub kind: String,
    /// What it drives: a joint's name, or a tendon's.
    pub target: String,
    /// Controls are clamped into `[min, max]` (MuJoCo's `ctrlrange`); `None`: unclamped.
    pub ctrl_range: Option<[f64; 2]>,
}

impl ActuatorSpec {
    pub(crate) fn of(assembly: &gymfleet_assembly::Assembly) -> Vec<ActuatorSpec> {
        assembly
            .actuators
            .iter()
            .map(|a| ActuatorSpec {
                name: a.name.clone(),
                kind: a.kind.as_str().to_string(),
                target: match a.transmission {
                    gymfleet_assembly::Transmission::Joint(j) => assembly.joints[j].name.clone(),
                    gymfleet_assembly::Transmission::Tendon(t) => assembly.tendons[t].name.clone(),
                },
                ctrl_range: a.ctrl_range,
            })
            .collect()
    }
}

/// What an agent needs to know about an environment.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvSpec {
    /// Joints with at least one DOF.
    pub num_joints: usize,
    /// Values per action: the DOFs of the actuated joints, then one control per actuator.
    pub action_dim: usize,
    /// *(ext)* The actuators, in order: the action's last `actuators.len()` values.
    pub actuators: Vec<ActuatorSpec>,
    /// Every DOF, passive ones included: the positions (and velocities) observed.
    pub num_dofs: usize,
    /// `2·DOF` (+ 13 with a floating base) + 13 per free body `+ 7·end effectors` + the
    /// task's floats.
    pub observation_dim: usize,
    /// Whether the first instance is a floating base, observed as `base_pose` and
    /// `base_velocity`.
    pub floating_base: bool,
    /// The flat observation's segments, in order; their sizes sum to `observation_dim`.
    pub observation_layout: Vec<ObservationSegment>,
    /// The free bodies' instances, in document order: what `free_body_poses` and
    /// `free_body_velocities` observe.
    pub free_bodies: Vec<String>,
    /// The mocap bodies' instances, in document order: what pose targets name.
    pub mocap_bodies: Vec<String>,
    /// The mass of everything that moves (neither fixed to the world nor a mocap body),
    /// kg, at the document's masses.
    pub moving_mass: f64,
    /// Observed instances, in order.
    pub end_effector_ids: Vec<String>,
    /// Names of the joints with at least one DOF, in document order.
    pub joint_names: Vec<String>,
    /// Every DOF, in observation order (the actuated ones, in the same order, make the
    /// action), with its units, limits and gains.
    pub dofs: Vec<JointDof>,
    /// Seconds per step.
    pub dt: f64,
    /// Physics substeps per step.
    pub substeps: u32,
    /// Steps until `truncated`.
    pub max_steps: u32,
    /// The units of the observation and the term values.
    pub units: Units,
    /// A terms task's term names, in the order their values are reported.
    pub term_names: Vec<String>,
    /// The document's keyframes, in order: what a reset may start from.
    pub keyframes: Vec<String>,
    /// The heightfields, in document order: instance name, rows, columns (what
    /// [`crate::RobotEnv::set_heightfield`] names and takes).
    pub heightfields: Vec<(String, usize, usize)>,
    /// The document's sensors, in order: name, type (its MJCF element name) and the
    /// floats it reports (a task reads them as `{"sensor": name, "component": k}`).
    pub sensors: Vec<(String, &'static str, usize)>,
}

impl EnvSpec {
    /// `task`: the name and size of the task's observation segment, if it has one.
    pub(crate) fn new(
        config: &EnvConfig,
        dofs: &[JointDof],
        bodies: ObservedBodies,
        task: Option<(&'static str, usize)>,
        term_names: Vec<String>,
        actuators: Vec<ActuatorSpec>,
    ) -> Self {
        let ObservedBodies {
            floating_base,
            free_bodies,
            mocap_bodies,
            moving_mass,
        } = bodies;
        let mut joint_names: Vec<String> = Vec::new();
        let mut last = None;
        for dof in dofs {
            if last != Some(dof.joint) {
                joint_names.push(dof.joint_name.clone());
                last = Some(dof.joint);
            }
        }
        let observation_layout = observation::layout(
            observation::Observed {
                dofs: dofs.len(),
                floating_base,
                free_bodies: free_bodies.len(),
                end_effectors: config.end_effector_ids.len(),
            },
            task,
        );
        EnvSpec {
            num_joints: joint_names.len(),
            action_dim: dofs.iter().filter(|d| d.actuated).count() + actuators.len(),
            actuators,
            num_dofs: dofs.len(),
            observation_dim: observation_layout.iter().map(|s| s.size).sum(),
            observation_layout,
            floating_base,
            free_bodies,
            mocap_bodies,
            moving_mass,
            end_effector_ids: config.end_effector_ids.clone(),
            joint_names,
            dofs: dofs.to_vec(),
            dt: config.dt,
            substeps: config.substeps,
            max_steps: config.max_steps,
            units: config.units,
            term_names,
            keyframes: Vec::new(),
            heightfields: Vec::new(),
            sensors: Vec::new(),
        }
    }
}
