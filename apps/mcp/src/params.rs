//! The tools' inputs: one `Deserialize + JsonSchema` struct per tool, with a description
//! (units included) on every field, since that schema is all an agent sees. Nested types
//! are inlined so that clients which do not follow `$ref` still see every description.

use gymfleet_client::{ActionType, Autoreset, BatchOptions, EnvOptions, PdGains};
use schemars::JsonSchema;
use serde::Deserialize;

use crate::actions::ActionValue;
use crate::document::Document;
use crate::errors::{McpError, Result};
use crate::task::{RandomizeParam, TaskParam};

/// Inputs of `create_robot_env`, and every env's options in `batch_create_envs`'s (one
/// struct: each description says what it means for a batch where that differs).
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct CreateEnvParams {
    /// The assembly document: a JSON object with `parts` and `assembly` (instances and
    /// joints), lengths in mm and angles in degrees, or a string containing that JSON
    /// (or MuJoCo MJCF or ROS URDF text). Give this or `model`.
    #[serde(default)]
    pub(crate) document: Option<Document>,
    /// Instead of a document: the name of a model in the server's library (see
    /// list_models), e.g. "reacher".
    #[serde(default)]
    pub(crate) model: Option<String>,
    /// The mesh files a URDF or JSON document references (STL, OBJ, DAE), as one zip, tar
    /// or tar.gz archive in base64; `package://pkg/path` and relative paths resolve against
    /// its root. Omit when the document names no mesh files.
    #[serde(default)]
    pub(crate) assets_base64: Option<String>,
    /// Instance names (the `name` of entries in `assembly.instances`) whose poses are
    /// observed (in every env of a batch), in this order. Each adds 7 values to the
    /// observation. Default: none.
    #[serde(default)]
    pub(crate) end_effector_ids: Vec<String>,
    /// Seconds of simulated time per step. Default 1/240 s (about 0.004167 s).
    pub(crate) dt: Option<f64>,
    /// Integration substeps per step (each is dt/substeps seconds). Default 5.
    pub(crate) substeps: Option<u32>,
    /// Episode length in steps: `truncated` (and `done`) become true at this step.
    /// Default 1000.
    pub(crate) max_steps: Option<u32>,
    /// Seed of the environment's random generator (integer); a batch's base seed: env i
    /// is seeded with seed + i. Default 0.
    pub(crate) seed: Option<u64>,
    /// Optional PD gain overrides for `position` and `velocity` actions (shared by every
    /// env of a batch). Omit to use the server's stable defaults.
    pub(crate) pd_gains: Option<PdGainsParam>,
    /// Optional start-state randomisation: every reset offsets each joint's position by
    /// a random value in [-reset_noise, +reset_noise] degrees (mm for sliding joints),
    /// drawn from the seeded generator and kept within the joint's limits. Default 0
    /// (every reset is the exact initial pose).
    pub(crate) reset_noise: Option<f64>,
    /// Optional task: the server then computes each step's reward and ends episodes
    /// when the goal is reached or the robot fell (in a batch, every env's; a reach
    /// target_box gives each env its own targets). Default: none (reward 0).
    pub(crate) task: Option<TaskParam>,
    /// Optional domain randomisation of masses, friction, damping and gains, drawn at
    /// every reset (each env of a batch draws its own factors). Default: none.
    pub(crate) randomize: Option<RandomizeParam>,
}

/// PD gain overrides, per DOF in DOF order, in SI units.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[schemars(inline)]
pub(crate) struct PdGainsParam {
    /// Proportional gains, one per DOF (every joint's, passive ones included) or empty for the defaults:
    /// N·m/rad for rotational DOFs, N/m for linear ones.
    #[serde(default)]
    pub(crate) kp: Vec<f64>,
    /// Derivative gains, one per DOF (every joint's, passive ones included) or empty for the defaults:
    /// N·m·s/rad for rotational DOFs, N·s/m for linear ones.
    #[serde(default)]
    pub(crate) kd: Vec<f64>,
}

/// Inputs of `gym_reset`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct ResetParams {
    /// The env_id returned by create_robot_env, e.g. "sim_1".
    pub(crate) env_id: String,
    /// Optional new seed (integer) for the environment's random generator, applied before
    /// the reset.
    pub(crate) seed: Option<u64>,
    /// Optional keyframe (one of create_robot_env's keyframes) to start from, the reset
    /// noise on top. Default: the document's initial keyframe, if any.
    pub(crate) keyframe: Option<String>,
}

/// Inputs of `gym_observe` and `gym_close`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct EnvRefParams {
    /// The env_id returned by create_robot_env, e.g. "sim_1".
    pub(crate) env_id: String,
}

