//! Robot descriptions from elsewhere, converted into gymfleet's assembly JSON (docs/design.md
//! §6.3), so that everything downstream (validation with paths, limits, tasks, batches,
//! MCP) works unchanged on them.
//!
//! This crate owns the conversions and the request's assets, and nothing else: it reads
//! text (with `roxmltree`), archives (`zip`, `tar`, `flate2`) and mesh files
//! (`mesh-loader`), and writes a JSON document; it knows nothing of physics or networks,
//! and the document it writes still goes through `gymfleet_assembly::parse` like any
//! other. The converters build the typed document (`gymfleet_assembly::Document` and its
//! `*Def` parts, serialised once at the end), never JSON by field name; only
//! [`inline_mesh_files`], which also serves documents users write in JSON, edits JSON.
//!
//! - **MJCF** ([`mjcf_to_document`]): the subset MuJoCo's classic models use — default
//!   classes, `compiler` angle units, `inertiafromgeom` and `settotalmass`, bodies with
//!   `pos` and `quat`/`euler`/`axisangle`, box/sphere/capsule/cylinder geoms with `size`
//!   or `fromto`, hinge/slide/ball joints (several per body) with damping, armature,
//!   springs (`stiffness`, `springref`) and `frictionloss`, a top-level body's free joint
//!   (the floating base), bodies without joints (welded), explicit `<inertial>`,
//!   `contype`/`conaffinity`, motors (`gear`, `ctrlrange` → `max_effort`; joints without
//!   a motor are passive), a fluid (`<option density viscosity>`), mesh geoms
//!   (`<asset><mesh file scale>` under `compiler meshdir`, or inline `vertex`),
//!   `<include file>` ([`expand_includes`]: from the assets, or beside a converted file),
//!   and `<equality>` `<connect>`/`<weld>` between bodies (loop-closing joints, unobserved).
//! - **URDF** ([`urdf_to_document`]): links with `<collision>` boxes, cylinders, spheres,
//!   capsules and meshes, `<inertial>`, revolute/continuous/prismatic/fixed joints with
//!   limits, effort, damping and friction, a `floating` joint from the world (the floating
//!   base).
//! - **Meshes** ([`inline_mesh_files`]): a `{"type": "mesh", "file": …}` primitive (what
//!   URDF meshes become, or written in JSON) is read from the request's [`Assets`] (a zip,
//!   tar or tar.gz archive; `package://` and relative paths) and replaced by its vertices,
//!   so the document is self-contained (env states carry it).
//!
//! Everything else is an error naming the element and its line, or, when it has no effect
//! on the dynamics, a warning.
//!
//! # Modules
//!
//! Both converters build the typed `gymfleet_assembly::Document` (its `*Def` types
//! serialise as well as parse, absent options left out) and serialise it once
//! (`Converted::of`). `convert` (the format given or detected by `Format::detect`, then
//! `to_json`) is the one way a description becomes a document: the server's requests and
//! `ConvertDocument`, its model library, and `convert_file` (the load client's files and
//! `examples/convert.rs`, which prints a conversion) all go through it. Errors name the
//! element and line (or the archive entry and the JSON path); constructs that can be
//! ignored become warnings.
//!
//! - `mjcf/` reads MJCF with `roxmltree`. `mod.rs`: the converter and the document's
//!   assembly, dispatching the top-level elements (settings first, then the rest in
//!   document order, then the bodies, then what names bodies: equalities, contacts,
//!   sensors; keyframes last, in `finish`). Default classes and childclasses are resolved
//!   per attribute; each geom is an instance with its own part; a body's extra geoms and
//!   joint-less bodies are welded; several joints per body are chained through helper
//!   instances; motors are kept as a joint's `gear` (actions are MuJoCo's ctrl) and
//!   `max_effort`, and a joint's `ref` as its `reference`; every `<site>` in a body and
//!   every named body's origin is kept as a site; world geoms and joint-less bodies below
//!   the world are `fixed` instances; a top-level body with a free joint and joints below
//!   it is the floating base, one with no joints below it a free body; `mocap="true"`
//!   bodies are mocap instances; `<flag>`s that switch off contacts, limits, equalities,
//!   constraints or gravity are honoured in the document they write. One file per element:
//!   - `attributes.rs`: attributes through default classes, compiler and `<option>`
//!     settings, frames.
//!   - `actuators.rs`: every `<actuator>` element read as MuJoCo's reader reads it, into
//!     its general form from its class's one actuator default (`actuator_form.rs`: the
//!     general form and each tag's shortcut, MuJoCo's `mjs_setTo*`); then either plain
//!     joint motors, in the joints' order, kept on their joints (`gear`, `max_effort`), or
//!     every actuator into `assembly.actuators`, in order.
//!   - `bodies.rs`: the tree, helpers, welds, inertials and sites (a body's parts read one by
//!     one in `body_parts.rs`); `joints.rs`; `geoms.rs`;
//!     `soft.rs`: a geom's `solref`/`solimp`/`margin` as its material's `soft_contact`.
//!   - `meshes.rs`: `<asset><mesh>` and mesh geoms as `{"type": "mesh", "file"}` under
//!     `meshdir`.
//!   - `tendons.rs`: `<tendon><fixed>` and `<tendon><spatial>` through sites into
//!     `assembly.tendons` (friction loss, wrapping geoms and pulleys refused).
//!   - `hfields.rs`: `<asset><hfield>` (inline, flat or a PNG, normalised and flipped into
//!     `hfield_data` order) and hfield geoms into heightfield primitives, each base a box
//!     under its terrain (a PNG is read with the meshes, `crate::meshes`).
//!   - `contacts.rs`: `<contact>` `<exclude>` and `<pair>` into `assembly.contacts` (body
//!     names to their geoms' instances, read after `<worldbody>`).
//!   - `equality.rs`: `<equality>` `<connect>`/`<weld>` between named bodies
//!     (`Converter::bodies`) into loop-closing joints (ball or fixed, `"observed": false`),
//!     and `<joint>`/`<tendon>` into `assembly.couplings`, read after `<worldbody>`.
//!   - `keyframes.rs`: `<keyframe><key>` into `assembly.keyframes`, through MuJoCo's qpos
//!     layout recorded joint by joint as the tree is converted (`QposSlot`; a free base's
//!     body-frame pose becomes its instance's).
//!   - `sensors.rs`: `<sensor>` into `assembly.sensors`, after the bodies, through the
//!     sites the conversion kept (`Converter::site_of`, `body_sites`; a world `<site>` is a
//!     site of the world's instance, after every body's) and the geoms' instances.
//!   - `include.rs`: `<include file>` spliced before parsing, from a reader the caller
//!     gives (the assets in `to_json`, or `to_json_in` with the model's folder among them,
//!     as a request's `document_path` gives it; in `convert_file`, the file's folder and up
//!     to three folders above it). Every include and mesh file is resolved from the main
//!     file's folder as MuJoCo resolves them (`asset_path`, `../` allowed while it stays
//!     inside the assets); nesting and size are bounded.
//! - `frame.rs`: frames composed in f64 with `glam`, and rotations written as the
//!   document's Euler angles.
//! - `urdf.rs` reads URDF the same way: the tree is walked from its one root link, or from
//!   a `floating` joint's child when the root is an empty world link; each `<collision>` is
//!   an instance, `<inertial>` is moved into the instance's frame, and meshes become
//!   `{"type": "mesh", "file"}`. `urdf/tree.rs` reads the links and joints into the checked
//!   tree and walks it; `urdf/links.rs` and `urdf/joints.rs` convert the two.
//! - `assets.rs` reads a request's archive (zip, tar, tar.gz; or a folder,
//!   `Assets::from_dir`) under bounds (`MAX_ASSET_FILES` = 4096 files, `MAX_ASSET_BYTES` =
//!   64 MiB inflated, counted as they inflate; no absolute paths or `..`) and resolves
//!   `package://` and relative references.
//! - `meshes.rs` reads STL, OBJ and DAE with `mesh-loader` (never the file system) and
//!   replaces each mesh `file` by its vertices (a hull's only), so the document is
//!   self-contained.
//! - `xml.rs` holds what both XML readers share: errors naming the element and its line,
//!   warnings given once, unique names.

