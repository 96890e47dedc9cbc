//! Tests on the pictures themselves: where the pendulum is, how large a part looks, the
//! PNG, and the error for every bad camera and size.

use gymfleet_env::{EnvConfig, RobotEnv, Scene, SceneShape};
use gymfleet_render::{render, Camera, CameraPreset, Frame, RenderError};
use rapier3d::math::{Rotation, Vector};

const PENDULUM: &str = include_str!("../../../models/pendulum.json");
const ARM2: &str = include_str!("../../../models/arm2.json");

fn scene(document: &str) -> Scene {
    RobotEnv::from_json(document, EnvConfig::default())
        .unwrap()
        .scene()
}

/// The pendulum's scene with its arm (instance 1) turned by `deg` about the hinge.
fn pendulum_at(deg: f32) -> Scene {
    let mut scene = scene(PENDULUM);
    let joint = scene.joints[0];
    let anchor = Vector::from(joint.anchor);
    let turn = Rotation::from_axis_angle(Vector::from(joint.axis), deg.to_radians());
    for part in scene.parts.iter_mut().filter(|p| p.instance == 1) {
        let p = anchor + turn * (Vector::from(part.position) - anchor);
        let [w, x, y, z] = part.rotation;
        let q = turn * Rotation::from_xyzw(x, y, z, w);
        part.position = p.into();
        part.rotation = [q.w, q.x, q.y, q.z];
    }
    for e in &mut scene.end_effectors {
        *e = (anchor + turn * (Vector::from(*e) - anchor)).into();
    }
    scene
}

/// The bounding box of the pixels showing `instance`: (min x, max x, min y, max y).
fn pixel_box(frame: &Frame, instance: usize) -> (usize, usize, usize, usize) {
    let id = instance as u16 + 1;
    let w = frame.width as usize;
    let mut b = (usize::MAX, 0, usize::MAX, 0);
    for (i, _) in frame
        .instance_ids
        .iter()
        .enumerate()
        .filter(|(_, &v)| v == id)
    {
        let (x, y) = (i % w, i / w);
        b = (b.0.min(x), b.1.max(x), b.2.min(y), b.3.max(y));
    }
    b
}

#[test]
fn the_pendulum_at_0_and_90_degrees_differs_where_the_arm_swings() {
    // A fixed perspective camera in front of the hinge (the pendulum swings about y).
    let camera = Camera {
        eye: Some([10.0, -120.0, 25.0]),
        target: Some([10.0, 10.0, 25.0]),
        ..Camera::default()
    };
    let upright = render(&pendulum_at(0.0), &camera, 320, 240).unwrap();
    let swung = render(&pendulum_at(90.0), &camera, 320, 240).unwrap();
    let (up_box, swung_box) = (pixel_box(&upright, 1), pixel_box(&swung, 1));
    // Upright: a tall, narrow arm; swung: a wide, flat one.
    assert!(
        up_box.3 - up_box.2 > 3 * (up_box.1 - up_box.0),
        "{up_box:?}"
    );
    assert!(
        swung_box.1 - swung_box.0 > 3 * (swung_box.3 - swung_box.2),
        "{swung_box:?}"
    );
    // Every pixel that changed lies where the arm was or now is (with the end-effector
    // dot's few pixels of margin); the base, the grid and the background did not move.
    let margin = 6;
    let inside = |(x, y): (usize, usize), b: (usize, usize, usize, usize)| {
        x + margin >= b.0 && x <= b.1 + margin && y + margin >= b.2 && y <= b.3 + margin
    };
    let w = upright.width as usize;
    let mut changed = 0;
    for i in 0..upright.instance_ids.len() {
        if upright.rgb[3 * i..3 * i + 3] != swung.rgb[3 * i..3 * i + 3] {
            changed += 1;
            let at = (i % w, i / w);
            assert!(
                inside(at, up_box) || inside(at, swung_box),
                "pixel {at:?} changed"
            );
        }
    }
    assert!(changed > 500, "only {changed} pixels changed");
    assert!(upright.coverage(0) > 0 && swung.coverage(0) > 0);
}

