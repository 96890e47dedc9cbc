//! Builders for `CreateEnv` and `CreateBatch`: [`EnvOptions`] and [`BatchOptions`].

use gymfleet_proto::v1 as pb;

use crate::task::{Randomization, Task};
use crate::types::Autoreset;

/// Controller gain overrides, per DOF, in SI units (N·m/rad, N·m·s/rad, N/m, N·s/m).
/// Each list is empty (the server's defaults) or `action_dim` long.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PdGains {
    /// Proportional gains.
    pub kp: Vec<f64>,
    /// Derivative gains.
    pub kd: Vec<f64>,
}

/// How to create one environment. Unset options take the server's defaults
/// (`dt` 1/240 s, 4 substeps, 1000 steps, seed 0, stable PD gains).
///
/// ```
/// use gymfleet_client::EnvOptions;
///
/// let options = EnvOptions::new(r#"{"parts": [], "assembly": {"instances": []}}"#)
///     .end_effectors(["arm"])
///     .dt(1.0 / 120.0)
///     .substeps(8)
///     .max_steps(500)
///     .seed(7);
/// assert_eq!(options.end_effector_ids(), ["arm"]);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EnvOptions {
    document_json: String,
    end_effector_ids: Vec<String>,
    dt: Option<f64>,
    substeps: Option<u32>,
    max_steps: Option<u32>,
    seed: Option<u64>,
    pd_gains: Option<PdGains>,
    reset_noise: Option<f64>,
    task: Option<Task>,
    randomize: Option<Randomization>,
    format: crate::DocumentFormat,
    model: Option<String>,
    assets: Vec<u8>,
    document_path: String,
    units: crate::Units,
}

impl EnvOptions {
    /// Options for the assembly document `document_json` (JSON text, or an MJCF
    /// description: the format is detected unless [`EnvOptions::format`] says it).
    pub fn new(document_json: impl Into<String>) -> Self {
        EnvOptions {
            document_json: document_json.into(),
            ..EnvOptions::default()
        }
    }

    /// Options for a model of the server's library (`--models DIR`, see
    /// [`Client::list_models`](crate::Client::list_models)) instead of a document.
    pub fn from_model(name: impl Into<String>) -> Self {
        EnvOptions {
            model: Some(name.into()),
            ..EnvOptions::default()
        }
    }

    /// The document.
    pub fn document_json(&self) -> &str {
        &self.document_json
    }

    /// The observed end effectors.
    pub fn end_effector_ids(&self) -> &[String] {
        &self.end_effector_ids
    }

    /// The options as they travel, in both create requests.
    pub(crate) fn into_options(self) -> pb::EnvOptions {
        pb::EnvOptions {
            document_json: self.document_json,
            end_effector_ids: self.end_effector_ids,
            // 0 asks for the server's default.
            dt: self.dt.unwrap_or(0.0),
            substeps: self.substeps.unwrap_or(0),
            max_steps: self.max_steps.unwrap_or(0),
            seed: self.seed,
            pd_gains: self.pd_gains.map(|g| pb::PdGains { kp: g.kp, kd: g.kd }),
            reset_noise: self.reset_noise,
            task: self.task.map(Into::into),
            randomize: self.randomize.map(Into::into),
            format: pb::DocumentFormat::from(self.format) as i32,
            model: self.model.unwrap_or_default(),
            assets: self.assets,
            document_path: self.document_path,
            units: pb::Units::from(self.units) as i32,
        }
    }

    pub(crate) fn into_request(self) -> pb::CreateEnvRequest {
        pb::CreateEnvRequest {
            options: Some(self.into_options()),
            ..Default::default()
        }
    }
}

