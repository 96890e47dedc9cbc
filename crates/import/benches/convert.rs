//! Criterion benchmarks of imports (BENCHMARKS.md H2): converting descriptions nobody here
//! wrote into assembly JSON, meshes included, and what a server then does with the result
//! (parse and validate it; build an env). Gymnasium's Reacher (MJCF, primitives),
//! example-robot-data's UR5 (URDF, 7 STL meshes) and Kinova Jaco 2 (URDF, 11 COLLADA
//! meshes). The assets are read into memory first; reading a request's archive is
//! measured separately (a tar of the UR5's meshes). Each document's size is printed.
#![allow(missing_docs)]

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use gymfleet_env::{EnvConfig, RobotEnv};
use gymfleet_import::{to_json, Assets, Format};

const REACHER: &str = include_str!("../tests/data/reacher.xml");
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
    group.finish();
}

criterion_group!(benches, bench_convert);
criterion_main!(benches);
