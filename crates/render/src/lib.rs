//! Pictures of a gymfleet env: a software renderer for a [`Scene`] (every part's shape at
//! its pose, Lambert-shaded, on a ground grid whose spacing in mm is printed in a corner, with joint axes, end
//! effectors and the task target marked), to an RGB [`Frame`] and to PNG.
//!
//! This crate owns cameras (presets that frame the robot automatically, or an explicit
//! eye, target and field of view; perspective or orthographic), rasterisation with a depth
//! buffer, and PNG encoding (the `png` crate). Shapes are tessellated by parry. It leaves
//! the scene to `gymfleet-env` and knows nothing of networks: the server runs it on its
//! pool like a step.
//!
//! `render(scene, camera, width, height) -> Frame` rasterises an `env::Scene`: parts
//! tessellated by parry, a depth buffer, Lambert shading with one light, a ground grid on
//! z = 0 whose spacing (1, 2 or 5 × 10ⁿ mm) follows the camera, and joint axes, end
//! effectors and a reach target drawn on top. `Camera` is a preset (`iso`, `front`,
//! `side`, `top`) that frames the robot's bounding sphere, or an explicit eye, target and
//! field of view, in perspective or orthographic. `Frame::to_png` encodes with the `png`
//! crate, `describe` gives agents a one-paragraph account, and `Frame::instance_ids` says
//! which instance each pixel shows (the tests measure silhouettes with it).
//!
//! `lib.rs` holds the API and the drawing order; `tessellate.rs` the shapes' triangles;
//! `view.rs` the camera made concrete (bounds, projection); `raster.rs` the pixels (depth
//! buffer, grid, label, markers). The scene comes from physics' `scene.rs`
//! (`RobotWorld::scene_parts`, `scene_joints`: collider shapes and world poses in mm) via
//! `RobotEnv::scene`. Pure CPU code: no tokio, tonic or prost; the server runs it on the
//! pool like a step (`Render`).

mod raster;
mod tessellate;
mod view;

use raster::{format_mm, nice_spacing, Raster};
use tessellate::{tessellate, vec};
use view::{Bounds, View};

use gymfleet_env::Scene;
use rapier3d::math::Vector;

/// The largest width or height accepted, in pixels.
pub const MAX_SIDE: u32 = 2048;
/// The smallest width or height accepted, in pixels.
pub const MIN_SIDE: u32 = 16;
/// Width and height used when a request gives 0.
pub const DEFAULT_WIDTH: u32 = 320;
/// See [`DEFAULT_WIDTH`].
pub const DEFAULT_HEIGHT: u32 = 240;
/// Vertical field of view used when a perspective camera gives 0, degrees.
pub const DEFAULT_FOV_DEG: f32 = 45.0;
/// The widest field of view accepted, degrees.
pub const MAX_FOV_DEG: f32 = 170.0;

/// Why a picture could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderError {
    /// Width or height out of range.
    #[error("image size {width}x{height} is out of range: each side must be {MIN_SIDE} to {MAX_SIDE} pixels (0 means {DEFAULT_WIDTH}x{DEFAULT_HEIGHT})")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// A camera that cannot be used.
    #[error("bad camera: {reason}")]
    BadCamera {
        /// What is wrong with it.
        reason: String,
    },
}

/// A camera preset: a viewing direction, framed automatically.
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

impl CameraPreset {
    /// The direction from the target to the eye.
    fn direction(self) -> Vector {
        match self {
            CameraPreset::Iso => Vector::new(1.0, -1.0, 0.8).normalize(),
            CameraPreset::Front => Vector::new(0.0, -1.0, 0.0),
            CameraPreset::Side => Vector::new(1.0, 0.0, 0.0),
            CameraPreset::Top => Vector::new(0.0, 0.0, 1.0),
        }
    }

    /// The preset's name, as the API spells it (lower case).
    pub fn name(self) -> &'static str {
        match self {
            CameraPreset::Iso => "iso",
            CameraPreset::Front => "front",
            CameraPreset::Side => "side",
            CameraPreset::Top => "top",
        }
    }
}

/// Where the picture is taken from. With neither `eye` nor `target` the preset frames the
/// whole scene; with one of them the other is derived (the target defaults to the scene's
/// centre, the eye to the preset's direction at a framing distance).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Camera {
    /// The viewing direction when `eye` is not given.
    pub preset: CameraPreset,
    /// The camera's position, world mm.
    pub eye: Option<[f32; 3]>,
    /// The point looked at, world mm.
    pub target: Option<[f32; 3]>,
    /// Vertical field of view for a perspective camera, degrees; 0 means
    /// [`DEFAULT_FOV_DEG`].
    pub fov_deg: f32,
    /// A parallel projection that frames the scene (the field of view is then unused).
    pub orthographic: bool,
}

/// A rendered picture.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` RGB triples, row by row from the top.
    pub rgb: Vec<u8>,
    /// For each pixel, 0 for none or 1 + the index of the instance drawn there.
    pub instance_ids: Vec<u16>,
    /// The distance between two ground-grid lines, mm (every fifth line is darker).
    pub grid_mm: f32,
    /// For an orthographic camera, the size of a pixel in mm.
    pub mm_per_pixel: Option<f32>,
    /// The camera used, world mm.
    pub eye: [f32; 3],
    /// The point looked at, world mm.
    pub target: [f32; 3],
}