mod assets;
mod frame;
mod meshes;
mod mjcf;
mod urdf;
mod xml;

pub use assets::{Assets, MAX_ASSET_BYTES, MAX_ASSET_FILES};
pub use meshes::{
    inline_mesh_files, load as load_mesh, with_mesh_files, MeshData, MAX_FILE_VERTICES,
};
pub use mjcf::{
    expand_includes, mjcf_to_document, mjcf_to_document_in, MAX_BODY_DEPTH, MAX_INCLUDED_BYTES,
    MAX_INCLUDE_DEPTH,
};
pub use urdf::urdf_to_document;

/// `s` quoted, cut to a readable length (names and paths echoed in errors).
pub(crate) fn quote(s: &str) -> String {
    const MAX: usize = 120;
    if s.chars().count() <= MAX {
        format!("\"{s}\"")
    } else {
        format!("\"{}…\"", s.chars().take(MAX).collect::<String>())
    }
}

/// A description's format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// gymfleet's assembly JSON.
    Json,
    /// ROS's Unified Robot Description Format.
    Urdf,
    /// MuJoCo's XML.
    Mjcf,
}

impl Format {
    /// The format's name as users write it: `JSON`, `URDF`, `MJCF`.
    pub fn name(self) -> &'static str {
        match self {
            Format::Json => "JSON",
            Format::Urdf => "URDF",
            Format::Mjcf => "MJCF",
        }
    }

    /// The format of `text`: XML whose root element is `<mujoco>` is MJCF, `<robot>` URDF;
    /// anything that does not start with `<` is JSON (and the JSON parser says what is
    /// wrong with it). An XML document of another root, or not well-formed, is an error.
    pub fn detect(text: &str) -> Result<Format> {
        if !text.trim_start().starts_with('<') {
            return Ok(Format::Json);
        }
        let doc = roxmltree::Document::parse(text).map_err(|e| ImportError::Xml(e.to_string()))?;
        match doc.root_element().tag_name().name() {
            "mujoco" => Ok(Format::Mjcf),
            "robot" => Ok(Format::Urdf),
            other => Err(ImportError::Unsupported {
                element: other.to_string(),
                line: doc.text_pos_at(doc.root_element().range().start).row,
                reason: "not a description gymfleet reads: MJCF's root is <mujoco>, URDF's <robot>"
                    .into(),
            }),
        }
    }
}

