//! `convert`, the one way a description becomes assembly JSON: its format detected or
//! given, and the errors of text that is neither.

use gymfleet_import::{convert, Format};

const REACHER: &str = include_str!("data/reacher.xml");
const PENDULUM_URDF: &str = r#"<robot name="pendulum">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.02"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><mass value="0.1"/><inertia ixx="0.01" iyy="0.01" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.01" length="0.4"/></geometry></collision>
  </link>
  <joint name="hinge" type="continuous">
    <parent link="base"/><child link="arm"/><origin xyz="0 0 0.01"/><axis xyz="0 1 0"/>
  </joint>
</robot>"#;
const PENDULUM: &str = include_str!("../../../models/pendulum.json");

#[test]
fn the_format_is_detected_from_the_root_element_or_json() {
    let mjcf = convert(REACHER, None, None).expect("MJCF converts");
    assert_eq!(mjcf.format, Format::Mjcf);
    gymfleet_assembly::parse(&mjcf.json).expect("a valid document");
    assert!(
        !mjcf.warnings.is_empty(),
        "Reacher's lights and cameras are left out"
    );

    let urdf = convert(PENDULUM_URDF, None, None).expect("URDF converts");
    assert_eq!(urdf.format, Format::Urdf);
    gymfleet_assembly::parse(&urdf.json).expect("a valid document");

    let json = convert(PENDULUM, None, None).expect("JSON passes");
    assert_eq!(json.format, Format::Json);
    assert_eq!(
        json.json, PENDULUM,
        "JSON without meshes passes through unchanged"
    );
    assert!(json.warnings.is_empty());
}

#[test]
fn a_given_format_is_used_as_given() {
    let err = convert(REACHER, Some(Format::Urdf), None).unwrap_err();
    assert!(err.to_string().contains("<mujoco>"), "{err}");
    // JSON is handed to the assembly parser as it is, whatever it holds.
    let as_json = convert(REACHER, Some(Format::Json), None).expect("passed through");
    assert_eq!(
        (as_json.format, as_json.json.as_str()),
        (Format::Json, REACHER)
    );
}

#[test]
fn xml_of_another_root_or_not_well_formed_is_refused() {
    let err = convert("<svg></svg>", None, None).unwrap_err();
    assert_eq!(
        err.to_string(),
        "line 1: <svg>: not a description gymfleet reads: MJCF's root is <mujoco>, URDF's <robot>"
    );
    let err = convert("<mujoco>", None, None).unwrap_err();
    assert!(
        err.to_string().starts_with("not well-formed XML: "),
        "{err}"
    );
}

/// The converters build typed documents and serialise them: what they write must read
/// back as the same document (a field serialised under another name than it parses, or an
/// option written when absent, would show here), for every feature the test models use.
#[test]
fn converted_documents_read_back_as_the_same_typed_document() {
    let models = [
        include_str!("data/ant.xml"),
        include_str!("data/half_cheetah.xml"),
        include_str!("data/reacher.xml"),
        include_str!("data/inverted_pendulum.xml"),
        PENDULUM_URDF,
    ];
    for text in models {
        let converted = convert(text, None, None).expect("converts");
        let written: serde_json::Value = serde_json::from_str(&converted.json).unwrap();
        let document: gymfleet_assembly::Document =
            serde_json::from_value(written.clone()).expect("reads back");
        let again = serde_json::to_value(&document).unwrap();
        assert_eq!(again, written, "{}", &text[..40]);
        gymfleet_assembly::validate(&document).expect("valid");
    }
}
