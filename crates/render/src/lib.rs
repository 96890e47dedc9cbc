//! Pictures of a gymfleet env: a software renderer for a [`Scene`] (every part's shape at
//! its pose, Lambert-shaded, on a ground grid whose spacing in mm is printed in a corner, with joint axes, end
//! effectors and the task target marked), to an RGB [`Frame`] and to PNG.
//!
//! This crate owns cameras (presets that frame the robot automatically, or an explicit
//! eye, target and field of view; perspective or orthographic), rasterisation with a depth
//! buffer, and PNG encoding (the `png` crate). Shapes are tessellated by parry. It leaves
//! the scene to `gymfleet-env` and knows nothing of networks: the server runs it on its
//! pool like a step.

use gymfleet_env::{Scene, SceneShape};
use rapier3d::math::{Rotation, Vector};
use rapier3d::parry::shape::{Ball, Capsule, Cuboid, Cylinder};

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

fn vec(v: [f32; 3]) -> Vector {
    Vector::new(v[0], v[1], v[2])
}

/// One part's triangles in world mm.
struct Mesh {
    instance: usize,
    vertices: Vec<Vector>,
    triangles: Vec<[u32; 3]>,
}

fn tessellate(scene: &Scene) -> Vec<Mesh> {
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

/// A sphere that holds the scene.
struct Bounds {
    centre: Vector,
    radius: f32,
}

impl Bounds {
    fn of(scene: &Scene, meshes: &[Mesh]) -> Bounds {
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
struct View {
    eye: Vector,
    target: Vector,
    forward: Vector,
    right: Vector,
    up: Vector,
    orthographic: bool,
    /// Perspective: tan(fov/2); orthographic: unused.
    tan_half_fov: f32,
    /// Orthographic: half the picture's height, mm.
    half_height: f32,
    aspect: f32,
    width: f32,
    height: f32,
}

impl View {
    fn new(camera: &Camera, bounds: &Bounds, width: u32, height: u32) -> Result<View, RenderError> {
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
    fn visible_half_height(&self) -> f32 {
        if self.orthographic {
            self.half_height
        } else {
            (self.target - self.eye).length() * self.tan_half_fov
        }
    }

    /// Pixel coordinates and a depth key (larger is nearer), or `None` behind the camera.
    fn project(&self, p: Vector) -> Option<(f32, f32, f32)> {
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

struct Raster {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
    ids: Vec<u16>,
    depth: Vec<f32>,
}

fn to_byte(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

impl Raster {
    fn new(width: u32, height: u32) -> Raster {
        let n = width as usize * height as usize;
        Raster {
            width: width as usize,
            height: height as usize,
            rgb: vec![0; 3 * n],
            ids: vec![0; n],
            depth: vec![f32::NEG_INFINITY; n],
        }
    }

    fn fill_background(&mut self) {
        for y in 0..self.height {
            let t = y as f32 / (self.height - 1).max(1) as f32;
            let c: [u8; 3] = std::array::from_fn(|k| {
                to_byte(BACKGROUND_TOP[k] * (1.0 - t) + BACKGROUND_BOTTOM[k] * t)
            });
            for x in 0..self.width {
                self.rgb[3 * (y * self.width + x)..][..3].copy_from_slice(&c);
            }
        }
    }

    fn put(&mut self, x: usize, y: usize, colour: [f32; 3]) {
        self.rgb[3 * (y * self.width + x)..][..3].copy_from_slice(&colour.map(to_byte));
    }

    /// A filled triangle, depth-tested, drawn where it faces the camera.
    fn triangle(&mut self, view: &View, corners: [Vector; 3], colour: [f32; 3], id: u16) {
        let Some(p0) = view.project(corners[0]) else {
            return;
        };
        let Some(p1) = view.project(corners[1]) else {
            return;
        };
        let Some(p2) = view.project(corners[2]) else {
            return;
        };
        // Signed area in pixel space (y points down): negative means facing the camera for
        // counter-clockwise, outward-wound faces.
        let area = (p1.0 - p0.0) * (p2.1 - p0.1) - (p2.0 - p0.0) * (p1.1 - p0.1);
        if area >= 0.0 {
            return;
        }
        let min_x = p0.0.min(p1.0).min(p2.0).floor().max(0.0) as usize;
        let max_x = (p0.0.max(p1.0).max(p2.0).ceil().min(self.width as f32)) as usize;
        let min_y = p0.1.min(p1.1).min(p2.1).floor().max(0.0) as usize;
        let max_y = (p0.1.max(p1.1).max(p2.1).ceil().min(self.height as f32)) as usize;
        let edge = |a: (f32, f32, f32), b: (f32, f32, f32), x: f32, y: f32| {
            (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)
        };
        for y in min_y..max_y {
            for x in min_x..max_x {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let w0 = edge(p1, p2, px, py) / area;
                let w1 = edge(p2, p0, px, py) / area;
                let w2 = edge(p0, p1, px, py) / area;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let key = w0 * p0.2 + w1 * p1.2 + w2 * p2.2;
                let i = y * self.width + x;
                if key > self.depth[i] {
                    self.depth[i] = key;
                    self.ids[i] = id;
                    self.put(x, y, colour);
                }
            }
        }
    }

    /// A line, optionally depth-tested, `thickness` pixels wide.
    fn line(
        &mut self,
        view: &View,
        a: Vector,
        b: Vector,
        colour: [f32; 3],
        depth_test: bool,
        thickness: i32,
    ) {
        // Lines are split so that each piece projects (a grid may pass behind the camera).
        const PIECES: usize = 16;
        for k in 0..PIECES {
            let pa = a + (b - a) * (k as f32 / PIECES as f32);
            let pb = a + (b - a) * ((k + 1) as f32 / PIECES as f32);
            let (Some(p), Some(q)) = (view.project(pa), view.project(pb)) else {
                continue;
            };
            // A piece wholly beside the picture draws nothing: skip its pixels.
            let (w, h) = (self.width as f32, self.height as f32);
            if (p.0 < 0.0 && q.0 < 0.0)
                || (p.0 >= w && q.0 >= w)
                || (p.1 < 0.0 && q.1 < 0.0)
                || (p.1 >= h && q.1 >= h)
            {
                continue;
            }
            let steps = (q.0 - p.0)
                .abs()
                .max((q.1 - p.1).abs())
                .ceil()
                .clamp(1.0, 8192.0) as usize;
            for s in 0..=steps {
                let t = s as f32 / steps as f32;
                let (x, y) = (p.0 + (q.0 - p.0) * t, p.1 + (q.1 - p.1) * t);
                let key = p.2 + (q.2 - p.2) * t;
                for dy in 0..thickness {
                    let (xi, yi) = (x.floor() as i64, y.floor() as i64 + i64::from(dy));
                    if xi < 0 || yi < 0 || xi >= self.width as i64 || yi >= self.height as i64 {
                        continue;
                    }
                    let i = yi as usize * self.width + xi as usize;
                    if !depth_test || key >= self.depth[i] {
                        self.put(xi as usize, yi as usize, colour);
                    }
                }
            }
        }
    }

    /// The ground grid on z = 0, around the point below the camera's target, behind
    /// whatever stands on it.
    fn grid(&mut self, view: &View, spacing: f32) {
        let n = (view.visible_half_height() * 3.0 / spacing)
            .ceil()
            .clamp(1.0, 100.0) as i32;
        let half = n as f32 * spacing;
        let cx = (view.target.x / (5.0 * spacing)).round() * 5.0 * spacing;
        let cy = (view.target.y / (5.0 * spacing)).round() * 5.0 * spacing;
        for k in -n..=n {
            let major = (cx / spacing).round() as i64 + i64::from(k);
            let colour = if major % 5 == 0 {
                GRID_MAJOR
            } else {
                GRID_MINOR
            };
            let o = k as f32 * spacing;
            self.line(
                view,
                Vector::new(cx + o, cy - half, 0.0),
                Vector::new(cx + o, cy + half, 0.0),
                colour,
                true,
                1,
            );
            let major = (cy / spacing).round() as i64 + i64::from(k);
            let colour = if major % 5 == 0 {
                GRID_MAJOR
            } else {
                GRID_MINOR
            };
            self.line(
                view,
                Vector::new(cx - half, cy + o, 0.0),
                Vector::new(cx + half, cy + o, 0.0),
                colour,
                true,
                1,
            );
        }
    }

    /// `text` in the bottom-left corner on a light box (the grid's scale), scaled with
    /// the picture; left out when the picture is too small to hold it.
    fn label(&mut self, text: &str) {
        let scale = (self.height / 240).max(1);
        let (cw, ch) = (6 * scale, 7 * scale);
        let (pad, n) = (2 * scale, text.chars().count());
        let (w, h) = (n * cw + 2 * pad, ch + 2 * pad);
        if w + 2 > self.width || h + 2 > self.height {
            return;
        }
        let (x0, y0) = (2, self.height - h - 2);
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                self.put(x, y, [1.0, 1.0, 1.0]);
            }
        }
        for (k, c) in text.chars().enumerate() {
            let Some(rows) = glyph(c) else { continue };
            for (row, bits) in rows.iter().enumerate() {
                for col in 0..5 {
                    if bits & (0x10 >> col) == 0 {
                        continue;
                    }
                    for dy in 0..scale {
                        for dx in 0..scale {
                            let x = x0 + pad + k * cw + col * scale + dx;
                            let y = y0 + pad + row * scale + dy;
                            self.put(x, y, [0.1, 0.1, 0.15]);
                        }
                    }
                }
            }
        }
    }

    /// A filled disc of `radius` pixels, drawn on top.
    fn dot(&mut self, view: &View, p: Vector, radius: f32, colour: [f32; 3]) {
        self.disc(view, p, radius, colour, 0.0);
    }

    /// A ring of `radius` pixels, drawn on top.
    fn ring(&mut self, view: &View, p: Vector, radius: f32, colour: [f32; 3]) {
        self.disc(view, p, radius, colour, radius - 2.0);
    }

    fn disc(&mut self, view: &View, p: Vector, outer: f32, colour: [f32; 3], inner: f32) {
        let Some((cx, cy, _)) = view.project(p) else {
            return;
        };
        let r = outer.ceil() as i64;
        for dy in -r..=r {
            for dx in -r..=r {
                let (x, y) = (cx.floor() as i64 + dx, cy.floor() as i64 + dy);
                if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
                    continue;
                }
                let d = ((dx * dx + dy * dy) as f32).sqrt();
                if d <= outer && d >= inner {
                    self.put(x as usize, y as usize, colour);
                }
            }
        }
    }
}

/// A grid spacing as a person writes it: `20`, `0.5`, `1000`.
fn format_mm(mm: f32) -> String {
    let text = format!("{mm:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A 5 × 7 bitmap of each character the picture's label uses (rows top to bottom, the
/// five low bits of each row left to right).
fn glyph(c: char) -> Option<[u8; 7]> {
    Some(match c {
        '0' => [0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e],
        '1' => [0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e],
        '2' => [0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f],
        '3' => [0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e],
        '4' => [0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02],
        '5' => [0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e],
        '6' => [0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e],
        '7' => [0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e],
        '9' => [0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c],
        'g' => [0x00, 0x00, 0x0f, 0x11, 0x0f, 0x01, 0x0e],
        'r' => [0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10],
        'i' => [0x04, 0x00, 0x0c, 0x04, 0x04, 0x04, 0x0e],
        'd' => [0x01, 0x01, 0x0d, 0x13, 0x11, 0x11, 0x0f],
        'm' => [0x00, 0x00, 0x1a, 0x15, 0x15, 0x11, 0x11],
        ' ' => [0; 7],
        _ => return None,
    })
}

/// The 1, 2, 5 × 10ⁿ mm spacing nearest above `raw`.
fn nice_spacing(raw: f32) -> f32 {
    let raw = raw.max(1.0e-3);
    let decade = 10f32.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * decade)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_spacings_are_one_two_five() {
        assert_eq!(nice_spacing(0.9), 1.0);
        assert_eq!(nice_spacing(1.5), 2.0);
        assert_eq!(nice_spacing(30.0), 50.0);
        assert_eq!(nice_spacing(51.0), 100.0);
    }

    #[test]
    fn spacings_print_as_people_write_them() {
        assert_eq!(format_mm(20.0), "20");
        assert_eq!(format_mm(0.5), "0.5");
        assert_eq!(format_mm(1000.0), "1000");
        assert!("grid 0.5 mm".chars().all(|c| glyph(c).is_some()));
        assert!("0123456789".chars().all(|c| glyph(c).is_some()));
    }
}