#[test]
fn an_orthographic_silhouette_has_the_parts_projected_area() {
    // From the front, the pendulum's base shows its 20 × 5 mm face, the arm 4 × 40 mm.
    let scene = scene(PENDULUM);
    let camera = Camera {
        preset: CameraPreset::Front,
        orthographic: true,
        ..Camera::default()
    };
    let frame = render(&scene, &camera, 640, 480).unwrap();
    let mm = frame.mm_per_pixel.unwrap();
    for (instance, expected_mm2) in [(0, 20.0 * 5.0), (1, 4.0 * 40.0)] {
        let area = frame.coverage(instance) as f32 * mm * mm;
        let error = (area - expected_mm2).abs() / expected_mm2;
        assert!(
            error < 0.03,
            "instance {instance}: {area} mm² against {expected_mm2} mm²"
        );
    }
    // From above, a cylinder's disc (arm2's base, if it is one) and the boxes scale alike.
    let arm2 = self::scene(ARM2);
    let top = Camera {
        preset: CameraPreset::Top,
        orthographic: true,
        ..Camera::default()
    };
    let frame = render(&arm2, &top, 480, 480).unwrap();
    let mm = frame.mm_per_pixel.unwrap();
    let visible: f32 = (0..arm2.instance_names.len())
        .map(|i| frame.coverage(i) as f32 * mm * mm)
        .sum();
    assert!(visible > 0.0);
    for part in arm2
        .parts
        .iter()
        .filter(|p| matches!(p.shape, SceneShape::Cylinder { .. }))
    {
        assert!(
            frame.coverage(part.instance) > 0,
            "cylinder {} not drawn",
            part.instance
        );
    }
}

#[test]
fn the_png_decodes_to_the_frame() {
    let frame = render(&scene(ARM2), &Camera::default(), 0, 0).unwrap();
    assert_eq!((frame.width, frame.height), (320, 240));
    let png = frame.to_png();
    let decoder = png::Decoder::new(std::io::Cursor::new(png));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!((info.width, info.height), (320, 240));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(&pixels[..info.buffer_size()], &frame.rgb[..]);
    // Something was drawn: both links, and more than one colour.
    assert!(frame.coverage(1) > 100 && frame.coverage(2) > 100);
}

#[test]
fn the_grid_spacing_is_printed_bottom_left() {
    let frame = render(&scene(ARM2), &Camera::default(), 320, 240).unwrap();
    let label = format!("grid {} mm", frame.grid_mm);
    // A white box 6 px per character + 4 wide, 11 high, 2 px from the corner, with dark
    // glyph pixels in it.
    let (w, h) = (6 * label.len() + 4, 11);
    let (mut white, mut dark) = (0, 0);
    for y in 240 - 2 - h..240 - 2 {
        for x in 2..2 + w {
            let p = &frame.rgb[3 * (y * 320 + x)..][..3];
            white += usize::from(p == [255, 255, 255]);
            dark += usize::from(p[0] < 40 && p[1] < 40 && p[2] < 50);
        }
    }
    assert!(dark > 40 && white > dark, "white {white}, dark {dark}");
    // Too small a picture has no room for it, and is still drawn.
    render(&scene(ARM2), &Camera::default(), 16, 16).unwrap();
}

#[test]
fn every_preset_frames_the_whole_robot() {
    let scene = scene(ARM2);
    for preset in [
        CameraPreset::Iso,
        CameraPreset::Front,
        CameraPreset::Side,
        CameraPreset::Top,
    ] {
        for orthographic in [false, true] {
            let camera = Camera {
                preset,
                orthographic,
                ..Camera::default()
            };
            let frame = render(&scene, &camera, 160, 120).unwrap();
            let w = frame.width as usize;
            let edge = frame.instance_ids.iter().enumerate().any(|(i, &id)| {
                let (x, y) = (i % w, i / w);
                id != 0 && (x == 0 || y == 0 || x == w - 1 || y == frame.height as usize - 1)
            });
            assert!(
                !edge,
                "{preset:?} (orthographic {orthographic}) cuts the robot off"
            );
            assert!(
                frame.instance_ids.iter().any(|&id| id != 0),
                "{preset:?}: nothing drawn"
            );
        }
    }
}