/// A description as assembly JSON: what [`convert`] returns.
#[derive(Debug, Clone, PartialEq)]
pub struct Conversion {
    /// The assembly JSON text.
    pub json: String,
    /// What the conversion left out, one line each (see [`Converted::warnings`]).
    pub warnings: Vec<String>,
    /// The description's format, as given or detected.
    pub format: Format,
}

/// `text` as assembly JSON: the one way a description becomes a document (the server's
/// requests and model library, [`convert_file`]). Its format is `format`, or detected
/// ([`Format::detect`]) when `None`; its mesh files are read from `assets`
/// ([`to_json`]). Its relative references (MJCF includes and mesh files) are read from
/// the assets' root: [`convert_in`] reads them from the document's own folder.
pub fn convert(text: &str, format: Option<Format>, assets: Option<&Assets>) -> Result<Conversion> {
    convert_in(text, format, assets, "")
}

/// [`convert`] for a document that sits in `folder` of its `assets` (`""`: the root;
/// `"fetch"` for `fetch/push.xml`): an MJCF document's `<include file>`s and mesh files
/// are read from that folder, `../` included, as MuJoCo reads them from the folder of the
/// model file ([`asset_path`]).
pub fn convert_in(
    text: &str,
    format: Option<Format>,
    assets: Option<&Assets>,
    folder: &str,
) -> Result<Conversion> {
    let format = match format {
        Some(format) => format,
        None => Format::detect(text)?,
    };
    let (json, warnings) = to_json_in(text, format, assets, folder)?;
    Ok(Conversion {
        json,
        warnings,
        format,
    })
}

