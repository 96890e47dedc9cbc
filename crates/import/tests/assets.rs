//! Assets archives (zip, tar, tar.gz) resolve a description's mesh files, under bounds;
//! bad archives and missing files get precise errors.

use std::io::Write;

use gymfleet_import::{to_json, Assets, Format, MAX_ASSET_BYTES};

const UR5: &str = include_str!("data/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf");
const MESH_DIR: &str = "example-robot-data/robots/ur_description/meshes/ur5/collision";

/// The UR5's collision meshes, by their path from the archive's root.
fn ur5_meshes() -> Vec<(String, Vec<u8>)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(MESH_DIR);
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
        .expect("the test data")
        .map(|e| {
            let e = e.unwrap();
            let name = format!("{MESH_DIR}/{}", e.file_name().to_string_lossy());
            (name, std::fs::read(e.path()).unwrap())
        })
        .collect();
    files.sort();
    files
}

fn zip(files: &[(String, Vec<u8>)]) -> Vec<u8> {
    let mut out = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .large_file(true);
    for (name, bytes) in files {
        out.start_file(name.as_str(), options).unwrap();
        out.write_all(bytes).unwrap();
    }
    out.finish().unwrap().into_inner()
}

fn tar(files: &[(String, Vec<u8>)]) -> Vec<u8> {
    let mut out = tar::Builder::new(Vec::new());
    for (name, bytes) in files {
        let mut header = tar::Header::new_gnu();
        header.set_size(bytes.len() as u64);
        header.set_mode(0o644);
        header.set_cksum();
        out.append_data(&mut header, name, bytes.as_slice())
            .unwrap();
    }
    out.into_inner().unwrap()
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut out = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    out.write_all(bytes).unwrap();
    out.finish().unwrap()
}

#[test]
fn zip_tar_and_tar_gz_give_the_same_document() {
    let files = ur5_meshes();
    assert_eq!(files.len(), 7);
    let from_dir = {
        let assets = Assets::from_files(files.clone());
        to_json(UR5, Format::Urdf, Some(&assets))
            .expect("converts")
            .0
    };
    for archive in [zip(&files), tar(&files), gzip(&tar(&files))] {
        let assets = Assets::from_archive(&archive).expect("reads");
        assert_eq!(assets.len(), 7);
        let (document, _) = to_json(UR5, Format::Urdf, Some(&assets)).expect("converts");
        assert_eq!(document, from_dir);
    }
    // Meshes are inlined: the document is self-contained and names no file.
    assert!(
        !from_dir.contains("\"file\""),
        "a file left in the document"
    );
    gymfleet_assembly::parse(&from_dir).expect("parses");
}

#[test]
fn package_paths_resolve_from_a_root_above_or_below_the_package() {
    // The archive's root is the UR's package folder itself: `meshes/ur5/collision/…`.
    let files: Vec<(String, Vec<u8>)> = ur5_meshes()
        .into_iter()
        .map(|(name, bytes)| {
            (
                name.replace("example-robot-data/robots/ur_description/", ""),
                bytes,
            )
        })
        .collect();
    let assets = Assets::from_archive(&zip(&files)).expect("reads");
    to_json(UR5, Format::Urdf, Some(&assets)).expect("resolves below the package");
    // …or a folder above it.
    let files: Vec<(String, Vec<u8>)> = ur5_meshes()
        .into_iter()
        .map(|(name, bytes)| (format!("share/{name}"), bytes))
        .collect();
    let assets = Assets::from_archive(&tar(&files)).expect("reads");
    to_json(UR5, Format::Urdf, Some(&assets)).expect("resolves above the package");
}

#[test]
fn a_missing_mesh_names_the_file_and_what_the_archive_holds() {
    let mut files = ur5_meshes();
    files.retain(|(name, _)| !name.ends_with("forearm.stl"));
    let assets = Assets::from_archive(&zip(&files)).expect("reads");
    let err = to_json(UR5, Format::Urdf, Some(&assets)).expect_err("forearm.stl is missing");
    let message = err.to_string();
    assert!(
        message.starts_with("parts[")
            && message.contains(".primitive.file: assets: no file \"package://example-robot-data/robots/ur_description/meshes/ur5/collision/forearm.stl\" in the archive")
            && message.contains("it holds 6 files"),
        "{message}"
    );
}

#[test]
fn mesh_files_without_assets_are_refused_by_the_validator_naming_the_file() {
    let (document, _) = to_json(UR5, Format::Urdf, None).expect("converts without reading meshes");
    let err = gymfleet_assembly::parse(&document).expect_err("no assets");
    let message = err.to_string();
    assert!(
        message.contains(".primitive.file: \"package://example-robot-data/robots/ur_description/meshes/ur5/collision/base.stl\": a mesh file is read from the request's assets"),
        "{message}"
    );
}

#[test]
fn a_zip_bomb_stops_at_the_bound() {
    // 80 MiB of zeros deflate to about 80 kB.
    let bomb = zip(&[(
        "zeros.stl".to_string(),
        vec![0u8; (MAX_ASSET_BYTES + (16 << 20)) as usize],
    )]);
    assert!(bomb.len() < 1 << 20, "{} bytes", bomb.len());
    let err = Assets::from_archive(&bomb).expect_err("too big once inflated");
    assert_eq!(
        err.to_string(),
        "assets: the archive's files hold more than 64 MiB uncompressed (at \"zeros.stl\")"
    );
}

