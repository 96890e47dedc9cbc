//! Cameras made concrete: the sphere that holds the scene ([`Bounds`]), and a [`View`]
//! (eye, target, axes, projection) that projects world mm to pixels.

use gymfleet_env::Scene;
use rapier3d::math::Vector;

use crate::tessellate::{vec, Mesh};
use crate::{Camera, RenderError, DEFAULT_FOV_DEG, MAX_FOV_DEG};

/// A sphere that holds the scene.
pub(crate) struct Bounds {
    pub(crate) centre: Vector,
    pub(crate) radius: f32,
}

impl Bounds {
    pub(crate) fn of(scene: &Scene, meshes: &[Mesh]) -> Bounds {
        let points = meshes
            .iter()
            .flat_map(|m| m.vertices.iter().copied())
            .chain(scene.end_effectors.iter().map(|&p| vec(p)))
            .chain(scene.target.map(vec));
        let (mut lo, mut hi) = (
            Vector::splat(f32::INFINITY),
            Vector::splat(f32::NEG_INFINITY),
        );
        for p in points.filter(|p| p.is_finite()) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        if !lo.is_finite() {
            return Bounds {
                centre: Vector::ZERO,
                radius: 100.0,
            };
        }
        // The ground plane (z = 0) belongs in the picture.
        lo.z = lo.z.min(0.0);
        let centre = (lo + hi) * 0.5;
        Bounds {
            centre,
            radius: ((hi - lo).length() * 0.5).max(1.0),
        }
    }
}

/// A camera made concrete: its frame and projection.
pub(crate) struct View {
    pub(crate) eye: Vector,
    pub(crate) target: Vector,
    pub(crate) forward: Vector,
    pub(crate) right: Vector,
    pub(crate) up: Vector,
    pub(crate) orthographic: bool,
    /// Perspective: tan(fov/2); orthographic: unused.
    pub(crate) tan_half_fov: f32,
    /// Orthographic: half the picture's height, mm.
    pub(crate) half_height: f32,
    pub(crate) aspect: f32,
    pub(crate) width: f32,
    pub(crate) height: f32,
}

impl View {
    pub(crate) fn new(
        camera: &Camera,
        bounds: &Bounds,
        width: u32,
        height: u32,
    ) -> Result<View, RenderError> {
        let bad = |reason: String| Err(RenderError::BadCamera { reason });
        for (name, v) in [("eye", camera.eye), ("target", camera.target)] {
            if let Some(v) = v {
                if !v.iter().all(|c| c.is_finite() && c.abs() <= 1.0e7) {
                    return bad(format!(
                        "{name} must be finite and within 1e7 mm of the origin, got {v:?}"
                    ));
                }
            }
        }
        let fov_deg = if camera.fov_deg == 0.0 {
            DEFAULT_FOV_DEG
        } else {
            camera.fov_deg
        };
        if !(fov_deg > 0.0 && fov_deg <= MAX_FOV_DEG) {
            return bad(format!(
                "fov_deg must be in (0, {MAX_FOV_DEG}] degrees (0 means {DEFAULT_FOV_DEG}), got {}",
                camera.fov_deg
            ));
        }
        let aspect = width as f32 / height as f32;
        let tan_half_fov = (fov_deg.to_radians() * 0.5).tan();
        // The distance at which the bounding sphere fills the narrower field of view.
        let fit = bounds.radius * 1.08;
        let narrow = tan_half_fov.min(tan_half_fov * aspect);
        let distance = fit / (narrow.atan()).sin();
        let target = camera.target.map(vec).unwrap_or(bounds.centre);
        let eye = match camera.eye {
            Some(eye) => vec(eye),
            None => target + camera.preset.direction() * distance,
        };
        let to_target = target - eye;
        if to_target.length() < 1.0e-3 {
            return bad(format!(
                "eye and target are the same point {:?}",
                <[f32; 3]>::from(eye)
            ));
        }
        let forward = to_target.normalize();
        let world_up = if forward.z.abs() > 0.999 {
            Vector::Y
        } else {
            Vector::Z
        };
        let right = forward.cross(world_up).normalize();
        let up = right.cross(forward);
        Ok(View {
            eye,
            target,
            forward,
            right,
            up,
            orthographic: camera.orthographic,
            tan_half_fov,
            half_height: fit * (1.0f32).max(1.0 / aspect),
            aspect,
            width: width as f32,
            height: height as f32,
        })
    }

    /// Half the height the picture spans at the target's distance, mm.
    pub(crate) fn visible_half_height(&self) -> f32 {
        if self.orthographic {
            self.half_height
        } else {
            (self.target - self.eye).length() * self.tan_half_fov
        }
    }

    /// Pixel coordinates and a depth key (larger is nearer), or `None` behind the camera.
    pub(crate) fn project(&self, p: Vector) -> Option<(f32, f32, f32)> {
        let d = p - self.eye;
        let (x, y, z) = (d.dot(self.right), d.dot(self.up), d.dot(self.forward));
        let (nx, ny, key) = if self.orthographic {
            (
                x / (self.half_height * self.aspect),
                y / self.half_height,
                -z,
            )
        } else {
            if z <= 1.0e-3 {
                return None;
            }
            let s = 1.0 / (z * self.tan_half_fov);
            (x * s / self.aspect, y * s, 1.0 / z)
        };
        Some((
            (nx + 1.0) * 0.5 * self.width,
            (1.0 - ny) * 0.5 * self.height,
            key,
        ))
    }
}
