//! [`Model`]: the robot document a run loads, either one of the three built-in models
//! (compiled in from `models/`) or a document file (assembly JSON, or MJCF converted by
//! `gymfleet-import`), with its end effectors and the torque scale that moves it without
//! throwing it about.

use std::path::Path;

use serde::Serialize;

use crate::error::{LoadError, Result};

/// The seed's 1-DOF pendulum.
pub const PENDULUM: &str = include_str!("../../../models/pendulum.json");
/// The seed's 2-DOF arm.
pub const ARM2: &str = include_str!("../../../models/arm2.json");
/// A 6-DOF arm: base yaw, shoulder and elbow pitch, wrist roll, pitch and roll.
pub const ARM6: &str = include_str!("../../../models/arm6.json");
/// A chain of 20 revolute links.
pub const CHAIN20: &str = include_str!("../../../models/chain20.json");
/// A crank-rocker four-bar linkage: a closed kinematic chain, its crank driven.
pub const FOURBAR: &str = include_str!("../../../models/fourbar.json");

/// The built-in models, one per file of `models/`: name (the file's stem), document, tip
/// instance (the default end effector) and torque amplitude (N·m).
pub const BUILTINS: [(&str, &str, &str); 5] = [
    ("pendulum", PENDULUM, "arm"),
    ("arm2", ARM2, "forearm"),
    ("arm6", ARM6, "tool"),
    ("chain20", CHAIN20, "link20"),
    ("fourbar", FOURBAR, "coupler"),
];

/// Torque amplitude (N·m) where a server reports no action bounds (servers before them):
/// suits the seed-sized parts (grams, centimetres), whose gravity torques are about 1e-4 N·m.
/// Otherwise each DOF swings within its own bound (`JointInfo.action_bounds`).
pub const DEFAULT_TORQUE_AMPLITUDE: f32 = 1e-4;

/// An assembly document to load, and how to drive it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Model {
    /// A built-in model's name ([`BUILTINS`]), or the file path as given.
    pub name: String,
    /// Whether it is one of the built-in models.
    pub builtin: bool,
    /// The document (JSON text).
    #[serde(skip)]
    pub document: String,
    /// The instances observed by default: the built-ins' tips, or a file's last instance.
    pub default_end_effectors: Vec<String>,
}

impl Model {
    /// Resolves `--model`: a built-in name, else a path to a document file.
    pub fn resolve(name: &str) -> Result<Self> {
        if let Some(&(_, document, tip)) = BUILTINS.iter().find(|b| b.0 == name) {
            return Ok(Model {
                name: name.to_string(),
                builtin: true,
                document: document.to_string(),
                default_end_effectors: vec![tip.to_string()],
            });
        }
        let path = Path::new(name);
        if !path.exists() {
            return Err(LoadError::UnknownModel {
                name: name.to_string(),
            });
        }
        // An MJCF or URDF description becomes assembly JSON here (its meshes read from
        // its folder), so that in-process runs (which build without a server) read it
        // too; JSON passes through.
        let document = gymfleet_import::convert_file(path)
            .map(|(json, _warnings)| json)
            .map_err(|e| LoadError::ModelFile {
                path: path.to_path_buf(),
                reason: e.to_string(),
            })?;
        Ok(Model {
            name: name.to_string(),
            builtin: false,
            default_end_effectors: last_instance(&document).into_iter().collect(),
            document,
        })
    }
}

/// The name of the document's last instance, if the document is readable JSON with one.
/// A broken document is left to the server, which reports it with its JSON path.
fn last_instance(document: &str) -> Option<String> {
    let value: serde_json::Value = serde_json::from_str(document).ok()?;
    let instances = value.get("assembly")?.get("instances")?.as_array()?;
    Some(instances.last()?.get("name")?.as_str()?.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtins_name_their_tips() {
        assert_eq!(
            Model::resolve("pendulum").unwrap().default_end_effectors,
            ["arm"]
        );
        assert_eq!(
            Model::resolve("arm2").unwrap().default_end_effectors,
            ["forearm"]
        );
        let arm6 = Model::resolve("arm6").unwrap();
        assert_eq!(arm6.default_end_effectors, ["tool"]);
        assert!(arm6.document.contains("\"tool\""));
    }

    #[test]
    fn an_mjcf_file_is_converted_into_json() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../crates/import/tests/data/reacher.xml"
        );
        let model = Model::resolve(path).unwrap();
        assert!(model.document.trim_start().starts_with('{'));
        assert_eq!(model.default_end_effectors, ["target"]);
        let bad =
            std::env::temp_dir().join(format!("gymfleet-load-bad-{}.xml", std::process::id()));
        std::fs::write(
            &bad,
            "<mujoco><worldbody><body><joint type=\"ball\" springdamper=\"0.1 1\"/><geom size=\".1\"/></body></worldbody></mujoco>",
        )
        .unwrap();
        let err = Model::resolve(bad.to_str().unwrap())
            .unwrap_err()
            .to_string();
        std::fs::remove_file(&bad).ok();
        assert!(
            err.contains(
                "<joint>: springdamper on a ball joint (a rotational spring) is not supported yet"
            ),
            "{err}"
        );
    }

    #[test]
    fn files_default_to_their_last_instance() {
        assert_eq!(last_instance(ARM2).as_deref(), Some("forearm"));
        assert_eq!(last_instance("not json"), None);
        assert_eq!(last_instance(r#"{"assembly": {"instances": []}}"#), None);
    }
}