#[test]
fn bad_archives_are_refused_precisely() {
    let err = Assets::from_archive(b"not an archive at all").expect_err("no archive");
    assert_eq!(
        err.to_string(),
        "assets: expected a zip, tar or tar.gz archive; the 21 bytes given are none of these"
    );
    let err = Assets::from_archive(b"PK\x03\x04 truncated").expect_err("a broken zip");
    assert!(
        err.to_string()
            .starts_with("assets: not a readable zip archive: "),
        "{err}"
    );
    let escape = zip(&[("../../etc/passwd".to_string(), b"x".to_vec())]);
    let err = Assets::from_archive(&escape).expect_err("escapes the root");
    assert_eq!(
        err.to_string(),
        "assets: \"../../etc/passwd\" escapes the archive's root (absolute, or with ..)"
    );
    // The same in a tar, its name field written as a hostile client would.
    let mut header = tar::Header::new_gnu();
    header.set_size(1);
    header.as_old_mut().name[..12].copy_from_slice(b"../../x.stl\0");
    header.set_cksum();
    let mut out = tar::Builder::new(Vec::new());
    out.append(&header, &b"x"[..]).unwrap();
    let err = Assets::from_archive(&out.into_inner().unwrap()).expect_err("escapes the root");
    assert_eq!(
        err.to_string(),
        "assets: \"../../x.stl\" escapes the archive's root (absolute, or with ..)"
    );
    let many: Vec<(String, Vec<u8>)> = (0..=gymfleet_import::MAX_ASSET_FILES)
        .map(|i| (format!("f{i}"), Vec::new()))
        .collect();
    let err = Assets::from_archive(&tar(&many)).expect_err("too many files");
    assert_eq!(
        err.to_string(),
        "assets: more than 4096 files in the archive"
    );
}

#[test]
fn a_mesh_file_that_is_not_a_mesh_is_named() {
    let json = r#"{"parts": [{"name": "p", "primitive": {"type": "mesh", "file": "m/p.stl"}}],
                   "assembly": {"instances": [{"part": "p", "name": "p"}]}}"#;
    let assets = Assets::from_files([("m/p.stl".to_string(), b"solid nothing\nendsolid".to_vec())]);
    let err = to_json(json, Format::Json, Some(&assets)).expect_err("no vertices");
    assert_eq!(
        err.to_string(),
        "parts[0].primitive.file: \"m/p.stl\" holds no vertices"
    );
    let assets = Assets::from_files([("m/p.stl".to_string(), b"x".to_vec())]);
    let json = json.replace("m/p.stl", "m/p.ply");
    let assets2 = Assets::from_files([("m/p.ply".to_string(), b"ply".to_vec())]);
    let err = to_json(&json, Format::Json, Some(&assets2)).expect_err("not a mesh kind we read");
    assert_eq!(
        err.to_string(),
        "parts[0].primitive.file: \"m/p.ply\": expected a mesh file ending in .stl, .obj or .dae"
    );
    drop(assets);
}

/// A tetrahedron in OBJ and in COLLADA (in centimetres: `<unit meter="0.01">`), both read.
#[test]
fn obj_and_collada_meshes_are_read() {
    let obj = "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    let (vertices, triangles) =
        gymfleet_import::load_mesh(obj.as_bytes(), "t.obj").expect("an OBJ");
    assert_eq!(triangles.len(), 4);
    let mut distinct: Vec<[f32; 3]> = vertices.clone();
    distinct.sort_by(|a, b| a.partial_cmp(b).unwrap());
    distinct.dedup();
    assert_eq!(
        distinct,
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 10.0],
            [0.0, 10.0, 0.0],
            [10.0, 0.0, 0.0]
        ]
    );
    let dae = r##"<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="12">0 0 0 10 0 0 0 10 0 0 0 10</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="4"><input semantic="VERTEX" source="#v" offset="0"/><p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##;
    let (vertices, triangles) = gymfleet_import::load_mesh(dae.as_bytes(), "t.dae").expect("a DAE");
    assert_eq!(triangles.len(), 4);
    let far = vertices.iter().flatten().fold(0f32, |m, c| m.max(c.abs()));
    assert!((far - 0.1).abs() < 1e-6, "10 cm in metres: {far}");
}

/// A binary STL whose header starts with "solid" (Solo 12's feet in example-robot-data)
/// and whose triangle count's first byte is a newline fools an ASCII parse into reading
/// the triangles as text; its exact binary size makes it read as binary.
#[test]
fn a_binary_stl_with_a_solid_header_is_read_as_binary() {
    let mut stl = b"solid foot".to_vec();
    stl.resize(80, b' ');
    let triangles = 10u32; // 0x0A: a newline right after the header
    stl.extend(triangles.to_le_bytes());
    for k in 0..triangles {
        let z = k as f32;
        stl.extend([0f32, 0.0, 1.0].iter().flat_map(|v| v.to_le_bytes()));
        for v in [[0.0, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]] {
            stl.extend(v.iter().flat_map(|c: &f32| c.to_le_bytes()));
        }
        stl.extend([0u8, 0]);
    }
    assert_eq!(stl.len(), 84 + 50 * 10);
    let (vertices, faces) = gymfleet_import::load_mesh(&stl, "foot.stl").expect("binary STL");
    assert_eq!(faces.len(), 10);
    assert!(vertices.iter().any(|v| v[2] == 9.0), "{vertices:?}");
    // Not a binary STL's size: the ASCII parser's error stands.
    let err = gymfleet_import::load_mesh(&stl[..500], "foot.stl").unwrap_err();
    assert!(err.contains("\"foot.stl\" is not a readable mesh"), "{err}");
}
