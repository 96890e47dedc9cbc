//! Helpers the MJCF test files share.

#![allow(dead_code)] // Each test file uses some of them.

use gymfleet_env::{EnvConfig, RobotEnv};
use gymfleet_import::mjcf_to_document;

/// The env the MJCF `xml` converts into, with `end_effectors`, and the conversion's warnings.
pub(crate) fn env(xml: &str, end_effectors: &[&str]) -> (RobotEnv, Vec<String>) {
    let converted = mjcf_to_document(xml).expect("converts");
    let text = converted.document.to_string();
    let env = RobotEnv::from_json(
        &text,
        EnvConfig::with_end_effectors(end_effectors.iter().copied()),
    )
    .unwrap_or_else(|e| panic!("the converted document builds: {e}\n{text}"));
    (env, converted.warnings)
}

/// The error converting `xml` gives (a panic if it converts).
pub(crate) fn error(xml: &str) -> String {
    match mjcf_to_document(xml) {
        Err(e) => e.to_string(),
        Ok(c) => panic!("expected an error, got {}", c.document),
    }
}

/// A model whose world has a sphere, then `inner`, one element per line.
pub(crate) fn model(inner: &str) -> String {
    format!("<mujoco>\n<worldbody>\n<geom type=\"sphere\" size=\".1\"/>\n{inner}\n</worldbody>\n</mujoco>")
}

/// A model whose world is `inner` alone (line 3).
pub(crate) fn bare(inner: &str) -> String {
    format!("<mujoco>\n<worldbody>\n{inner}\n</worldbody>\n</mujoco>")
}
