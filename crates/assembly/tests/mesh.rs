//! Mesh primitives: a hull has the volume and centroid of the solid it encloses, a
//! decomposition follows a concave shape, and every bad mesh is refused with its path.

use gymfleet_assembly::{parse, Shape};
use serde_json::{json, Value};

fn document(primitive: Value) -> String {
    json!({
        "parts": [{"name": "m", "primitive": primitive}],
        "assembly": {"instances": [{"part": "m", "name": "m"}]}
    })
    .to_string()
}

/// The 8 corners of an `x × y × z` mm box at `origin`, and its 12 triangles.
fn box_mesh(origin: [f64; 3], size: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut v = Vec::new();
    for i in 0..8 {
        v.push([
            origin[0] + size[0] * f64::from(i & 1),
            origin[1] + size[1] * f64::from((i >> 1) & 1),
            origin[2] + size[2] * f64::from((i >> 2) & 1),
        ]);
    }
    let t = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    (v, t)
}

fn convex(text: &str) -> std::sync::Arc<gymfleet_assembly::ConvexParts> {
    match parse(text).expect("parses").instances[0].shape.clone() {
        Shape::Convex(parts) => parts,
        other => panic!("a mesh, got {other:?}"),
    }
}

#[test]
fn a_hull_of_a_boxs_corners_is_the_box() {
    let (mut vertices, _) = box_mesh([0.0; 3], [100.0, 50.0, 20.0]);
    vertices.push([50.0, 25.0, 10.0]); // inside: not on the hull
    let parts = convex(&document(json!({"type": "mesh", "vertices": vertices})));
    assert_eq!(parts.pieces.len(), 1);
    assert_eq!(parts.pieces[0].vertices.len(), 8);
    assert!((parts.volume() - 1e-4).abs() < 1e-10, "{}", parts.volume());
    let c = parts.centroid();
    assert!(
        (c[0] - 0.05).abs() < 1e-9 && (c[1] - 0.025).abs() < 1e-9 && (c[2] - 0.01).abs() < 1e-9,
        "{c:?}"
    );
    assert!((parts.min_extent() - 0.02).abs() < 1e-9);
    // `scale` multiplies the coordinates (here into a 10× larger box).
    let scaled = convex(&document(
        json!({"type": "mesh", "vertices": vertices, "scale": {"x": 10, "y": 10, "z": 10}}),
    ));
    assert!((scaled.volume() - 0.1).abs() < 1e-7, "{}", scaled.volume());
}

#[test]
fn a_decomposition_follows_an_l_shape_that_its_hull_fills_in() {
    // An L: a 100×20×20 bar and a 20×20×80 post on its end, as one closed mesh made of
    // two closed boxes (V-HACD voxelises the solid they enclose).
    let (mut v, mut t) = box_mesh([0.0; 3], [100.0, 20.0, 20.0]);
    let (v2, t2) = box_mesh([0.0, 0.0, 20.0], [20.0, 20.0, 80.0]);
    t.extend(t2.iter().map(|tri| tri.map(|i| i + 8)));
    v.extend(v2);
    let solid = (100.0 * 20.0 * 20.0 + 20.0 * 20.0 * 80.0) * 1e-9;
    let hull = convex(&document(
        json!({"type": "mesh", "vertices": v, "indices": t}),
    ));
    // The hull's section is the pentagon (0,0) (100,0) (100,20) (20,100) (0,100): 6800 mm².
    let filled = 6800.0 * 20.0 * 1e-9;
    assert!(
        (hull.volume() - filled).abs() < 1e-12,
        "the hull fills the L in: {}",
        hull.volume()
    );
    let parts = convex(&document(
        json!({"type": "mesh", "vertices": v, "indices": t, "convex": "decomposition"}),
    ));
    assert!(parts.pieces.len() >= 2, "{} parts", parts.pieces.len());
    // V-HACD works on voxels (1.6 mm here), whose hulls stand a little proud of the
    // surface: 21 % over the solid's volume on this thin L, against the hull's 89 %.
    assert!(
        (parts.volume() - solid).abs() / solid < 0.25 && parts.volume() < 0.7 * hull.volume(),
        "decomposed volume {} against {solid} (hull {})",
        parts.volume(),
        hull.volume()
    );
}

#[test]
fn bad_meshes_are_refused_with_their_paths() {
    let (v, t) = box_mesh([0.0; 3], [10.0, 10.0, 10.0]);
    let flat = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let many: Vec<[f64; 3]> = (0..=gymfleet_assembly::MAX_MESH_VERTICES)
        .map(|i| [i as f64, 0.0, 0.0])
        .collect();
    let cases = [
        (
            json!({"type": "mesh", "vertices": flat}),
            "parts[0].primitive: the vertices span no volume (fewer than 4 of them, or all on one plane)",
        ),
        (
            json!({"type": "mesh", "vertices": v, "indices": [[0, 1, 8]]}),
            "parts[0].primitive.indices[0]: vertex index 8 is out of range: the mesh has 8 vertices",
        ),
        (
            json!({"type": "mesh", "vertices": v, "convex": "decomposition"}),
            "parts[0].primitive: a decomposition needs the mesh's `indices` (its triangles)",
        ),
        (
            json!({"type": "mesh", "vertices": many}),
            "parts[0].primitive.vertices: a mesh may have at most 65536 vertices, got 65537",
        ),
        (
            json!({"type": "mesh", "vertices": [[0, 0, 0], [1e7, 0, 0], [0, 1, 0], [0, 0, 1]]}),
            "parts[0].primitive.vertices[1]: expected coordinates within ±1e6 mm, got [10000000, 0, 0]",
        ),
        (
            json!({"type": "mesh", "vertices": v, "scale": {"x": 0, "y": 1, "z": 1}}),
            "parts[0].primitive.scale.x: expected a finite, non-zero factor within ±1e6, got 0",
        ),
        (
            json!({"type": "mesh", "vertices": v, "indices": t, "convex": "voxels"}),
            "parts[0].primitive.convex: unknown variant `voxels`, expected `hull` or `decomposition`",
        ),
        (
            json!({"type": "mesh"}),
            "a mesh needs `vertices` (and `indices`) or a `file` of the assets",
        ),
        (
            json!({"type": "mesh", "vertices": v, "radius": 3}),
            "parts[0].primitive: unknown field `radius`, expected one of `vertices`, `indices`, `convex`, `file`, `scale`",
        ),
        (
            json!({"type": "mesh", "file": "arm.stl"}),
            "parts[0].primitive.file: \"arm.stl\": a mesh file is read from the request's assets",
        ),
    ];
    for (primitive, expected) in cases {
        let err = parse(&document(primitive.clone()))
            .expect_err("refused")
            .to_string();
        assert!(
            err.contains(expected),
            "expected {expected:?} in {err:?} for {primitive}"
        );
    }
}