/// `text` in `format` as assembly JSON text, with the conversion's warnings, its mesh
/// files read from `assets` into the document ([`inline_mesh_files`]). JSON without mesh
/// files passes through unchanged (its checks are `gymfleet_assembly::parse`'s).
pub fn to_json(
    text: &str,
    format: Format,
    assets: Option<&Assets>,
) -> Result<(String, Vec<String>)> {
    to_json_in(text, format, assets, "")
}

/// [`to_json`] for a document in `folder` of its assets (see [`convert_in`]).
pub fn to_json_in(
    text: &str,
    format: Format,
    assets: Option<&Assets>,
    folder: &str,
) -> Result<(String, Vec<String>)> {
    let mut converted = match format {
        Format::Json => {
            if assets.is_none() {
                return Ok((text.to_string(), Vec::new()));
            }
            match serde_json::from_str(text) {
                Ok(document) => Converted {
                    document,
                    warnings: Vec::new(),
                },
                // Not JSON: the assembly parser says what is wrong with it.
                Err(_) => return Ok((text.to_string(), Vec::new())),
            }
        }
        Format::Mjcf => match assets {
            Some(assets) => mjcf_to_document_in(
                &expand_includes(text, &mut |file| {
                    let bytes = assets
                        .get(&asset_path(folder, file)?)
                        .map_err(|e| e.to_string())?;
                    String::from_utf8(bytes.to_vec()).map_err(|_| "not UTF-8 text".to_string())
                })?,
                folder,
            )?,
            None => mjcf_to_document_in(text, folder)?,
        },
        Format::Urdf => urdf_to_document(text)?,
    };
    inline_mesh_files(&mut converted.document, assets)?;
    Ok((converted.document.to_string(), converted.warnings))
}

/// A description file as assembly JSON text, with the conversion's warnings. An MJCF
/// file's includes are read from its folder (`../` included), as MuJoCo reads them. Mesh
/// files it references are read from the folder that holds it, or else from the folders
/// above (up to three: a ROS package keeps `urdf/` beside `meshes/`, a MuJoCo scene
/// names `../stls/…`), the first that has them all.
pub fn convert_file(path: &std::path::Path) -> Result<(String, Vec<String>)> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| ImportError::Assets(format!("{}: {e}", path.display())))?;
    let format = Format::detect(&text)?;
    let here = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => std::path::Path::new("."),
    };
    // MuJoCo reads includes from the main model's folder.
    let text = if format == Format::Mjcf {
        expand_includes(&text, &mut |file| {
            std::fs::read_to_string(here.join(file)).map_err(|e| e.to_string())
        })?
    } else {
        text
    };
    // The model's folder, and up to three above it, each tried as the root of its assets:
    // the first whose files resolve every reference (a `../` one included) is the one.
    let mut best_error: Option<ImportError> = None;
    for root in here.ancestors().take(4) {
        // The model's folder as seen from `root` (forward slashes, as in archives).
        let folder = here
            .strip_prefix(root)
            .unwrap_or(std::path::Path::new(""))
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join("/");
        let root = if root.as_os_str().is_empty() {
            std::path::Path::new(".")
        } else {
            root
        };
        let attempt = convert_in(&text, Some(format), None, &folder).and_then(|plain| {
            if with_mesh_files(&plain.json).is_none() {
                return Ok((plain.json, plain.warnings));
            }
            to_json_in(&text, format, Some(&Assets::from_dir(root)?), &folder)
        });
        match attempt {
            Ok(converted) => return Ok(converted),
            // A file missing under a root that holds the model's references says more
            // than a reference that climbs above a lower root.
            Err(e) => {
                let climbs = |e: &ImportError| e.to_string().contains("climbs above");
                if best_error.as_ref().is_none_or(climbs) {
                    best_error = Some(e);
                }
            }
        }
    }
    Err(best_error.unwrap_or_else(|| ImportError::Assets("no folder to read meshes from".into())))
}

