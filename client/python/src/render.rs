//! Pictures for `render_mode="rgb_array"`: a camera from Python's arguments, and the
//! server's PNG decoded into a `height × width × 3` uint8 array.

use gymfleet_client::{Camera, CameraPreset, Image};
use numpy::{PyArray3, PyArrayMethods};
use pyo3::prelude::*;

use crate::options::invalid;

/// A camera from a preset name and optional overrides.
pub(crate) fn camera(
    preset: &str,
    eye: Option<[f64; 3]>,
    target: Option<[f64; 3]>,
    fov_deg: f32,
    orthographic: bool,
) -> PyResult<Camera> {
    let preset = match preset {
        "iso" => CameraPreset::Iso,
        "front" => CameraPreset::Front,
        "side" => CameraPreset::Side,
        "top" => CameraPreset::Top,
        other => {
            return Err(invalid(format!(
                "camera: expected \"iso\", \"front\", \"side\" or \"top\", got {:?}",
                other.chars().take(64).collect::<String>()
            )))
        }
    };
    Ok(Camera {
        preset,
        eye,
        target,
        fov_deg,
        orthographic,
    })
}

/// The image's pixels as a `height × width × 3` array.
pub(crate) fn to_array<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyArray3<u8>>> {
    let bad = |e: &dyn std::fmt::Display| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("the server sent an unreadable PNG: {e}"))
    };
    let decoder = png::Decoder::new(std::io::Cursor::new(&image.png));
    let mut reader = decoder.read_info().map_err(|e| bad(&e))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| bad(&"too large"))?;
    let mut pixels = vec![0; size];
    let info = reader.next_frame(&mut pixels).map_err(|e| bad(&e))?;
    if info.color_type != png::ColorType::Rgb || info.bit_depth != png::BitDepth::Eight {
        return Err(bad(&format!(
            "{:?} {:?}, not 8-bit RGB",
            info.color_type, info.bit_depth
        )));
    }
    pixels.truncate(info.buffer_size());
    let (h, w) = (info.height as usize, info.width as usize);
    let flat = numpy::PyArray1::from_vec(py, pixels);
    flat.reshape([h, w, 3])
}
