//! MJCF mesh geoms (`<asset><mesh>`, `compiler meshdir`, inline `vertex`) and
//! `<include file>`, read from a request's assets: the UR5's collision meshes of the test
//! data stand for a robot's files.

use gymfleet_import::{expand_includes, load_mesh, mjcf_to_document, to_json, Assets, Format};
use serde_json::Value;

const MESHES: &str = "tests/data/example-robot-data/robots/ur_description/meshes/ur5/collision";

fn mesh_file(name: &str) -> Vec<u8> {
    std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(MESHES)
            .join(name),
    )
    .expect("the test data")
}

/// A two-link arm of UR5 meshes: the base on the ground, the shoulder on a hinge.
const ARM: &str = r#"<mujoco model="ur">
  <compiler meshdir="meshes/ur5"/>
  <asset>
    <mesh file="base.stl"/>
    <mesh name="shoulder" file="shoulder.stl" scale="1 1 2"/>
  </asset>
  <worldbody>
    <body name="base_link">
      <geom type="mesh" mesh="base"/>
      <geom type="mesh" mesh="base" contype="0" conaffinity="0" mass="0"/>
      <body name="shoulder_link" pos="0 0 0.089">
        <joint name="pan" axis="0 0 1"/>
        <geom type="mesh" mesh="shoulder"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="pan" gear="10"/></actuator>
</mujoco>"#;

fn arm_assets() -> Assets {
    Assets::from_files([
        ("meshes/ur5/base.stl".to_string(), mesh_file("base.stl")),
        (
            "meshes/ur5/shoulder.stl".to_string(),
            mesh_file("shoulder.stl"),
        ),
    ])
}

fn bounds(points: impl Iterator<Item = [f64; 3]>) -> [[f64; 3]; 2] {
    let mut b = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    for p in points {
        for k in 0..3 {
            b[0][k] = b[0][k].min(p[k]);
            b[1][k] = b[1][k].max(p[k]);
        }
    }
    b
}

fn vertices(part: &Value) -> impl Iterator<Item = [f64; 3]> + '_ {
    part["primitive"]["vertices"]
        .as_array()
        .expect("inlined vertices")
        .iter()
        .map(|v| [0, 1, 2].map(|k| v[k].as_f64().unwrap()))
}

#[test]
fn a_mesh_geom_is_its_files_hull_scaled_where_the_file_puts_it() {
    let (json, warnings) = to_json(ARM, Format::Mjcf, Some(&arm_assets())).expect("converts");
    let document: Value = serde_json::from_str(&json).unwrap();
    let parts = document["parts"].as_array().unwrap();
    // The base (a body without joints: fixed where it is) and the shoulder; the massless
    // visual copy is dropped.
    assert_eq!(parts.len(), 2, "{}", document["parts"]);
    assert_eq!(document["assembly"]["instances"][0]["fixed"], true);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("a massless geom that collides with nothing: dropped")),
        "{warnings:?}"
    );
    for (part, file, scale) in [
        (&parts[0], "base.stl", [1.0, 1.0, 1.0]),
        (&parts[1], "shoulder.stl", [1.0, 1.0, 2.0]),
    ] {
        let (points, _) = load_mesh(&mesh_file(file), file).expect("reads");
        let expected = bounds(
            points
                .iter()
                .map(|p| [0, 1, 2].map(|k| f64::from(p[k]) * 1000.0 * scale[k])),
        );
        let got = bounds(vertices(part));
        for side in 0..2 {
            for k in 0..3 {
                assert!(
                    (got[side][k] - expected[side][k]).abs() < 1e-3,
                    "{file}: hull bounds {got:?}, the file's {expected:?}"
                );
            }
        }
    }
    // It builds and steps like any document.
    let assembly = gymfleet_assembly::parse(&json).expect("validates");
    let names: Vec<&str> = assembly.instances.iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["base_link_geom", "shoulder_link_geom"]);
}

