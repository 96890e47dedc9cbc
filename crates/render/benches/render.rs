//! What a picture costs: the seed arms at 320 × 240 (the default) and 640 × 480, with and
//! without the PNG encoding.

use criterion::{criterion_group, criterion_main, Criterion};
use gymfleet_env::{EnvConfig, RobotEnv};
use gymfleet_render::{render, Camera};

fn pictures(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    for (name, document) in [
        ("arm2", include_str!("../../../models/arm2.json")),
        ("arm6", include_str!("../../../models/arm6.json")),
    ] {
        let scene = RobotEnv::from_json(document, EnvConfig::default())
            .expect("a seed model")
            .scene();
        let camera = Camera::default();
        for (w, h) in [(320, 240), (640, 480)] {
            group.bench_function(format!("{name}/{w}x{h}/rgb"), |b| {
                b.iter(|| render(&scene, &camera, w, h).expect("render"))
            });
            group.bench_function(format!("{name}/{w}x{h}/png"), |b| {
                b.iter(|| render(&scene, &camera, w, h).expect("render").to_png())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, pictures);
criterion_main!(benches);
