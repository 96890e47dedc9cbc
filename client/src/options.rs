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

    /// The instances whose poses are observed, in observation order.
    pub fn end_effectors<S: Into<String>>(mut self, ids: impl IntoIterator<Item = S>) -> Self {
        self.end_effector_ids = ids.into_iter().map(Into::into).collect();
        self
    }

    /// The document's format (default: detected by the server).
    pub fn format(mut self, format: crate::DocumentFormat) -> Self {
        self.format = format;
        self
    }

    /// The files the document references (STL/OBJ/DAE meshes) as one zip, tar or tar.gz
    /// archive; `package://pkg/path` and relative paths resolve against its root.
    pub fn assets(mut self, archive: impl Into<Vec<u8>>) -> Self {
        self.assets = archive.into();
        self
    }

    /// Where the document sits in its [`EnvOptions::assets`], e.g. `"fetch/push.xml"`: an
    /// MJCF document's includes and mesh files are read from that folder (`../`
    /// included), as MuJoCo reads them from the model file's. Default: the archive's
    /// root.
    pub fn document_path(mut self, path: impl Into<String>) -> Self {
        self.document_path = path.into();
        self
    }

    /// Seconds per env step.
    pub fn dt(mut self, dt: f64) -> Self {
        self.dt = Some(dt);
        self
    }

    /// Physics substeps per env step.
    pub fn substeps(mut self, substeps: u32) -> Self {
        self.substeps = Some(substeps);
        self
    }

    /// Episode length in steps.
    pub fn max_steps(mut self, max_steps: u32) -> Self {
        self.max_steps = Some(max_steps);
        self
    }

    /// Seed of the env's random generator.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = Some(seed);
        self
    }

    /// Controller gain overrides.
    pub fn pd_gains(mut self, gains: PdGains) -> Self {
        self.pd_gains = Some(gains);
        self
    }

    /// Initial-state noise: every reset offsets each DOF's position by a value drawn
    /// uniformly from `[-half_width, +half_width]` (deg or mm) from the env's seeded
    /// stream, clamped to its limits. Unset or 0: resets are exact.
    pub fn reset_noise(mut self, half_width: f64) -> Self {
        self.reset_noise = Some(half_width);
        self
    }

    /// The task: reward, goal and task terminations computed by the server in the step.
    pub fn task(mut self, task: impl Into<Task>) -> Self {
        self.task = Some(task.into());
        self
    }

    /// Domain randomisation: scale factors drawn at every reset.
    pub fn randomize(mut self, randomization: Randomization) -> Self {
        self.randomize = Some(randomization);
        self
    }

    /// The units of observations and of a terms task (default: the document's).
    pub fn units(mut self, units: crate::Units) -> Self {
        self.units = units;
        self
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

    /// See [`EnvOptions::end_effectors`].
    pub fn end_effectors<S: Into<String>>(mut self, ids: impl IntoIterator<Item = S>) -> Self {
        self.env = self.env.end_effectors(ids);
        self
    }

    /// See [`EnvOptions::format`].
    pub fn format(mut self, format: crate::DocumentFormat) -> Self {
        self.env = self.env.format(format);
        self
    }

    /// See [`EnvOptions::assets`].
    pub fn assets(mut self, archive: impl Into<Vec<u8>>) -> Self {
        self.env = self.env.assets(archive);
        self
    }

    /// See [`EnvOptions::document_path`].
    pub fn document_path(mut self, path: impl Into<String>) -> Self {
        self.env = self.env.document_path(path);
        self
    }

    /// See [`EnvOptions::dt`].
    pub fn dt(mut self, dt: f64) -> Self {
        self.env = self.env.dt(dt);
        self
    }

    /// See [`EnvOptions::substeps`].
    pub fn substeps(mut self, substeps: u32) -> Self {
        self.env = self.env.substeps(substeps);
        self
    }

    /// See [`EnvOptions::max_steps`].
    pub fn max_steps(mut self, max_steps: u32) -> Self {
        self.env = self.env.max_steps(max_steps);
        self
    }

    /// Base seed: env `i` is seeded with `seed + seed_offset + i`.
    pub fn seed(mut self, seed: u64) -> Self {
        self.env = self.env.seed(seed);
        self
    }

    /// See [`EnvOptions::pd_gains`].
    pub fn pd_gains(mut self, gains: PdGains) -> Self {
        self.env = self.env.pd_gains(gains);
        self
    }

    /// See [`EnvOptions::reset_noise`].
    pub fn reset_noise(mut self, half_width: f64) -> Self {
        self.env = self.env.reset_noise(half_width);
        self
    }

    /// See [`EnvOptions::task`]. A reach target box gives each env its own targets.
    pub fn task(mut self, task: impl Into<Task>) -> Self {
        self.env = self.env.task(task);
        self
    }

    /// See [`EnvOptions::randomize`]; each env draws its own factors.
    pub fn randomize(mut self, randomization: Randomization) -> Self {
        self.env = self.env.randomize(randomization);
        self
    }

    /// See [`EnvOptions::units`].
    pub fn units(mut self, units: crate::Units) -> Self {
        self.env = self.env.units(units);
        self
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