/// `reference` (a relative path a description in `folder` of its assets names: an
/// include, a mesh file) as a path from the assets' root, with `.` and `..` resolved as
/// MuJoCo resolves them against the model file's folder. A path that climbs above the
/// root is refused: the assets must hold the folder it names. An absolute path, or a
/// `package://` or `file://` reference, is left to [`Assets::get`].
pub fn asset_path(folder: &str, reference: &str) -> std::result::Result<String, String> {
    if reference.starts_with('/') || reference.contains("://") {
        return Ok(reference.to_string());
    }
    let mut parts: Vec<&str> = Vec::new();
    for part in folder
        .split(['/', '\\'])
        .chain(reference.split(['/', '\\']))
    {
        match part {
            "" | "." => {}
            ".." => {
                if parts.pop().is_none() {
                    return Err(format!(
                        "{} climbs above the assets' root{}: send the folder that holds it \
                         as the assets, and the model's path in it as document_path (Python: \
                         make(path, assets=folder) does this when path is inside folder)",
                        quote(reference),
                        if folder.is_empty() {
                            String::new()
                        } else {
                            format!(" from the model's folder {}", quote(folder))
                        }
                    ));
                }
            }
            part => parts.push(part),
        }
    }
    Ok(parts.join("/"))
}

/// A converted description: the assembly JSON and what the conversion left out.
#[derive(Debug, Clone, PartialEq)]
pub struct Converted {
    /// The gymfleet assembly document.
    pub document: serde_json::Value,
    /// Constructs without effect on the dynamics that were ignored (colours, cameras,
    /// lights …) or approximated (MJCF's `RK4` integrator …), one line each, with the line
    /// number.
    pub warnings: Vec<String>,
}

impl Converted {
    /// A typed document as the converted JSON, with the conversion's warnings.
    pub(crate) fn of(document: &gymfleet_assembly::Document, warnings: Vec<String>) -> Self {
        Converted {
            // A document's fields are strings, numbers, arrays and maps: always JSON.
            document: serde_json::to_value(document).expect("a document serialises"),
            warnings,
        }
    }
}

/// Why a description could not be converted. Every error names the element and its line
/// (or, for assets, the archive entry or the document path).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImportError {
    /// The assets archive, or a mesh file in it, cannot be used.
    #[error("{0}")]
    Assets(String),
    /// The text is not well-formed XML.
    #[error("not well-formed XML: {0}")]
    Xml(String),
    /// A construct that matters to the dynamics and that gymfleet cannot express (yet).
    #[error("line {line}: <{element}>: {reason}")]
    Unsupported {
        /// The element's name.
        element: String,
        /// Its line, from 1.
        line: u32,
        /// What is not supported, and what to do instead if anything.
        reason: String,
    },
    /// A value that is missing or does not parse.
    #[error("line {line}: <{element} {attribute}=…>: {reason}")]
    BadAttribute {
        /// The element's name.
        element: String,
        /// The attribute's name.
        attribute: String,
        /// Its line, from 1.
        line: u32,
        /// What was expected and what was found.
        reason: String,
    },
}

/// Result alias for this crate.
pub type Result<T, E = ImportError> = std::result::Result<T, E>;
