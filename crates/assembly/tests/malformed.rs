//! Structural errors met while deserialising: bad JSON, missing and unknown fields,
//! unknown tags and numbers out of range. Each names its path; none panics.

mod common;

use common::{assert_malformed, base_doc, err, err_text};
use serde_json::json;

#[test]
fn malformed_json_is_reported_on_the_document() {
    let e = err_text(r#"{ "parts": [ "#);
    assert_malformed(
        &e,
        "document",
        "expected a JSON document: EOF while parsing",
    );
    assert_eq!(e.path(), "document");

    let e = err_text(r#"{ "parts": [ , ] }"#);
    assert_malformed(
        &e,
        "document",
        "expected a JSON document: expected value at line 1",
    );

    let e = err_text("");
    assert_malformed(
        &e,
        "document",
        "expected a JSON document: EOF while parsing",
    );
}

#[test]
fn trailing_characters_are_rejected() {
    let text = format!("{} x", base_doc());
    let e = err_text(&text);
    assert_malformed(
        &e,
        "document",
        "expected a JSON document: trailing characters",
    );
    // Trailing whitespace is fine.
    assert!(gymfleet_assembly::parse(&format!("{}\n  \n", base_doc())).is_ok());
}

#[test]
fn a_document_must_be_an_object() {
    let e = err_text("42");
    assert_malformed(
        &e,
        "document",
        "invalid type: integer `42`, expected struct Document",
    );
}

#[test]
fn missing_fields() {
    let mut doc = base_doc();
    doc.as_object_mut().unwrap().remove("assembly");
    assert_malformed(&err(doc), "document", "missing field `assembly`");

    let mut doc = base_doc();
    doc["assembly"]["instances"][1]
        .as_object_mut()
        .unwrap()
        .remove("name");
    assert_malformed(&err(doc), "assembly.instances[1]", "missing field `name`");

    let mut doc = base_doc();
    doc["assembly"]["joints"][0]
        .as_object_mut()
        .unwrap()
        .remove("child");
    assert_malformed(&err(doc), "assembly.joints[0]", "missing field `child`");

    let mut doc = base_doc();
    doc["parts"][1]["primitive"]["size"] = json!({ "x": 4, "y": 4 });
    assert_malformed(&err(doc), "parts[1].primitive.size", "missing field `z`");

    let mut doc = base_doc();
    doc["parts"][1]["primitive"] = json!({ "type": "cylinder", "radius": 2 });
    assert_malformed(&err(doc), "parts[1].primitive", "missing field `height`");

    let mut doc = base_doc();
    doc["parts"][1]["primitive"] = json!({ "radius": 2 });
    assert_malformed(&err(doc), "parts[1].primitive", "missing field `type`");
}

#[test]
fn unknown_fields() {
    let mut doc = base_doc();
    doc["assembly"]["instances"][1]["postion"] = json!({ "x": 8, "y": 8, "z": 5 });
    assert_malformed(
        &err(doc),
        "assembly.instances[1].postion",
        "unknown field `postion`, expected one of `part`, `name`, `position`, `rotation`, `material`",
    );

    let mut doc = base_doc();
    doc["version"] = json!(2);
    assert_malformed(
        &err(doc),
        "version",
        "unknown field `version`, expected one of `parts`, `materials`, `assembly`",
    );

    let mut doc = base_doc();
    doc["assembly"]["joints"][0]["limits"] = json!([-90, 90]);
    assert_malformed(
        &err(doc),
        "assembly.joints[0].limits",
        "unknown field `limits`",
    );

    // A field named `""` at the top: reported on the document, not on an empty path
    // (found by `properties.rs` from the text `{""`).
    let mut doc = base_doc();
    doc[""] = json!(1);
    assert_malformed(
        &err(doc),
        "document",
        "unknown field ``, expected one of `parts`, `materials`, `assembly`",
    );

    let mut doc = base_doc();
    doc["materials"] = json!({ "steel": { "densty": 7850 } });
    assert_malformed(
        &err(doc),
        "materials.steel.densty",
        "unknown field `densty`",
    );
}

#[test]
fn unknown_primitive_fields() {
    // Once the tag is read, only its own fields are expected.
    let text = r#"{"parts": [{"name": "A", "primitive": {"type": "cylinder", "radius": 2, "heigth": 4}}],
                   "assembly": {"instances": [{"part": "A", "name": "a"}]}}"#;
    assert_malformed(
        &err_text(text),
        "parts[0].primitive.heigth",
        "unknown field `heigth`, expected `radius` or `height`",
    );
    // Before it (serde_json::Value sorts keys), any primitive field is expected.
    let mut doc = base_doc();
    doc["parts"][1]["primitive"] = json!({ "type": "cylinder", "radius": 2, "heigth": 40 });
    assert_malformed(
        &err(doc),
        "parts[1].primitive.heigth",
        "unknown field `heigth`, expected one of `type`, `size`, `radius`, `radii`, `height`",
    );

    // A field of another primitive type is unknown too, wherever the tag is.
    let text = r#"{"parts": [{"name": "A", "primitive": {"type": "sphere", "radius": 2, "height": 4}}],
                   "assembly": {"instances": [{"part": "A", "name": "a"}]}}"#;
    assert_malformed(
        &err_text(text),
        "parts[0].primitive.height",
        "unknown field `height`, expected `radius`",
    );
    let text = r#"{"parts": [{"name": "A", "primitive": {"size": {"x": 1, "y": 1, "z": 1}, "type": "sphere"}}],
                   "assembly": {"instances": [{"part": "A", "name": "a"}]}}"#;
    assert_malformed(
        &err_text(text),
        "parts[0].primitive",
        "unknown field `size`, expected `radius`",
    );
}