/// Inputs of `gym_set_mocap_pose`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct MocapPoseParams {
    /// The env_id returned by create_robot_env, e.g. "sim_1".
    pub(crate) env_id: String,
    /// The mocap body to move: one of create_robot_env's mocap_bodies.
    pub(crate) body: String,
    /// Where its frame is to be: [x, y, z] in world mm.
    pub(crate) position: [f32; 3],
    /// Its orientation [qw, qx, qy, qz] (normalised); default [1, 0, 0, 0], no rotation.
    #[serde(default = "no_rotation")]
    pub(crate) quaternion: [f32; 4],
}

fn no_rotation() -> [f32; 4] {
    [1.0, 0.0, 0.0, 0.0]
}

/// Inputs of `gym_load_state`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct LoadStateParams {
    /// The env_id to load the state into: an env of the same document and options as the
    /// one the state was saved from (the seed may differ), e.g. "sim_1".
    pub(crate) env_id: String,
    /// The state, base64, exactly as gym_save_state returned it.
    pub(crate) state: String,
}

/// Inputs of `gym_render`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct RenderParams {
    /// The env_id returned by create_robot_env, e.g. "sim_1".
    pub(crate) env_id: String,
    /// Viewing direction, framing the whole robot: "iso" (default, from front-right and above), "front" (from -y), "side" (from +x) or "top".
    #[serde(default)]
    pub(crate) camera: Option<CameraName>,
    /// Optional camera position [x, y, z] in world mm (overrides the preset's direction).
    #[serde(default)]
    pub(crate) eye: Option<[f64; 3]>,
    /// Optional point to look at [x, y, z] in world mm (default: the robot's centre).
    #[serde(default)]
    pub(crate) target: Option<[f64; 3]>,
    /// Vertical field of view in degrees, (0, 170]; default 45.
    #[serde(default)]
    pub(crate) fov_deg: Option<f32>,
    /// Parallel projection (true) instead of perspective.
    #[serde(default)]
    pub(crate) orthographic: Option<bool>,
    /// Image width in pixels, 16 to 2048 (default 320).
    #[serde(default)]
    pub(crate) width: Option<u32>,
    /// Image height in pixels, 16 to 2048 (default 240).
    #[serde(default)]
    pub(crate) height: Option<u32>,
}

/// A camera preset's name.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
#[schemars(inline)]
pub(crate) enum CameraName {
    /// From the front-right and above.
    Iso,
    /// From -y, looking along +y.
    Front,
    /// From +x, looking along -x.
    Side,
    /// From above.
    Top,
}

impl RenderParams {
    /// The camera and size the client sends.
    pub(crate) fn camera(&self) -> (gymfleet_client::Camera, u32, u32) {
        use gymfleet_client::CameraPreset;
        let preset = match self.camera.unwrap_or(CameraName::Iso) {
            CameraName::Iso => CameraPreset::Iso,
            CameraName::Front => CameraPreset::Front,
            CameraName::Side => CameraPreset::Side,
            CameraName::Top => CameraPreset::Top,
        };
        let camera = gymfleet_client::Camera {
            preset,
            eye: self.eye,
            target: self.target,
            fov_deg: self.fov_deg.unwrap_or(0.0),
            orthographic: self.orthographic.unwrap_or(false),
        };
        let (w, h) = match (self.width, self.height) {
            (None, None) => (0, 0),
            (w, h) => (w.unwrap_or(320), h.unwrap_or(240)),
        };
        (camera, w, h)
    }
}

/// How action values are interpreted.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[serde(rename_all = "lowercase")]
#[schemars(inline)]
pub(crate) enum ActionKind {
    Torque,
    Position,
    Velocity,
}

impl From<ActionKind> for ActionType {
    fn from(kind: ActionKind) -> Self {
        match kind {
            ActionKind::Torque => ActionType::Torque,
            ActionKind::Position => ActionType::Position,
            ActionKind::Velocity => ActionType::Velocity,
        }
    }
}

/// Inputs of `gym_step`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct StepParams {
    /// The env_id returned by create_robot_env, e.g. "sim_1".
    pub(crate) env_id: String,
    /// How `values` are read: "torque" = effort in N·m (revolute) or N (prismatic);
    /// "position" = target angle in degrees or displacement in mm, tracked by a PD
    /// controller; "velocity" = target speed in degrees/s or mm/s.
    pub(crate) action_type: ActionKind,
    /// One finite number per DOF, in document joint order: exactly action_dim values
    /// (action_dim comes from create_robot_env). Units follow action_type.
    #[schemars(with = "Vec<f64>")]
    pub(crate) values: Vec<ActionValue>,
}

/// What a batch does with an environment whose episode ended.
#[derive(Debug, Clone, Copy, Default, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
#[serde(rename_all = "snake_case")]
#[schemars(inline)]
pub(crate) enum AutoresetParam {
    #[default]
    Disabled,
    SameStep,
    NextStep,
}

