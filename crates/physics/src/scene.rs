//! The robot's shapes and joints as they are now, in world millimetres, for drawing it
//! (rendering, replays). Read from the live Rapier sets; nothing here changes the world.

use std::sync::Arc;

use rapier3d::math::{Pose, Real, Vector};
use rapier3d::parry::shape::{HeightField, Shape, ShapeType};

use crate::units::to_mm;
use crate::world::RobotWorld;

/// One primitive, in its own frame (see [`ScenePart`]), millimetres.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneShape {
    /// A box centred on its frame's origin.
    Cuboid {
        /// Half the box's size along its frame's x, y, z.
        half_extents: [f32; 3],
    },
    /// A cylinder centred on its frame's origin, its axis along the frame's y.
    Cylinder {
        /// Radius.
        radius: f32,
        /// Half the length along the axis.
        half_height: f32,
    },
    /// A sphere centred on its frame's origin.
    Ball {
        /// Radius.
        radius: f32,
    },
    /// A capsule centred on its frame's origin, its axis along the frame's y.
    Capsule {
        /// Radius.
        radius: f32,
        /// Half the length of the axis segment between the caps' centres.
        half_segment: f32,
    },
    /// A convex polyhedron (a mesh's hull, or one part of its decomposition).
    Mesh {
        /// Vertices in the frame, mm.
        vertices: Arc<[[f32; 3]]>,
        /// Triangles, three indices into `vertices` each, counter-clockwise seen from outside.
        triangles: Arc<[[u32; 3]]>,
    },
}

/// A part of the robot: an instance's shape placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenePart {
    /// The instance it belongs to (document order).
    pub instance: usize,
    /// The shape, in the frame given by `position` and `rotation`.
    pub shape: SceneShape,
    /// The shape frame's origin, world mm.
    pub position: [f32; 3],
    /// The shape frame's orientation, `[qw, qx, qy, qz]`.
    pub rotation: [f32; 4],
}

/// A joint's anchor and axis (the first DOF's axis; a ball joint's frame x), world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneJoint {
    /// The anchor, world mm.
    pub anchor: [f32; 3],
    /// A unit vector.
    pub axis: [f32; 3],
}

fn mm(v: Vector) -> [f32; 3] {
    [v.x, v.y, v.z].map(|c| to_mm(f64::from(c)) as f32)
}

fn to_part(instance: usize, shape: SceneShape, pose: &Pose) -> ScenePart {
    let q = pose.rotation;
    ScenePart {
        instance,
        shape,
        position: mm(pose.translation),
        rotation: [q.w, q.x, q.y, q.z],
    }
}

/// A collider's shape in mm, if gymfleet builds shapes of its kind.
fn scene_shape(shape: &dyn Shape) -> Option<SceneShape> {
    let len = |v: f32| to_mm(f64::from(v)) as f32;
    Some(match shape.shape_type() {
        ShapeType::Cuboid => {
            let c = shape.as_cuboid()?;
            SceneShape::Cuboid {
                half_extents: [c.half_extents.x, c.half_extents.y, c.half_extents.z].map(len),
            }
        }
        ShapeType::Cylinder => {
            let c = shape.as_cylinder()?;
            SceneShape::Cylinder {
                radius: len(c.radius),
                half_height: len(c.half_height),
            }
        }
        ShapeType::Ball => SceneShape::Ball {
            radius: len(shape.as_ball()?.radius),
        },
        // Built along its frame's y (`capsule_y`), centred.
        ShapeType::Capsule => {
            let c = shape.as_capsule()?;
            SceneShape::Capsule {
                radius: len(c.radius),
                half_segment: len(c.half_height()),
            }
        }
        ShapeType::ConvexPolyhedron => {
            let (vertices, triangles) = shape.as_convex_polyhedron()?.to_trimesh();
            SceneShape::Mesh {
                vertices: vertices.into_iter().map(mm).collect(),
                triangles: triangles.into(),
            }
        }
        ShapeType::HeightField => {
            let (vertices, triangles) = heightfield_mesh(shape.as_heightfield()?);
            SceneShape::Mesh {
                vertices: vertices.into_iter().map(mm).collect(),
                triangles: triangles.into(),
            }
        }
        _ => return None,
    })
}

/// Most grid points along a side of a heightfield's drawn surface: a finer grid is drawn
/// every k-th row and column.
const DRAWN_SIDE: usize = 128;

