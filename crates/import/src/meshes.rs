//! Mesh files into documents: every `{"type": "mesh", "file": …}` primitive of an assembly
//! document is replaced by the mesh's vertices (in mm) read from the request's assets with
//! `mesh-loader` (STL, OBJ, COLLADA), so that the document that is validated, built and
//! saved in env states is self-contained. A hull keeps only the hull's vertices.

use std::path::Path;

use serde_json::{json, Value};

use crate::assets::Assets;
use crate::{ImportError, Result};

/// Most vertices a mesh file may have before it is made convex (a hull's are far fewer).
pub const MAX_FILE_VERTICES: usize = 1 << 20;

fn bad(path: &str, reason: impl std::fmt::Display) -> ImportError {
    ImportError::Assets(format!("{path}: {reason}"))
}

/// Replaces the `file` of every mesh primitive in `document` with `vertices` (and, for a
/// decomposition, `indices`) read from `assets`. A document without mesh files is left as
/// it is; one with mesh files but no assets is left for the validator to refuse (it says
/// which file needs them).
pub fn inline_mesh_files(document: &mut Value, assets: Option<&Assets>) -> Result<()> {
    let Some(assets) = assets else { return Ok(()) };
    let Some(parts) = document.get_mut("parts").and_then(Value::as_array_mut) else {
        return Ok(());
    };
    for (i, part) in parts.iter_mut().enumerate() {
        let Some(primitive) = part.get_mut("primitive").and_then(Value::as_object_mut) else {
            continue;
        };
        if primitive.get("type").and_then(Value::as_str) == Some("heightfield") {
            if let Some(file) = primitive.remove("file") {
                let file = file.as_str().unwrap_or_default().to_string();
                let path = format!("parts[{i}].primitive.file");
                let bytes = assets.get(&file).map_err(|e| bad(&path, e))?;
                let (rows, columns, heights) = png_heights(bytes).map_err(|e| bad(&path, e))?;
                primitive.insert("rows".into(), json!(rows));
                primitive.insert("columns".into(), json!(columns));
                primitive.insert("heights".into(), json!(heights));
            }
            continue;
        }
        if primitive.get("type").and_then(Value::as_str) != Some("mesh") {
            continue;
        }
        let Some(file) = primitive
            .get("file")
            .and_then(Value::as_str)
            .map(str::to_string)
        else {
            continue;
        };
        let path = format!("parts[{i}].primitive.file");
        let scale = match primitive.get("scale") {
            None => [1.0; 3],
            Some(s) => {
                ["x", "y", "z"].map(|k| s.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN))
            }
        };
        if scale.iter().any(|s| !(s.is_finite() && *s != 0.0)) {
            return Err(bad(
                &format!("parts[{i}].primitive.scale"),
                "expected {\"x\", \"y\", \"z\"}: finite, non-zero factors",
            ));
        }
        let decompose = primitive.get("convex").and_then(Value::as_str) == Some("decomposition");
        let (vertices, triangles) = load(assets.get(&file).map_err(|e| bad(&path, e))?, &file)
            .map_err(|e| bad(&path, e))?;
        let vertices: Vec<[f64; 3]> = vertices
            .iter()
            .map(|v| [0, 1, 2].map(|k| f64::from(v[k]) * scale[k]))
            .collect();
        primitive.remove("file");
        primitive.remove("scale");
        if decompose {
            primitive.insert("vertices".into(), json!(vertices));
            primitive.insert("indices".into(), json!(triangles));
        } else {
            primitive.insert("vertices".into(), json!(hull_points(&vertices)));
        }
    }
    Ok(())
}

/// An assembly JSON text as a JSON value, if it has mesh primitives that name a `file`
/// (for [`inline_mesh_files`] to read once the assets are at hand); `None` otherwise.
pub fn with_mesh_files(document: &str) -> Option<Value> {
    let value = serde_json::from_str::<Value>(document).ok()?;
    let names_files = value["parts"].as_array().is_some_and(|parts| {
        parts.iter().any(|p| {
            matches!(
                p["primitive"]["type"].as_str(),
                Some("mesh" | "heightfield")
            ) && p["primitive"].get("file").is_some()
        })
    });
    names_files.then_some(value)
}

