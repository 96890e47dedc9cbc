//! Pictures: [`Camera`], [`Image`], and `render` on an [`Env`] or a [`Batch`]'s env.

use gymfleet_proto::v1 as pb;

use crate::{Batch, Env, Result};

/// A camera's viewing direction when no eye is given; it frames the robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CameraPreset {
    /// From the front-right and above (+x, −y, +z).
    #[default]
    Iso,
    /// From −y, looking along +y.
    Front,
    /// From +x, looking along −x.
    Side,
    /// From above, looking down −z.
    Top,
}

/// Where a picture is taken from (docs/design.md §6.5). The default frames the whole robot
/// from the `iso` direction in perspective.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Camera {
    /// The viewing direction when `eye` is not given.
    pub preset: CameraPreset,
    /// The camera's position, world mm; derived from the preset when `None`.
    pub eye: Option<[f64; 3]>,
    /// The point looked at, world mm; the robot's centre when `None`.
    pub target: Option<[f64; 3]>,
    /// Vertical field of view, degrees, (0, 170]; 0 means 45.
    pub fov_deg: f32,
    /// A parallel projection that frames the robot.
    pub orthographic: bool,
}

impl Camera {
    /// A preset camera.
    pub fn preset(preset: CameraPreset) -> Camera {
        Camera {
            preset,
            ..Camera::default()
        }
    }
}

/// A rendered picture.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// An 8-bit RGB PNG file.
    pub png: Vec<u8>,
    /// Pixels.
    pub width: u32,
    /// Pixels.
    pub height: u32,
    /// What it shows, in words (camera, grid spacing, markers, positions).
    pub description: String,
    /// The distance between two ground-grid lines, mm.
    pub grid_mm: f32,
}

impl From<pb::Image> for Image {
    fn from(i: pb::Image) -> Self {
        Image {
            png: i.png,
            width: i.width,
            height: i.height,
            description: i.description,
            grid_mm: i.grid_mm,
        }
    }
}

/// The request for a picture of `env_id`, or of env `env_index` of `batch_id`.
fn request(
    env_id: &str,
    batch_id: &str,
    env_index: usize,
    c: &Camera,
    width: u32,
    height: u32,
) -> pb::RenderRequest {
    pb::RenderRequest {
        env_id: env_id.to_string(),
        batch_id: batch_id.to_string(),
        env_index: u32::try_from(env_index).unwrap_or(u32::MAX),
        camera: Some(camera(c)),
        width,
        height,
    }
}

fn camera(c: &Camera) -> pb::Camera {
    let point = |p: Option<[f64; 3]>| p.map(|[x, y, z]| pb::Vec3 { x, y, z });
    pb::Camera {
        preset: match c.preset {
            CameraPreset::Iso => pb::CameraPreset::Iso,
            CameraPreset::Front => pb::CameraPreset::Front,
            CameraPreset::Side => pb::CameraPreset::Side,
            CameraPreset::Top => pb::CameraPreset::Top,
        } as i32,
        eye: point(c.eye),
        target: point(c.target),
        fov_deg: c.fov_deg,
        orthographic: c.orthographic,
    }
}

impl Env {
    /// A PNG picture of the env as it is now, `width × height` pixels (0 × 0 for 320 × 240;
    /// 16 to 2048 each). A bad size or camera is [`crate::ClientError::InvalidArgument`].
    pub async fn render(&self, camera: &Camera, width: u32, height: u32) -> Result<Image> {
        let request = request(self.id(), "", 0, camera, width, height);
        Ok(self.client.rpc().render(request).await?.into_inner().into())
    }
}

impl Batch {
    /// [`Env::render`] for env `env_index` of the batch.
    pub async fn render(
        &self,
        env_index: usize,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<Image> {
        let request = request("", self.id(), env_index, camera, width, height);
        Ok(self.client.rpc().render(request).await?.into_inner().into())
    }
}

/// A part's shape, centred on its pose's origin (a mesh: in its pose's frame), mm.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneShape {
    /// A box: half its size along its frame's x, y, z.
    Box {
        /// Half extents.
        half_extents: [f64; 3],
    },
    /// A cylinder along its frame's y.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Half its length.
        half_height: f64,
    },
    /// A sphere.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// A capsule along its frame's y.
    Capsule {
        /// Radius.
        radius: f64,
        /// Half the length between the caps' centres.
        half_segment: f64,
    },
    /// A convex polyhedron (a mesh's hull, or one part of its decomposition).
    Mesh {
        /// Vertices in the pose's frame.
        vertices: Vec<[f32; 3]>,
        /// Three indices into `vertices` per triangle, counter-clockwise seen from outside.
        triangles: Vec<[u32; 3]>,
    },
}