/// The option setters, listed once: each is an [`EnvOptions`] method that sets its field,
/// and a [`BatchOptions`] method of the same name that sets it on every env's options
/// (with its own note where a batch reads it differently).
macro_rules! option_setters {
    ($(
        $(#[doc = $doc:literal])*
        $(batch: $batch:literal;)?
        fn $name:ident($arg:ident: $ty:ty) { $field:ident = $value:expr }
    )*) => {
        impl EnvOptions {
            $(
                $(#[doc = $doc])*
                pub fn $name(mut self, $arg: $ty) -> Self {
                    self.$field = $value;
                    self
                }
            )*
        }

        impl BatchOptions {
            $(
                #[doc = concat!("See [`EnvOptions::", stringify!($name), "`].")]
                $(#[doc = concat!(" ", $batch)])?
                pub fn $name(mut self, $arg: $ty) -> Self {
                    self.env = self.env.$name($arg);
                    self
                }
            )*
        }
    };
}

option_setters! {
    /// The instances whose poses are observed, in observation order.
    fn end_effectors(ids: impl IntoIterator<Item = impl Into<String>>) {
        end_effector_ids = ids.into_iter().map(Into::into).collect()
    }
    /// The document's format (default: detected by the server).
    fn format(format: crate::DocumentFormat) { format = format }
    /// The files the document references (STL/OBJ/DAE meshes) as one zip, tar or tar.gz
    /// archive; `package://pkg/path` and relative paths resolve against its root.
    fn assets(archive: impl Into<Vec<u8>>) { assets = archive.into() }
    /// Where the document sits in its [`EnvOptions::assets`], e.g. `"fetch/push.xml"`: an
    /// MJCF document's includes and mesh files are read from that folder (`../`
    /// included), as MuJoCo reads them from the model file's. Default: the archive's
    /// root.
    fn document_path(path: impl Into<String>) { document_path = path.into() }
    /// Seconds per env step.
    fn dt(dt: f64) { dt = Some(dt) }
    /// Physics substeps per env step.
    fn substeps(substeps: u32) { substeps = Some(substeps) }
    /// Episode length in steps.
    fn max_steps(max_steps: u32) { max_steps = Some(max_steps) }
    /// Seed of the env's random generator.
    batch: "A batch's is its base seed: env `i` is seeded with `seed + seed_offset + i`.";
    fn seed(seed: u64) { seed = Some(seed) }
    /// Controller gain overrides.
    fn pd_gains(gains: PdGains) { pd_gains = Some(gains) }
    /// Initial-state noise: every reset offsets each DOF's position by a value drawn
    /// uniformly from `[-half_width, +half_width]` (deg or mm) from the env's seeded
    /// stream, clamped to its limits. Unset or 0: resets are exact.
    fn reset_noise(half_width: f64) { reset_noise = Some(half_width) }
    /// The task: reward, goal and task terminations computed by the server in the step.
    batch: "A reach target box gives each env its own targets.";
    fn task(task: impl Into<Task>) { task = Some(task.into()) }
    /// Domain randomisation: scale factors drawn at every reset.
    batch: "Each env draws its own factors.";
    fn randomize(randomization: Randomization) { randomize = Some(randomization) }
    /// The units of observations and of a terms task (default: the document's).
    fn units(units: crate::Units) { units = units }
}

/// How to create a batch of `n_envs` identical environments.
///
/// ```
/// use gymfleet_client::{Autoreset, BatchOptions};
///
/// let options = BatchOptions::new(r#"{"parts": [], "assembly": {"instances": []}}"#, 16)
///     .end_effectors(["forearm"])
///     .autoreset(Autoreset::SameStep)
///     .seed(1)
///     .seed_offset(32);
/// assert_eq!(options.n_envs(), 16);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BatchOptions {
    env: EnvOptions,
    n_envs: usize,
    autoreset: Autoreset,
    seed_offset: u64,
}

impl BatchOptions {
    /// A batch of `n_envs` envs of the document `document_json`.
    pub fn new(document_json: impl Into<String>, n_envs: usize) -> Self {
        Self::from_env(EnvOptions::new(document_json), n_envs)
    }

    /// A batch of `n_envs` envs configured as `env`.
    pub fn from_env(env: EnvOptions, n_envs: usize) -> Self {
        BatchOptions {
            env,
            n_envs,
            autoreset: Autoreset::Disabled,
            seed_offset: 0,
        }
    }

    /// What happens to finished envs.
    pub fn autoreset(mut self, autoreset: Autoreset) -> Self {
        self.autoreset = autoreset;
        self
    }

    /// Added to every env's seed index, for one logical batch sharded across servers.
    pub fn seed_offset(mut self, seed_offset: u64) -> Self {
        self.seed_offset = seed_offset;
        self
    }

    /// The number of envs.
    pub fn n_envs(&self) -> usize {
        self.n_envs
    }

    /// The offset added to every env's seed index.
    pub(crate) fn seed_offset_base(&self) -> u64 {
        self.seed_offset
    }

    /// The same options for `n_envs` envs (a fleet shard).
    pub(crate) fn with_n_envs(mut self, n_envs: usize) -> Self {
        self.n_envs = n_envs;
        self
    }

    pub(crate) fn into_request(self) -> pb::CreateBatchRequest {
        pb::CreateBatchRequest {
            options: Some(self.env.into_options()),
            // Over u32::MAX envs: saturate, and let the server's limit refuse it.
            n_envs: u32::try_from(self.n_envs).unwrap_or(u32::MAX),
            autoreset: pb::Autoreset::from(self.autoreset) as i32,
            seed_offset: self.seed_offset,
            ..Default::default()
        }
    }
}