#[test]
fn unknown_primitive_type() {
    let mut doc = base_doc();
    doc["parts"][1]["primitive"] = json!({ "type": "cone", "radius": 2, "height": 40 });
    assert_malformed(
        &err(doc),
        "parts[1].primitive.type",
        "unknown variant `cone`, expected one of `cube`, `cylinder`, `sphere`, `capsule`",
    );
}

#[test]
fn unknown_joint_type() {
    let mut doc = base_doc();
    doc["assembly"]["joints"][0]["type"] = json!("hinge");
    assert_malformed(
        &err(doc),
        "assembly.joints[0].type",
        "unknown variant `hinge`, expected one of `revolute`, `prismatic`, `cylindrical`, `ball`, `fixed`",
    );
}

#[test]
fn wrong_value_types_name_their_field() {
    let mut doc = base_doc();
    doc["parts"][1]["primitive"]["size"]["z"] = json!("40");
    assert_malformed(
        &err(doc),
        "parts[1].primitive.size.z",
        r#"invalid type: string "40", expected f64"#,
    );

    let mut doc = base_doc();
    doc["assembly"]["joints"][0]["min"] = json!("-90");
    assert_malformed(
        &err(doc),
        "assembly.joints[0].min",
        r#"invalid type: string "-90", expected f64"#,
    );

    let mut doc = base_doc();
    doc["parts"][0]["primitive"] = json!("cube");
    assert_malformed(
        &err(doc),
        "parts[0].primitive",
        r#"invalid type: string "cube""#,
    );
}

#[test]
fn duplicate_keys_are_rejected() {
    let text = r#"{"parts": [{"name": "A", "primitive": {"type": "sphere", "radius": 1, "radius": 2}}],
                   "assembly": {"instances": [{"part": "A", "name": "a"}]}}"#;
    assert_malformed(
        &err_text(text),
        "parts[0].primitive.radius",
        "duplicate field `radius`",
    );
}

/// Numbers beyond f64 give a clean error naming the field, never a panic or an infinity.
#[test]
fn numbers_overflowing_f64_are_errors() {
    let cases = [
        (
            r#""position": {"x": 1e999, "y": 0, "z": 0}"#,
            "assembly.instances[0].position.x",
        ),
        (
            r#""rotation": {"x": 0, "y": -1e999, "z": 0}"#,
            "assembly.instances[0].rotation.y",
        ),
        (
            r#""position": {"x": 0, "y": 0, "z": 1000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000}"#,
            "assembly.instances[0].position.z",
        ),
    ];
    for (field, path) in cases {
        let text = format!(
            r#"{{"parts": [{{"name": "A", "primitive": {{"type": "sphere", "radius": 1}}}}],
                "assembly": {{"instances": [{{"part": "A", "name": "a", {field}}}]}}}}"#
        );
        let e = err_text(&text);
        assert_malformed(
            &e,
            "document",
            "expected a JSON document: number out of range",
        );
        assert!(e.to_string().ends_with(&format!("(in {path})")), "{e}");
    }

    let text = r#"{"parts": [{"name": "A", "primitive": {"type": "sphere", "radius": 1e999}}],
                   "materials": {"m": {"density": 1e400}},
                   "assembly": {"instances": [{"part": "A", "name": "a"}]}}"#;
    let e = err_text(text);
    assert_malformed(
        &e,
        "document",
        "expected a JSON document: number out of range",
    );
    assert!(
        e.to_string().ends_with("(in parts[0].primitive.radius)"),
        "{e}"
    );
}