/// A heightfield's surface as a mesh in its own frame (Parry's: heights along y), vertices
/// shared, at most [`DRAWN_SIDE`] points a side.
fn heightfield_mesh(field: &HeightField) -> (Vec<Vector>, Vec<[u32; 3]>) {
    let heights = field.heights();
    let (rows, columns) = (heights.nrows(), heights.ncols());
    let step = rows.max(columns).div_ceil(DRAWN_SIDE).max(1);
    // Every step-th line, and always the last.
    let lines = |n: usize| -> Vec<usize> {
        let mut at: Vec<usize> = (0..n).step_by(step).collect();
        if at.last() != Some(&(n - 1)) {
            at.push(n - 1);
        }
        at
    };
    let (is, js) = (lines(rows), lines(columns));
    let scale = field.scale();
    let mut vertices = Vec::with_capacity(is.len() * js.len());
    for &i in &is {
        for &j in &js {
            let h = heights.data()[heights.flat_index(i, j)];
            vertices.push(Vector::new(
                (j as Real / (columns - 1) as Real - 0.5) * scale.x,
                h * scale.y,
                (i as Real / (rows - 1) as Real - 0.5) * scale.z,
            ));
        }
    }
    let width = js.len() as u32;
    let mut triangles = Vec::with_capacity(2 * is.len() * js.len());
    for r in 0..is.len() as u32 - 1 {
        for c in 0..width - 1 {
            let (a, b) = (r * width + c, r * width + c + 1);
            let (d, e) = (a + width, b + width);
            triangles.push([a, d, b]);
            triangles.push([b, d, e]);
        }
    }
    (vertices, triangles)
}

impl RobotWorld {
    /// Every collider of every instance, where it is now (a decomposed mesh: each of its
    /// convex parts). Shapes gymfleet does not build (none today) are left out.
    pub fn scene_parts(&self) -> Vec<ScenePart> {
        let mut parts = Vec::with_capacity(self.bodies.len());
        for (instance, &co) in self.colliders.iter().enumerate() {
            let Some(co) = self.live.colliders.get(co) else {
                continue;
            };
            // A fused planar root's helper is drawn where the chain would hold it.
            let moved;
            let co_position = match self.planar_helper(instance) {
                Some(_) => {
                    let wrt = co.position_wrt_parent().copied().unwrap_or(Pose::IDENTITY);
                    moved = self.body_frame(instance) * wrt;
                    &moved
                }
                None => co.position(),
            };
            match co.shape().as_compound() {
                Some(compound) => {
                    for (pose, piece) in compound.shapes() {
                        if let Some(shape) = scene_shape(&**piece) {
                            parts.push(to_part(instance, shape, &(*co_position * *pose)));
                        }
                    }
                }
                None => {
                    if let Some(shape) = scene_shape(co.shape()) {
                        parts.push(to_part(instance, shape, co_position));
                    }
                }
            }
        }
        parts
    }

    /// Every document joint with at least one DOF, in document order.
    pub fn scene_joints(&self) -> Vec<SceneJoint> {
        self.joints
            .iter()
            .filter(|slot| slot.kind != gymfleet_assembly::JointType::Fixed)
            .map(|slot| {
                let frame = self.joint_frame_world(slot);
                let axis = frame.rotation * Vector::X;
                SceneJoint {
                    anchor: mm(frame.translation),
                    axis: [axis.x, axis.y, axis.z],
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::WorldOptions;

    const PENDULUM: &str = include_str!("../../../models/pendulum.json");

    #[test]
    fn parts_and_joints_are_in_world_millimetres() {
        let assembly = gymfleet_assembly::parse(PENDULUM).unwrap();
        let world = RobotWorld::new(&assembly, &WorldOptions::default()).unwrap();
        let parts = world.scene_parts();
        assert_eq!(parts.len(), 2);
        let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-3);
        // The base: a 20 × 20 × 5 mm box with its corner at the origin.
        assert_eq!(parts[0].instance, 0);
        assert_eq!(
            parts[0].shape,
            SceneShape::Cuboid {
                half_extents: [10.0, 10.0, 2.5]
            }
        );
        assert!(
            close(parts[0].position, [10.0, 10.0, 2.5]),
            "{:?}",
            parts[0].position
        );
        // The arm: 4 × 4 × 40 mm from (8, 8, 5).
        assert_eq!(
            parts[1].shape,
            SceneShape::Cuboid {
                half_extents: [2.0, 2.0, 20.0]
            }
        );
        assert!(
            close(parts[1].position, [10.0, 10.0, 25.0]),
            "{:?}",
            parts[1].position
        );
        let joints = world.scene_joints();
        assert_eq!(joints.len(), 1);
        assert!(
            close(joints[0].anchor, [10.0, 10.0, 5.0]),
            "{:?}",
            joints[0].anchor
        );
        assert!(
            close(joints[0].axis, [0.0, 1.0, 0.0]),
            "{:?}",
            joints[0].axis
        );
    }
}