#[test]
fn bad_sizes_and_cameras_get_exact_errors() {
    let scene = scene(PENDULUM);
    let size = |w, h| {
        render(&scene, &Camera::default(), w, h)
            .unwrap_err()
            .to_string()
    };
    let expected = |w, h| {
        format!("image size {w}x{h} is out of range: each side must be 16 to 2048 pixels (0 means 320x240)")
    };
    assert_eq!(size(4096, 100), expected(4096, 100));
    assert_eq!(size(8, 8), expected(8, 8));
    assert_eq!(size(0, 240), expected(0, 240));
    let cam = |camera: Camera| render(&scene, &camera, 64, 64).unwrap_err();
    assert_eq!(
        cam(Camera {
            fov_deg: 180.0,
            ..Camera::default()
        })
        .to_string(),
        "bad camera: fov_deg must be in (0, 170] degrees (0 means 45), got 180"
    );
    assert_eq!(
        cam(Camera {
            fov_deg: f32::NAN,
            ..Camera::default()
        })
        .to_string(),
        "bad camera: fov_deg must be in (0, 170] degrees (0 means 45), got NaN"
    );
    assert_eq!(
        cam(Camera {
            eye: Some([f32::INFINITY, 0.0, 0.0]),
            ..Camera::default()
        })
        .to_string(),
        "bad camera: eye must be finite and within 1e7 mm of the origin, got [inf, 0.0, 0.0]"
    );
    assert_eq!(
        cam(Camera {
            eye: Some([1.0, 2.0, 3.0]),
            target: Some([1.0, 2.0, 3.0]),
            ..Camera::default()
        }),
        RenderError::BadCamera {
            reason: "eye and target are the same point [1.0, 2.0, 3.0]".into()
        }
    );
}

/// Writes a few pictures to `$GYMFLEET_RENDER_DIR` for a person to look at (a no-op unless
/// the variable is set).
#[test]
fn pictures_for_a_person() {
    let Some(dir) = std::env::var_os("GYMFLEET_RENDER_DIR") else {
        return;
    };
    let dir = std::path::PathBuf::from(dir);
    for (name, document) in [
        ("pendulum", PENDULUM),
        ("arm2", ARM2),
        ("arm6", include_str!("../../../models/arm6.json")),
    ] {
        for preset in [CameraPreset::Iso, CameraPreset::Front, CameraPreset::Top] {
            let frame = render(
                &scene(document),
                &Camera {
                    preset,
                    ..Camera::default()
                },
                320,
                240,
            )
            .unwrap();
            std::fs::write(
                dir.join(format!("{name}-{}.png", preset.name())),
                frame.to_png(),
            )
            .unwrap();
        }
    }
}

#[test]
fn a_capsule_shows_its_projected_area() {
    // The pendulum with a capsule arm (radius 2 mm, 40 mm long caps included): from the
    // front, a 4 × 36 mm rectangle and two half discs of radius 2 mm.
    let document = PENDULUM.replace(
        r#"{ "type": "cube", "size": { "x": 4, "y": 4, "z": 40 } }"#,
        r#"{ "type": "capsule", "radius": 2, "height": 40 }"#,
    );
    assert_ne!(document, PENDULUM, "the arm's primitive was replaced");
    let scene = scene(&document);
    assert!(scene
        .parts
        .iter()
        .any(|p| matches!(p.shape, SceneShape::Capsule { .. })));
    let camera = Camera {
        preset: CameraPreset::Front,
        orthographic: true,
        ..Camera::default()
    };
    let frame = render(&scene, &camera, 640, 480).unwrap();
    let mm = frame.mm_per_pixel.unwrap();
    let expected = 4.0 * 36.0 + std::f32::consts::PI * 2.0 * 2.0;
    let area = frame.coverage(1) as f32 * mm * mm;
    assert!(
        (area - expected).abs() / expected < 0.03,
        "{area} mm² against {expected} mm²"
    );
}

/// A closed chain renders like any robot: the four-bar's scene has its four joints (the
/// loop's closing pin among them), and its rocker's pixels move when the crank turns it.
#[test]
fn a_four_bar_renders_and_its_rocker_moves_with_the_crank() {
    let document = include_str!("../../../models/fourbar.json");
    let mut env = RobotEnv::from_json(document, EnvConfig::default()).unwrap();
    assert_eq!(env.scene().joints.len(), 4);
    let camera = Camera {
        preset: CameraPreset::Front,
        ..Camera::default()
    };
    let before = render(&env.scene(), &camera, 320, 240).unwrap();
    for _ in 0..60 {
        env.step(gymfleet_env::ActionType::Velocity, &[360.0])
            .unwrap();
    }
    let after = render(&env.scene(), &camera, 320, 240).unwrap();
    // Instance 3 is the rocker, driven only through the loop.
    assert_ne!(
        pixel_box(&before, 3),
        pixel_box(&after, 3),
        "the rocker moved"
    );
}
