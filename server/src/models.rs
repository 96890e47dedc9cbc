//! The model library (`--models DIR`): descriptions a request names by `model` instead of
//! sending a document, listed by `ListModels`. Loaded once at start: every file is read,
//! converted (MJCF, URDF) and validated then, so a broken library stops the server with the
//! file named, not a request later. Mesh files the descriptions reference are read from
//! the directory (and its subdirectories: `package://` and relative paths resolve against
//! it) into the converted documents.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use gymfleet_import::Format;

use crate::error::StartupError;

type Result<T, E = StartupError> = std::result::Result<T, E>;

/// File extensions the library reads, and the format each implies (JSON is checked).
const EXTENSIONS: [&str; 4] = ["json", "xml", "mjcf", "urdf"];

/// One model of the library.
#[derive(Debug, Clone, PartialEq)]
pub struct LibraryModel {
    /// Its assembly JSON (converted at load when the file is MJCF).
    pub document: String,
    /// The file's format.
    pub format: Format,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Values per action (the actuated DOFs).
    pub action_dim: usize,
    /// The file it came from.
    pub path: PathBuf,
}

/// The models of one directory, by name (the file name without its extension).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelLibrary {
    models: BTreeMap<String, LibraryModel>,
}

fn library_error(path: &Path, reason: impl Into<String>) -> StartupError {
    StartupError::ModelLibrary {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

impl ModelLibrary {
    /// Reads every `.json`, `.xml`, `.mjcf` and `.urdf` file of `dir` (not its
    /// subdirectories), converting and validating each; the first failure names its file.
    pub fn load(dir: &Path) -> Result<ModelLibrary> {
        let entries = std::fs::read_dir(dir).map_err(|e| library_error(dir, e.to_string()))?;
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.is_file()
                    && p.extension()
                        .and_then(|e| e.to_str())
                        .is_some_and(|e| EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
            })
            .collect();
        paths.sort();
        let mut models = BTreeMap::new();
        // The directory's files, read once and only if a description references meshes.
        let mut assets: Option<gymfleet_import::Assets> = None;
        for path in paths {
            let name = path
                .file_stem()
                .and_then(|s| s.to_str())
                .ok_or_else(|| library_error(&path, "the file name is not UTF-8"))?
                .to_string();
            let text =
                std::fs::read_to_string(&path).map_err(|e| library_error(&path, e.to_string()))?;
            let model = Self::model(dir, &path, &text, &mut assets)?;
            if let Some(other) = models.insert(name.clone(), model) {
                return Err(library_error(
                    &path,
                    format!("model {name:?} is also {}", other.path.display()),
                ));
            }
        }
        Ok(ModelLibrary { models })
    }

    fn model(
        dir: &Path,
        path: &Path,
        text: &str,
        assets: &mut Option<gymfleet_import::Assets>,
    ) -> Result<LibraryModel> {
        let converted = gymfleet_import::convert(text, None, None)
            .map_err(|e| library_error(path, e.to_string()))?;
        let (mut document, format) = (converted.json, converted.format);
        if let Some(mut value) = gymfleet_import::with_mesh_files(&document) {
            if assets.is_none() {
                *assets = Some(
                    gymfleet_import::Assets::from_dir(dir)
                        .map_err(|e| library_error(dir, e.to_string()))?,
                );
            }
            gymfleet_import::inline_mesh_files(&mut value, assets.as_ref())
                .map_err(|e| library_error(path, e.to_string()))?;
            document = value.to_string();
        }
        let assembly =
            gymfleet_assembly::parse(&document).map_err(|e| library_error(path, e.to_string()))?;
        Ok(LibraryModel {
            dofs: assembly.total_dof(),
            action_dim: assembly.action_dim(),
            document,
            format,
            path: path.to_path_buf(),
        })
    }

    /// The model named `name`.
    pub fn get(&self, name: &str) -> Option<&LibraryModel> {
        self.models.get(name)
    }

    /// Every model, by name.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &LibraryModel)> {
        self.models.iter().map(|(n, m)| (n.as_str(), m))
    }

    /// How many models it holds.
    pub fn len(&self) -> usize {
        self.models.len()
    }

    /// Whether it holds none.
    pub fn is_empty(&self) -> bool {
        self.models.is_empty()
    }
}
