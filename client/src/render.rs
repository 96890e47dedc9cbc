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

/// Where a picture is taken from (PRODUCT.md §6.5). The default frames the whole robot
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
        let request = pb::RenderRequest {
            env_id: self.id().to_string(),
            camera: Some(self::camera(camera)),
            width,
            height,
            ..Default::default()
        };
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
        let request = pb::RenderRequest {
            batch_id: self.id().to_string(),
            env_index: u32::try_from(env_index).unwrap_or(u32::MAX),
            camera: Some(self::camera(camera)),
            width,
            height,
            ..Default::default()
        };
        Ok(self.client.rpc().render(request).await?.into_inner().into())
    }
}