impl From<AutoresetParam> for Autoreset {
    fn from(a: AutoresetParam) -> Self {
        match a {
            AutoresetParam::Disabled => Autoreset::Disabled,
            AutoresetParam::SameStep => Autoreset::SameStep,
            AutoresetParam::NextStep => Autoreset::NextStep,
        }
    }
}

/// Inputs of `batch_create_envs`: how many envs, every env's options (as
/// `create_robot_env`'s), and what happens to finished envs.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct CreateBatchParams {
    /// Number of identical environments in the batch (at least 1).
    pub(crate) n_envs: u32,
    /// Every env's document and options.
    #[serde(flatten)]
    pub(crate) env: CreateEnvParams,
    /// What happens to an env whose episode ended: "disabled" (default: call
    /// batch_reset), "same_step" (reset within the step; its last observation is returned
    /// as final_observation) or "next_step" (Gymnasium style: reset on the next step,
    /// whose action for it is ignored).
    #[serde(default)]
    pub(crate) autoreset: AutoresetParam,
}

/// Inputs of `batch_step`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct BatchStepParams {
    /// The batch_id returned by batch_create_envs, e.g. "batch_1".
    pub(crate) batch_id: String,
    /// How actions are read: "torque" = N·m (revolute) or N (prismatic); "position" =
    /// target in degrees or mm; "velocity" = target in degrees/s or mm/s.
    pub(crate) action_type: ActionKind,
    /// One array per environment (n_envs arrays, env 0 first), each with exactly
    /// action_dim finite numbers in document joint order, e.g. [[0.5, -0.3], [0.1, 0.2]]
    /// for 2 envs of a 2-DOF arm. Units follow action_type.
    #[schemars(with = "Vec<Vec<f64>>")]
    pub(crate) actions: Vec<Vec<ActionValue>>,
}

/// Inputs of `batch_reset`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct BatchResetParams {
    /// The batch_id returned by batch_create_envs, e.g. "batch_1".
    pub(crate) batch_id: String,
    /// Optional base seed (integer): env i is reseeded with seed + i before the reset.
    pub(crate) seed: Option<u64>,
    /// Optional keyframe (one of batch_create_envs's keyframes) every env starts from.
    pub(crate) keyframe: Option<String>,
}

/// Inputs of `batch_close`.
#[derive(Debug, Deserialize, JsonSchema)]
#[schemars(transform = crate::schema::one_line_descriptions)]
pub(crate) struct BatchRefParams {
    /// The batch_id returned by batch_create_envs, e.g. "batch_1".
    pub(crate) batch_id: String,
}

impl CreateEnvParams {
    /// The client's options, or why the document cannot be sent; unset options take
    /// the server's defaults.
    pub(crate) fn into_options(self) -> Result<EnvOptions> {
        let options = match (self.document, self.model) {
            (Some(document), None) => EnvOptions::new(document.into_json_text()?),
            (None, Some(model)) => EnvOptions::from_model(model),
            (Some(_), Some(_)) => {
                return Err(McpError::bad_argument(
                    "give document or model, not both".to_string(),
                ))
            }
            (None, None) => {
                return Err(McpError::bad_argument(
                    "document is required: the assembly document (JSON, MJCF or URDF), or \
                     give model: a name from list_models"
                        .to_string(),
                ))
            }
        };
        let mut options = options.end_effectors(self.end_effector_ids);
        if let Some(text) = self.assets_base64 {
            use base64::Engine as _;
            let archive = base64::engine::general_purpose::STANDARD
                .decode(text.trim())
                .map_err(|e| McpError::bad_argument(format!("assets_base64: not base64: {e}")))?;
            options = options.assets(archive);
        }
        if let Some(dt) = self.dt {
            options = options.dt(dt);
        }
        if let Some(substeps) = self.substeps {
            options = options.substeps(substeps);
        }
        if let Some(max_steps) = self.max_steps {
            options = options.max_steps(max_steps);
        }
        if let Some(seed) = self.seed {
            options = options.seed(seed);
        }
        if let Some(noise) = self.reset_noise {
            options = options.reset_noise(noise);
        }
        if let Some(task) = self.task {
            options = options.task(task.into_task()?);
        }
        if let Some(randomize) = self.randomize {
            options = options.randomize(randomize.into());
        }
        if let Some(gains) = self.pd_gains {
            options = options.pd_gains(PdGains {
                kp: gains.kp,
                kd: gains.kd,
            });
        }
        Ok(options)
    }
}

impl CreateBatchParams {
    /// The client's options, or why the document cannot be sent.
    pub(crate) fn into_options(self) -> Result<BatchOptions> {
        let env = self.env.into_options()?;
        Ok(BatchOptions::from_env(env, self.n_envs as usize).autoreset(self.autoreset.into()))
    }
}