/// One part of the robot where it is now.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneBody {
    /// Its instance's name.
    pub name: String,
    /// Its shape.
    pub shape: SceneShape,
    /// The shape's centre, world mm.
    pub position: [f64; 3],
    /// Its orientation, `[qw, qx, qy, qz]`.
    pub rotation: [f64; 4],
}

/// A joint's anchor (world mm) and unit axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneJoint {
    /// World mm.
    pub anchor: [f64; 3],
    /// A unit vector.
    pub axis: [f64; 3],
}

/// What an env looks like now: enough to draw it (docs/design.md §6.5 `GetScene`).
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Every part.
    pub bodies: Vec<SceneBody>,
    /// Joints with at least one DOF, in document order.
    pub joints: Vec<SceneJoint>,
    /// Each end effector's position, world mm.
    pub end_effectors: Vec<[f64; 3]>,
    /// A reach task's current target, world mm.
    pub target: Option<[f64; 3]>,
}

fn malformed(what: &str) -> crate::ClientError {
    crate::ClientError::Protocol {
        message: format!("malformed Scene from the server: {what} missing"),
        code: tonic::Code::Ok,
    }
}

fn point(v: Option<pb::Vec3>, what: &str) -> Result<[f64; 3]> {
    v.map(|v| [v.x, v.y, v.z]).ok_or_else(|| malformed(what))
}

/// A mesh's flat arrays as vertices and triangles, each index checked.
fn mesh(m: pb::SceneMesh) -> Result<SceneShape> {
    let (vertices, rest) = m.vertices.as_chunks::<3>();
    let (triangles, tail) = m.triangles.as_chunks::<3>();
    let n = vertices.len() as u32;
    if !rest.is_empty() || !tail.is_empty() || triangles.iter().flatten().any(|&i| i >= n) {
        return Err(malformed(
            "a well-formed mesh (whole vertices and triangles, indices in range)",
        ));
    }
    Ok(SceneShape::Mesh {
        vertices: vertices.to_vec(),
        triangles: triangles.to_vec(),
    })
}

impl TryFrom<pb::Scene> for Scene {
    type Error = crate::ClientError;

    fn try_from(s: pb::Scene) -> Result<Self> {
        use pb::scene_shape::Kind;
        let bodies = s
            .bodies
            .into_iter()
            .map(|b| {
                let shape = match b.shape.and_then(|s| s.kind) {
                    Some(Kind::BoxHalfExtents(h)) => SceneShape::Box {
                        half_extents: [h.x, h.y, h.z],
                    },
                    Some(Kind::Cylinder(c)) => SceneShape::Cylinder {
                        radius: c.radius,
                        half_height: c.half_height,
                    },
                    Some(Kind::SphereRadius(radius)) => SceneShape::Sphere { radius },
                    Some(Kind::Capsule(c)) => SceneShape::Capsule {
                        radius: c.radius,
                        half_segment: c.half_segment,
                    },
                    Some(Kind::Mesh(m)) => mesh(m)?,
                    None => return Err(malformed("a body's shape")),
                };
                let pose = b.pose.ok_or_else(|| malformed("a body's pose"))?;
                Ok(SceneBody {
                    name: b.name,
                    shape,
                    position: point(pose.position, "a body's position")?,
                    rotation: [pose.qw, pose.qx, pose.qy, pose.qz],
                })
            })
            .collect::<Result<_>>()?;
        let joints = s
            .joints
            .into_iter()
            .map(|j| {
                Ok(SceneJoint {
                    anchor: point(j.anchor, "a joint's anchor")?,
                    axis: point(j.axis, "a joint's axis")?,
                })
            })
            .collect::<Result<_>>()?;
        Ok(Scene {
            bodies,
            joints,
            end_effectors: s
                .end_effectors
                .into_iter()
                .map(|p| [p.x, p.y, p.z])
                .collect(),
            target: s.target.map(|p| [p.x, p.y, p.z]),
        })
    }
}

impl Env {
    /// The env's shapes and poses now, to draw it yourself (an HTML replay, a plot).
    pub async fn scene(&self) -> Result<Scene> {
        self.client
            .rpc()
            .get_scene(self.env_ref())
            .await?
            .into_inner()
            .try_into()
    }
}
