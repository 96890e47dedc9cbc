//! The fuzz targets' bodies (issue R2), shared by the libFuzzer binaries in
//! `fuzz/fuzz_targets/` and by `tests/tests/fuzz_corpora.rs`, which replays the committed
//! corpora through them in every `cargo test` (no instrumentation needed).
//!
//! Each takes untrusted bytes through one door of the server and asserts more than "no
//! panic": errors stay under their bound, a document that validates also builds and steps,
//! a state that loads also steps. Each returns how far the input got, so that a replay can
//! report the share of inputs that got past parsing.

use gymfleet_env::{ActionType, EnvConfig, RobotEnv, SavedState};

/// The longest error message any door may return, bytes: 20 issues of at most 1 000
/// characters (`gymfleet_assembly`'s bounds) with their paths, and some margin.
pub const MAX_ERROR_BYTES: usize = 32 * 1024;

/// How far an input got.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Reached {
    /// Refused while parsing (not UTF-8, not JSON/XML, a malformed field).
    Parsing,
    /// Parsed, refused by validation or conversion.
    Validation,
    /// Built into an env, and stepped.
    Stepping,
}

fn bounded(error: &dyn std::fmt::Display) {
    let text = error.to_string();
    assert!(
        text.len() <= MAX_ERROR_BYTES,
        "an error of {} bytes: {}…",
        text.len(),
        text.chars().take(200).collect::<String>()
    );
}

/// Builds an env of a validated document and steps it a few times with zero torque; both
/// must succeed.
fn build_and_step(document: &str) -> Reached {
    let assembly = match gymfleet_assembly::parse(document) {
        Ok(a) => a,
        Err(e) => {
            bounded(&e);
            return if matches!(e, gymfleet_assembly::AssemblyError::Malformed { .. }) {
                Reached::Parsing
            } else {
                Reached::Validation
            };
        }
    };
    let config = EnvConfig {
        max_steps: 5,
        ..EnvConfig::default()
    };
    let mut env = match RobotEnv::new(&assembly, config) {
        Ok(env) => env,
        Err(e) => panic!("a document that validates must build: {e}"),
    };
    let zeros = vec![0.0f32; env.spec().action_dim];
    for _ in 0..3 {
        if let Err(e) = env.step(ActionType::Torque, &zeros) {
            bounded(&e);
            break;
        }
    }
    Reached::Stepping
}

/// The assembly document door (`CreateEnv`'s JSON): parse, validate, build, step.
pub fn assembly_document(data: &[u8]) -> Reached {
    match std::str::from_utf8(data) {
        Ok(text) => build_and_step(text),
        Err(_) => Reached::Parsing,
    }
}

/// The MJCF door: convert, then the document's own door.
pub fn mjcf(data: &[u8]) -> Reached {
    converted(data, gymfleet_import::mjcf_to_document)
}

/// The URDF door: convert, then the document's own door.
pub fn urdf(data: &[u8]) -> Reached {
    converted(data, gymfleet_import::urdf_to_document)
}

/// A description door: `convert` the text, then the document's own door.
fn converted(
    data: &[u8],
    convert: fn(&str) -> gymfleet_import::Result<gymfleet_import::Converted>,
) -> Reached {
    let Ok(text) = std::str::from_utf8(data) else {
        return Reached::Parsing;
    };
    match convert(text) {
        Ok(converted) => build_and_step(&converted.document.to_string()).max(Reached::Validation),
        Err(e) => {
            bounded(&e);
            if matches!(e, gymfleet_import::ImportError::Xml(_)) {
                Reached::Parsing
            } else {
                Reached::Validation
            }
        }
    }
}

/// The saved-state door (`LoadState`, `Fork`): decode, load into an env, step.
pub fn saved_state(data: &[u8]) -> Reached {
    let state = match SavedState::decode(data) {
        Ok(s) => s,
        Err(e) => {
            bounded(&e);
            return Reached::Parsing;
        }
    };
    let mut env = match RobotEnv::from_state(&state) {
        Ok(env) => env,
        Err(e) => {
            bounded(&e);
            return Reached::Validation;
        }
    };
    let zeros = vec![0.0f32; env.spec().action_dim];
    if let Err(e) = env.step(ActionType::Torque, &zeros) {
        bounded(&e);
    }
    Reached::Stepping
}

/// The MJCF model the assets target reads its archives against: two mesh files (STL and
/// OBJ) and an include, all looked up in the archive.
const ASSETS_MJCF: &str = r#"<mujoco model="assets">
  <include file="extra.xml"/>
  <asset>
    <mesh name="a" file="a.stl"/>
    <mesh name="b" file="meshes/b.obj"/>
  </asset>
  <worldbody>
    <body name="link" pos="0 0 0.5">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom type="mesh" mesh="a"/>
      <geom type="mesh" mesh="b" pos="0.1 0 0"/>
    </body>
  </worldbody>
  <actuator><motor joint="hinge" gear="1"/></actuator>
</mujoco>"#;

/// The URDF model the assets target reads its archives against: a COLLADA mesh by
/// `package://` URI.
const ASSETS_URDF: &str = include_str!("assets.urdf");

/// The assets door (`CreateEnv`'s `assets`): the bytes as a zip, tar or tar.gz archive,
/// read against an MJCF model (STL, OBJ, an include) and a URDF model (DAE); each model
/// that converts must build and step. Reports the furthest either got.
pub fn assets_archive(data: &[u8]) -> Reached {
    let assets = match gymfleet_import::Assets::from_archive(data) {
        Ok(assets) => assets,
        Err(e) => {
            bounded(&e);
            return Reached::Parsing;
        }
    };
    [
        (ASSETS_MJCF, gymfleet_import::Format::Mjcf),
        (ASSETS_URDF, gymfleet_import::Format::Urdf),
    ]
    .into_iter()
    .map(
        |(text, format)| match gymfleet_import::to_json(text, format, Some(&assets)) {
            Ok((json, _warnings)) => build_and_step(&json).max(Reached::Validation),
            Err(e) => {
                bounded(&e);
                Reached::Validation
            }
        },
    )
    .max()
    .unwrap_or(Reached::Validation)
}

/// The saved-state door past its checksum: the bytes are a state's fields (the payload
/// after the 12-byte header), sealed with the magic, [`gymfleet_env::STATE_VERSION`] and
/// their CRC-32 before decoding, so that mutations reach the field checks and the loader
/// instead of stopping at the checksum.
pub fn saved_state_fields(payload: &[u8]) -> Reached {
    let mut sealed = Vec::with_capacity(12 + payload.len());
    sealed.extend_from_slice(b"GFST");
    sealed.extend_from_slice(&gymfleet_env::STATE_VERSION.to_le_bytes());
    sealed.extend_from_slice(&crc32fast::hash(payload).to_le_bytes());
    sealed.extend_from_slice(payload);
    saved_state(&sealed)
}
