//! Shapes to triangles in world mm (parry's tessellations of balls, capsules, cuboids,
//! cylinders; meshes as they are), one [`Mesh`] per part.

use gymfleet_env::{Scene, SceneShape};
use rapier3d::math::{Rotation, Vector};
use rapier3d::parry::shape::{Ball, Capsule, Cuboid, Cylinder};

pub(crate) fn vec(v: [f32; 3]) -> Vector {
    Vector::new(v[0], v[1], v[2])
}

/// One part's triangles in world mm.
pub(crate) struct Mesh {
    pub(crate) instance: usize,
    pub(crate) vertices: Vec<Vector>,
    pub(crate) triangles: Vec<[u32; 3]>,
}

pub(crate) fn tessellate(scene: &Scene) -> Vec<Mesh> {
    scene
        .parts
        .iter()
        .map(|part| {
            let (vertices, mut triangles) = match part.shape {
                SceneShape::Mesh {
                    ref vertices,
                    ref triangles,
                } => (
                    vertices.iter().copied().map(vec).collect(),
                    triangles.to_vec(),
                ),
                SceneShape::Cuboid { half_extents } => Cuboid::new(vec(half_extents)).to_trimesh(),
                SceneShape::Cylinder {
                    radius,
                    half_height,
                } => Cylinder::new(half_height, radius).to_trimesh(32),
                SceneShape::Ball { radius } => Ball::new(radius).to_trimesh(12, 24),
                SceneShape::Capsule {
                    radius,
                    half_segment,
                } => Capsule::new_y(half_segment, radius).to_trimesh(24, 8),
            };
            // Every shape is convex: a face whose normal points towards the shape's
            // inside (its vertices' mean) is wound inwards.
            let inside = vertices.iter().copied().sum::<Vector>() / vertices.len().max(1) as f32;
            for tri in &mut triangles {
                let [a, b, c] = tri.map(|i| vertices[i as usize]);
                if (b - a).cross(c - a).dot(a + b + c - 3.0 * inside) < 0.0 {
                    tri.swap(1, 2);
                }
            }
            let [w, x, y, z] = part.rotation;
            let rotation = Rotation::from_xyzw(x, y, z, w).normalize();
            let origin = vec(part.position);
            Mesh {
                instance: part.instance,
                vertices: vertices
                    .into_iter()
                    .map(|v| origin + rotation * v)
                    .collect(),
                triangles,
            }
        })
        .collect()
}