/// A PNG heightfield as MuJoCo reads it: its rows and columns (the image's height and
/// width) and its heights in the document's order (row 0 at −y: the image's last row),
/// normalised to [0, 1]; a colour image's gray level is the mean of its channels.
pub(crate) fn png_heights(bytes: &[u8]) -> std::result::Result<(u32, u32, Vec<f64>), String> {
    let side = gymfleet_assembly::MAX_HEIGHTFIELD_SIDE;
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder
        .read_info()
        .map_err(|e| format!("not a PNG heightfield: {e}"))?;
    let (width, height) = (reader.info().width, reader.info().height);
    if !(2..=side).contains(&width) || !(2..=side).contains(&height) {
        return Err(format!(
            "a heightfield image is 2 to {side} pixels on each side, this one {width} × {height}"
        ));
    }
    let mut buffer = vec![0; reader.output_buffer_size().ok_or("the PNG is too large")?];
    let frame = reader
        .next_frame(&mut buffer)
        .map_err(|e| format!("not a PNG heightfield: {e}"))?;
    let channels = frame.color_type.samples();
    let colour = matches!(frame.color_type, png::ColorType::Rgb | png::ColorType::Rgba);
    let mut gray = Vec::with_capacity((width * height) as usize);
    for row in buffer[..frame.buffer_size()].chunks(frame.line_size) {
        for pixel in row.chunks(channels).take(width as usize) {
            let level = if colour {
                (f64::from(pixel[0]) + f64::from(pixel[1]) + f64::from(pixel[2])) / 3.0
            } else {
                f64::from(pixel[0])
            };
            gray.push(level);
        }
    }
    let heights = crate::mjcf::hfield_heights(&gray, width as usize);
    Ok((height, width, heights))
}

/// A mesh's vertices and triangles (three indices into the vertices each).
pub type MeshData = (Vec<[f32; 3]>, Vec<[u32; 3]>);

/// Whether `bytes` has exactly a binary STL's size: an 80-byte header, a triangle count
/// `n`, then `n` records of 50 bytes.
fn is_binary_stl_size(bytes: &[u8]) -> bool {
    let Some(count) = bytes.get(80..84) else {
        return false;
    };
    let n = u32::from_le_bytes(count.try_into().expect("4 bytes")) as usize;
    n.checked_mul(50)
        .and_then(|b| b.checked_add(84))
        .is_some_and(|size| size == bytes.len())
        && bytes.starts_with(b"solid")
}

/// A mesh file's vertices (in the file's units; COLLADA's `<unit>` applied) and triangles.
pub fn load(bytes: &[u8], name: &str) -> std::result::Result<MeshData, String> {
    // No reader of the file system: an OBJ's material library is not needed (only the
    // geometry is), and a request must never make the server read its own files.
    fn no_files(path: &Path) -> std::io::Result<Vec<u8>> {
        Err(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("{} is not read: only the geometry is used", path.display()),
        ))
    }
    let lower = name.to_ascii_lowercase();
    if ![".stl", ".obj", ".dae"]
        .iter()
        .any(|ext| lower.ends_with(ext))
    {
        return Err(format!(
            "{}: expected a mesh file ending in .stl, .obj or .dae",
            crate::quote(name)
        ));
    }
    let loader = mesh_loader::Loader::with_custom_reader(no_files).merge_meshes(true);
    let scene = match loader.load_from_slice(bytes, name) {
        Ok(scene) => scene,
        // A binary STL whose 80-byte header starts with "solid" (many exporters write
        // one) can fail mesh-loader's ASCII parse past the point where it falls back to
        // binary. When the size is exactly a binary STL's, read it as one.
        Err(_) if lower.ends_with(".stl") && is_binary_stl_size(bytes) => {
            let mut patched = bytes.to_vec();
            patched[..5].copy_from_slice(b"     ");
            loader
                .load_from_slice(&patched, name)
                .map_err(|e| format!("{} is not a readable mesh: {e}", crate::quote(name)))?
        }
        Err(e) => {
            return Err(format!(
                "{} is not a readable mesh: {e}",
                crate::quote(name)
            ))
        }
    };
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for mesh in scene.meshes {
        let base = vertices.len() as u32;
        if vertices.len() + mesh.vertices.len() > MAX_FILE_VERTICES {
            return Err(format!(
                "{} has more than {MAX_FILE_VERTICES} vertices",
                crate::quote(name)
            ));
        }
        triangles.extend(mesh.faces.iter().map(|f| f.map(|i| i + base)));
        vertices.extend(mesh.vertices);
    }
    if let Some(bad) = vertices
        .iter()
        .position(|v| v.iter().any(|c| !c.is_finite()))
    {
        return Err(format!(
            "{}: vertex {bad} is not finite",
            crate::quote(name)
        ));
    }
    if triangles
        .iter()
        .flatten()
        .any(|&i| i as usize >= vertices.len())
    {
        return Err(format!(
            "{}: a face indexes a vertex it does not have",
            crate::quote(name)
        ));
    }
    if vertices.is_empty() {
        return Err(format!("{} holds no vertices", crate::quote(name)));
    }
    Ok((vertices, triangles))
}

/// The vertices of the convex hull of `points` (a few of them when the hull cannot be
/// taken: the validator then says that the mesh has no volume).
fn hull_points(points: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let p: Vec<parry3d::math::Vector> = points
        .iter()
        .map(|v| parry3d::math::Vector::new(v[0] as f32, v[1] as f32, v[2] as f32))
        .collect();
    match parry3d::transformation::try_convex_hull(&p) {
        // To 0.1 µm: the document stays short, the shape the same.
        Ok((hull, _)) => hull
            .iter()
            .map(|v| [v.x, v.y, v.z].map(|c| (f64::from(c) * 1e4).round() / 1e4))
            .collect(),
        Err(_) => points.iter().take(4).copied().collect(),
    }
}