impl Frame {
    /// The picture as a PNG file (8-bit RGB).
    pub fn to_png(&self) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_compression(png::Compression::Fast);
            let mut writer = encoder
                .write_header()
                .expect("writing a PNG header to memory cannot fail");
            writer
                .write_image_data(&self.rgb)
                .expect("the buffer holds exactly width x height RGB pixels");
        }
        out
    }

    /// How many pixels show instance `instance`.
    pub fn coverage(&self, instance: usize) -> usize {
        let id = instance as u16 + 1;
        self.instance_ids.iter().filter(|&&i| i == id).count()
    }
}

const BACKGROUND_TOP: [f32; 3] = [0.93, 0.95, 0.98];
const BACKGROUND_BOTTOM: [f32; 3] = [0.80, 0.83, 0.87];
const GRID_MINOR: [f32; 3] = [0.62, 0.65, 0.70];
const GRID_MAJOR: [f32; 3] = [0.38, 0.41, 0.46];
const AXIS_COLOUR: [f32; 3] = [0.85, 0.10, 0.10];
const END_EFFECTOR_COLOUR: [f32; 3] = [0.05, 0.65, 0.15];
const TARGET_COLOUR: [f32; 3] = [0.85, 0.10, 0.80];
const PALETTE: [[f32; 3]; 6] = [
    [0.55, 0.58, 0.62],
    [0.95, 0.60, 0.15],
    [0.20, 0.50, 0.85],
    [0.90, 0.80, 0.25],
    [0.45, 0.75, 0.55],
    [0.70, 0.45, 0.80],
];

/// Renders `scene` as seen by `camera`, `width × height` pixels (0 for the defaults).
pub fn render(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Result<Frame, RenderError> {
    let (width, height) = match (width, height) {
        (0, 0) => (DEFAULT_WIDTH, DEFAULT_HEIGHT),
        (w, h) if (MIN_SIDE..=MAX_SIDE).contains(&w) && (MIN_SIDE..=MAX_SIDE).contains(&h) => {
            (w, h)
        }
        (w, h) => {
            return Err(RenderError::BadSize {
                width: w,
                height: h,
            })
        }
    };
    let meshes = tessellate(scene);
    let bounds = Bounds::of(scene, &meshes);
    let view = View::new(camera, &bounds, width, height)?;
    let mut raster = Raster::new(width, height);
    raster.fill_background();

    let light = (view.up * 0.6 + view.right * 0.3 - view.forward).normalize();
    for mesh in &meshes {
        let base = PALETTE[mesh.instance % PALETTE.len()];
        for tri in &mesh.triangles {
            let [a, b, c] = tri.map(|i| mesh.vertices[i as usize]);
            let normal = (b - a).cross(c - a);
            if normal.length_squared() == 0.0 {
                continue;
            }
            let normal = normal.normalize();
            let shade = 0.35 + 0.65 * normal.dot(light).max(0.0);
            let colour = base.map(|c| c * shade);
            raster.triangle(&view, [a, b, c], colour, mesh.instance as u16 + 1);
        }
    }

    // The grid follows the camera (what it sees around its target), not the robot, so
    // that a fixed camera draws the same grid whatever moves in front of it.
    let grid_mm = nice_spacing(view.visible_half_height() * 2.0 / 10.0);
    raster.grid(&view, grid_mm);

    let axis_len = bounds.radius * 0.18;
    for joint in &scene.joints {
        let anchor = vec(joint.anchor);
        let axis = vec(joint.axis);
        raster.line(
            &view,
            anchor - axis * axis_len,
            anchor + axis * axis_len,
            AXIS_COLOUR,
            false,
            1,
        );
        raster.dot(&view, anchor, 2.0, AXIS_COLOUR);
    }
    for &p in &scene.end_effectors {
        raster.dot(&view, vec(p), 4.0, END_EFFECTOR_COLOUR);
    }
    if let Some(t) = scene.target {
        raster.ring(&view, vec(t), 6.0, TARGET_COLOUR);
    }
    raster.label(&format!("grid {} mm", format_mm(grid_mm)));

    Ok(Frame {
        width,
        height,
        rgb: raster.rgb,
        instance_ids: raster.ids,
        grid_mm,
        mm_per_pixel: view
            .orthographic
            .then(|| 2.0 * view.half_height / height as f32),
        eye: view.eye.into(),
        target: view.target.into(),
    })
}

/// A short, human-readable account of a frame and the scene in it (for agents).
pub fn describe(scene: &Scene, frame: &Frame, camera: &Camera) -> String {
    let f = |v: [f32; 3]| format!("({:.0}, {:.0}, {:.0})", v[0], v[1], v[2]);
    let mut text = format!(
        "{}x{} {} view ({}), eye {} mm looking at {} mm; ground grid every {} mm (every fifth line darker; labelled bottom left); joint axes red, end effectors green",
        frame.width,
        frame.height,
        if camera.eye.is_some() { "custom" } else { camera.preset.name() },
        if camera.orthographic { "orthographic" } else { "perspective" },
        f(frame.eye),
        f(frame.target),
        frame.grid_mm,
    );
    if scene.target.is_some() {
        text.push_str(", task target magenta");
    }
    text.push('.');
    for (name, p) in scene.end_effectors.iter().enumerate() {
        text.push_str(&format!(" End effector {name} at {} mm.", f(*p)));
    }
    if let Some(t) = scene.target {
        text.push_str(&format!(" Target at {} mm.", f(t)));
    }
    text
}