#[test]
fn includes_are_spliced_from_the_assets() {
    let main = r#"<mujoco model="ur">
  <include file="ur/assets.xml"/>
  <worldbody><include file="ur/arm.xml"/></worldbody>
</mujoco>"#;
    let shared = r#"<mujocoinclude><compiler meshdir="meshes/ur5"/><asset>
    <mesh file="base.stl"/><mesh name="shoulder" file="shoulder.stl" scale="1 1 2"/></asset></mujocoinclude>"#;
    let arm = r#"<mujocoinclude><body name="base_link"><geom type="mesh" mesh="base"/>
      <body name="shoulder_link" pos="0 0 0.089"><joint name="pan" axis="0 0 1"/>
      <geom type="mesh" mesh="shoulder"/></body></body></mujocoinclude>"#;
    let mut files = vec![
        ("ur/assets.xml".to_string(), shared.as_bytes().to_vec()),
        ("ur/arm.xml".to_string(), arm.as_bytes().to_vec()),
    ];
    files.push(("meshes/ur5/base.stl".to_string(), mesh_file("base.stl")));
    files.push((
        "meshes/ur5/shoulder.stl".to_string(),
        mesh_file("shoulder.stl"),
    ));
    let (json, _) =
        to_json(main, Format::Mjcf, Some(&Assets::from_files(files))).expect("converts");
    let spliced: Value = serde_json::from_str(&json).unwrap();
    let (inline, _) = to_json(ARM, Format::Mjcf, Some(&arm_assets())).expect("converts");
    let inline: Value = serde_json::from_str(&inline).unwrap();
    assert_eq!(spliced["parts"], inline["parts"]);
    assert_eq!(
        spliced["assembly"]["instances"],
        inline["assembly"]["instances"]
    );
}

#[test]
fn an_inline_mesh_keeps_its_vertices() {
    let xml = r#"<mujoco><asset><mesh name="tetra" vertex="0 0 0  0.1 0 0  0 0.1 0  0 0 0.1" scale="2 1 1"/></asset>
      <worldbody><geom type="plane" size="1 1 0.1"/><body><joint type="hinge"/><geom type="mesh" mesh="tetra"/></body></worldbody></mujoco>"#;
    let converted = mjcf_to_document(xml).expect("converts");
    let got = bounds(vertices(&converted.document["parts"][1]));
    assert_eq!(got, [[0.0, 0.0, 0.0], [200.0, 100.0, 100.0]]);
}

fn error(xml: &str, assets: Option<&Assets>) -> String {
    match to_json(xml, Format::Mjcf, assets) {
        Err(e) => e.to_string(),
        Ok((json, _)) => panic!("expected an error, got {json}"),
    }
}

#[test]
fn mesh_and_include_errors_name_what_is_missing() {
    let model = |inner: &str| {
        format!("<mujoco>\n<asset><mesh file=\"a.stl\"/></asset>\n<worldbody>\n{inner}\n</worldbody>\n</mujoco>")
    };
    assert_eq!(
        error(
            &model(r#"<body><joint/><geom type="mesh" mesh="b"/></body>"#),
            None
        ),
        r#"line 4: <geom mesh=…>: no <asset><mesh> is named "b" (there are 1: "a")"#
    );
    assert_eq!(
        error(&model(r#"<body><joint/><geom type="mesh"/></body>"#), None),
        "line 4: <geom mesh=…>: missing: a mesh geom names an <asset><mesh>"
    );
    assert_eq!(
        error(
            &model(r#"<body><joint/><geom type="box" size="1 1 1" mesh="a"/></body>"#),
            None
        ),
        "line 4: <geom>: a box fitted to a mesh is not supported yet"
    );
    let missing = error(
        &model(r#"<body><joint/><geom type="mesh" mesh="a"/></body>"#),
        Some(&Assets::from_files([(
            "other.stl".to_string(),
            mesh_file("base.stl"),
        )])),
    );
    assert!(
        missing.starts_with("parts[0].primitive.file: assets: no file \"a.stl\""),
        "{missing}"
    );
    assert_eq!(
        error(
            "<mujoco>\n<asset><mesh/></asset><worldbody/></mujoco>",
            None
        ),
        "line 2: <mesh file=…>: missing (or vertex)"
    );
    // Includes.
    let with_include = "<mujoco>\n<include file=\"x.xml\"/>\n<worldbody/></mujoco>";
    assert_eq!(
        error(with_include, None),
        "line 2: <include>: the included file is not at hand: send the model's files as assets (or convert the model by its path)"
    );
    let assets = Assets::from_files([("y.xml".to_string(), b"<mujoco/>".to_vec())]);
    let message = error(with_include, Some(&assets));
    assert!(
        message.starts_with("line 2: <include>: \"x.xml\": assets: no file \"x.xml\""),
        "{message}"
    );
    let wrong_root = Assets::from_files([("x.xml".to_string(), b"<robot/>".to_vec())]);
    assert_eq!(
        error(with_include, Some(&wrong_root)),
        "line 2: <include>: \"x.xml\": the root element must be <mujoco> or <mujocoinclude>, got <robot>"
    );
    let mut cycle =
        |_: &str| Ok("<mujocoinclude><include file=\"x.xml\"/></mujocoinclude>".to_string());
    let message = expand_includes(with_include, &mut cycle)
        .unwrap_err()
        .to_string();
    assert!(
        message.ends_with("includes nest deeper than 8 (a cycle?)"),
        "{message}"
    );
}
