//! Helpers shared by the integration tests: a valid base document to mutate, and
//! assertions on the issues of a rejected one.

#![allow(dead_code)] // each test file uses a different subset

use gymfleet_assembly::{from_value, parse, Assembly, AssemblyError};
use serde_json::{json, Value};

/// A valid two-body document (the user guide's pendulum), to be mutated by each test.
pub(crate) fn base_doc() -> Value {
    json!({
        "parts": [
            { "name": "Base", "primitive": { "type": "cube", "size": { "x": 20, "y": 20, "z": 5 } } },
            { "name": "Arm", "primitive": { "type": "cube", "size": { "x": 4, "y": 4, "z": 40 } } }
        ],
        "assembly": {
            "instances": [
                { "part": "Base", "name": "base" },
                { "part": "Arm", "name": "arm", "position": { "x": 8, "y": 8, "z": 5 } }
            ],
            "joints": [
                { "type": "revolute", "parent": "base", "child": "arm",
                  "anchor": { "x": 10, "y": 10, "z": 5 }, "axis": { "x": 0, "y": 1, "z": 0 } }
            ]
        }
    })
}

/// A valid chain of `names.len()` small cubes, all of part "Block", without joints.
pub(crate) fn blocks_doc(names: &[&str]) -> Value {
    let instances: Vec<Value> = names
        .iter()
        .map(|n| json!({ "part": "Block", "name": n }))
        .collect();
    json!({
        "parts": [{ "name": "Block", "primitive": { "type": "cube", "size": { "x": 1, "y": 1, "z": 1 } } }],
        "assembly": { "instances": instances, "joints": [] }
    })
}

/// A revolute joint about Z at the origin.
pub(crate) fn revolute(parent: &str, child: &str) -> Value {
    json!({ "type": "revolute", "parent": parent, "child": child,
            "anchor": { "x": 0, "y": 0, "z": 0 }, "axis": { "x": 0, "y": 0, "z": 1 } })
}

/// Parses a document that must be valid.
pub(crate) fn ok(doc: Value) -> Assembly {
    from_value(doc).unwrap_or_else(|e| panic!("expected a valid document, got: {e}"))
}

/// Parses a document that must be rejected.
pub(crate) fn err(doc: Value) -> AssemblyError {
    match from_value(doc) {
        Ok(a) => panic!("expected an error, got {a:?}"),
        Err(e) => e,
    }
}

/// Parses JSON text that must be rejected.
pub(crate) fn err_text(text: &str) -> AssemblyError {
    match parse(text) {
        Ok(a) => panic!("expected an error, got {a:?}"),
        Err(e) => e,
    }
}

/// Asserts that `doc` is rejected with exactly one issue, whose Display is `expected`.
pub(crate) fn assert_issue(doc: Value, expected: &str) {
    let e = err(doc);
    assert_eq!(e.issues().len(), 1, "expected one issue, got: {e}");
    assert_eq!(e.to_string(), expected);
}

/// Asserts that `doc` is rejected by serde at `path`, with a message starting with
/// `prefix` (serde appends the line and column, which the tests do not pin).
pub(crate) fn assert_malformed(e: &AssemblyError, path: &str, prefix: &str) {
    assert!(
        matches!(e, AssemblyError::Malformed { .. }),
        "not malformed: {e:?}"
    );
    assert_eq!(e.issues().len(), 1);
    let issue = &e.issues()[0];
    assert_eq!(issue.path, path, "wrong path in: {e}");
    assert!(
        issue.message.starts_with(prefix),
        "message {:?} does not start with {prefix:?}",
        issue.message
    );
}
