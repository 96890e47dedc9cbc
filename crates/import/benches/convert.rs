//! Criterion benchmarks of imports (BENCHMARKS.md H2): converting descriptions nobody here
//! wrote into assembly JSON, meshes included, and what a server then does with the result
//! (parse and validate it; build an env). Gymnasium's Reacher and Ant (MJCF, primitives;
//! the Ant has a floating base), example-robot-data's UR5 (URDF, 7 STL meshes) and Kinova
//! Jaco 2 (URDF, 11 COLLADA meshes). The assets are read into memory first; reading a
//! request's archive is measured separately (a tar of the UR5's meshes), and so is a convex
//! decomposition (V-HACD) of one UR5 mesh, which validation computes. Each document's size
//! is printed.
#![allow(missing_docs)]

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use gymfleet_env::{EnvConfig, RobotEnv};
use gymfleet_import::{to_json, Assets, Format};

const REACHER: &str = include_str!("../tests/data/reacher.xml");
const ANT: &str = include_str!("../tests/data/ant.xml");
const UR5: &str =
    include_str!("../tests/data/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf");
const KINOVA: &str =
    include_str!("../tests/data/example-robot-data/robots/kinova_description/robots/kinova.urdf");

fn ur5_tar() -> Vec<u8> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/example-robot-data/robots/ur_description/meshes/ur5/collision");
    let mut out = tar::Builder::new(Vec::new());
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        let name = format!(
            "example-robot-data/robots/ur_description/meshes/ur5/collision/{}",
            path.file_name().unwrap().to_string_lossy()
        );
        out.append_path_with_name(&path, name).unwrap();
    }
    out.into_inner().unwrap()
}

fn bench_convert(c: &mut Criterion) {
    let assets =
        Assets::from_dir(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")).unwrap();
    let mut group = c.benchmark_group("import");
    for (name, text, format) in [
        ("reacher", REACHER, Format::Mjcf),
        ("ant", ANT, Format::Mjcf),
        ("ur5", UR5, Format::Urdf),
        ("kinova", KINOVA, Format::Urdf),
    ] {
        let (json, _) = to_json(text, format, Some(&assets)).unwrap();
        println!(
            "import/{name}: {} bytes of description, {} bytes of assembly JSON",
            text.len(),
            json.len()
        );
        group.bench_function(format!("convert/{name}"), |b| {
            b.iter(|| to_json(text, format, Some(&assets)).unwrap())
        });
        group.bench_function(format!("parse/{name}"), |b| {
            b.iter(|| gymfleet_assembly::parse(&json).unwrap())
        });
        group.bench_function(format!("build/{name}"), |b| {
            b.iter(|| RobotEnv::from_json(&json, EnvConfig::default()).unwrap())
        });
    }
    let tar = ur5_tar();
    println!(
        "import/assets: a tar of the UR5's 7 meshes, {} bytes",
        tar.len()
    );
    group.bench_function("assets/ur5-tar", |b| {
        b.iter(|| Assets::from_archive(&tar).unwrap())
    });
    // One mesh part made convex by decomposition at validation: the UR5's upper arm.
    for (name, convex) in [("hull", "hull"), ("decomposition", "decomposition")] {
        let document = serde_json::json!({
            "parts": [{"name": "Link", "primitive": {"type": "mesh", "convex": convex,
                "file": "example-robot-data/robots/ur_description/meshes/ur5/collision/upperarm.stl",
                "scale": {"x": 1000, "y": 1000, "z": 1000}}}],
            "assembly": {"instances": [{"part": "Link", "name": "link"}]}
        })
        .to_string();
        let (json, _) = to_json(&document, Format::Json, Some(&assets)).unwrap();
        let parts = gymfleet_assembly::parse(&json).unwrap();
        println!(
            "import/{name}: the UR5 upper arm's mesh, {} bytes of assembly JSON, shape {}",
            json.len(),
            match &parts.instances[0].shape {
                gymfleet_assembly::Shape::Convex(c) => format!("{} convex parts", c.pieces.len()),
                other => format!("{other:?}"),
            }
        );
        group.bench_function(format!("parse/ur5-upperarm-{name}"), |b| {
            b.iter(|| gymfleet_assembly::parse(&json).unwrap())
        });
    }
    // The worst case a request may ask for: a decomposition of a mesh at the triangle cap
    // (32 768), a torus of 128 × 128 quads (R = 100 mm, r = 30 mm).
    let (n, big, small) = (128usize, 100.0f64, 30.0f64);
    let mut vertices = Vec::with_capacity(n * n);
    let mut indices = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        let u = i as f64 / n as f64 * std::f64::consts::TAU;
        for j in 0..n {
            let v = j as f64 / n as f64 * std::f64::consts::TAU;
            let ring = big + small * v.cos();
            vertices.push([ring * u.cos(), ring * u.sin(), small * v.sin() + 200.0]);
            let (a, b) = (i * n + j, i * n + (j + 1) % n);
            let (c, d) = (((i + 1) % n) * n + j, ((i + 1) % n) * n + (j + 1) % n);
            indices.push([a, c, b]);
            indices.push([b, c, d]);
        }
    }
    let torus = serde_json::json!({
        "parts": [{"name": "Torus", "primitive": {"type": "mesh", "convex": "decomposition",
            "vertices": vertices, "indices": indices}}],
        "assembly": {"instances": [{"part": "Torus", "name": "torus"}]}
    })
    .to_string();
    println!(
        "import/torus: {} triangles, {} bytes of JSON",
        indices.len(),
        torus.len()
    );
    group.sample_size(10);
    group.bench_function("parse/torus-32768-decomposition", |b| {
        b.iter(|| gymfleet_assembly::parse(&torus).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench_convert);
criterion_main!(benches);
