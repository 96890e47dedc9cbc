//! The server's domain values, free of protobuf: the requests `convert.rs` decodes from
//! the wire and [`crate::simulation::Simulation`] acts on, and the outcomes it returns for
//! `convert.rs` to encode. Both modules sit above this one.

use gymfleet_batch::{Autoreset, BatchStepOutput};
use std::sync::Arc;

use gymfleet_env::{ActionType, EnvConfig, EnvSpec, ObservationSegment, StepFlags};

use crate::config::ServerConfig;

/// A validated `CreateEnvRequest`: the document and the domain configuration.
#[derive(Debug, Clone)]
pub(crate) struct EnvRequest {
    pub(crate) document: String,
    /// The document's format; `None`: detect it.
    pub(crate) format: Option<gymfleet_import::Format>,
    /// A model of the library instead of the document.
    pub(crate) model: Option<String>,
    /// The document's mesh files: a zip, tar or tar.gz archive (empty: none).
    pub(crate) assets: Vec<u8>,
    /// Where the document sits in `assets` (empty: the root), for its relative references.
    pub(crate) document_path: String,
    pub(crate) config: EnvConfig,
}

/// A validated `CreateBatchRequest`.
#[derive(Debug, Clone)]
pub(crate) struct BatchRequest {
    pub(crate) env: EnvRequest,
    /// The caller's seed, if given (the batch reseeds its envs from it).
    pub(crate) seed: Option<u64>,
    pub(crate) n_envs: usize,
    pub(crate) autoreset: Autoreset,
    pub(crate) seed_offset: u64,
}

/// A validated `ForkRequest`: the state is decoded on the pool.
#[derive(Debug, Clone)]
pub(crate) struct ForkRequest {
    pub(crate) state: Vec<u8>,
    pub(crate) n_envs: usize,
    pub(crate) autoreset: Autoreset,
}

/// A validated action: type and values, and the mocap targets that travel with it
/// (empty: they stay).
#[derive(Debug, Clone)]
pub(crate) struct Action {
    pub(crate) action_type: ActionType,
    pub(crate) values: Vec<f32>,
    pub(crate) mocap_poses: Vec<f32>,
}

/// A validated `StepRequest`.
#[derive(Debug, Clone)]
pub(crate) struct EnvStep {
    pub(crate) env_id: String,
    pub(crate) action: Action,
}

/// A validated `StepBatchRequest`.
#[derive(Debug, Clone)]
pub(crate) struct BatchStep {
    pub(crate) batch_id: String,
    pub(crate) action: Action,
    /// The envs to step (empty: every env).
    pub(crate) env_indices: Vec<u32>,
}

/// The parent and child instance names of each non-fixed joint, in document order.
#[derive(Debug, Clone, Default)]
pub(crate) struct JointLinks(pub(crate) Vec<(String, String)>);

/// A single env's flat observation, with the env's own layout to split it along.
#[derive(Debug, Clone)]
pub(crate) struct Observed {
    pub(crate) flat: Vec<f32>,
    pub(crate) layout: Arc<[ObservationSegment]>,
}

/// The outcome of a single-env step.
pub(crate) struct EnvStepOutcome {
    pub(crate) observation: Observed,
    pub(crate) flags: StepFlags,
    pub(crate) episode_step: u32,
    /// A terms task's values of the step.
    pub(crate) terms: Vec<f32>,
}

/// Every env's observation in a batch, after a reset or an observe.
pub(crate) struct BatchObservations {
    pub(crate) batch_id: String,
    pub(crate) n_envs: usize,
    pub(crate) observation_dim: usize,
    /// `n_envs × observation_dim` floats, row-major per env.
    pub(crate) observations: Vec<f32>,
}

/// The outcome of one batch step: the batch's step output, copied out of the buffers
/// the batch keeps for its next step.
pub(crate) struct BatchStepped {
    pub(crate) batch_id: String,
    /// Steps taken by this batch so far, this one included.
    pub(crate) step_index: u64,
    pub(crate) out: BatchStepOutput,
    /// The envs stepped, when the request listed some (empty: every env).
    pub(crate) env_indices: Vec<u32>,
}

/// What the server is and holds, for `GetServerInfo`.
pub(crate) struct ServerStatus<'a> {
    pub(crate) instance_id: &'a str,
    pub(crate) threads: usize,
    /// The caller.
    pub(crate) tenant: crate::tenant::Tenant,
    pub(crate) envs: usize,
    pub(crate) batches: usize,
    pub(crate) batch_envs: usize,
    pub(crate) config: &'a ServerConfig,
}

/// A created env or batch: its id and description.
pub(crate) struct Created {
    pub(crate) id: String,
    pub(crate) spec: EnvSpec,
    pub(crate) links: JointLinks,
    /// Batches only: the size and autoreset mode.
    pub(crate) batch: Option<(usize, Autoreset)>,
}

/// A picture to take: of whom, from where, how large.
#[derive(Debug, Clone)]
pub(crate) struct RenderOf {
    pub(crate) of: DrawsOf,
    pub(crate) camera: gymfleet_render::Camera,
    pub(crate) width: u32,
    pub(crate) height: u32,
}

/// A picture taken: the PNG and its account.
#[derive(Debug, Clone)]
pub(crate) struct Rendered {
    pub(crate) png: Vec<u8>,
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) description: String,
    pub(crate) grid_mm: f32,
}

/// Whose randomisation factors (or picture): an env, or env `index` of a batch.
#[derive(Debug, Clone)]
pub(crate) enum DrawsOf {
    Env(String),
    BatchEnv(String, usize),
}
