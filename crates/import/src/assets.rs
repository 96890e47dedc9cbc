//! A request's assets: a zip or tar (optionally gzipped) archive of the files a description
//! references (meshes), read into memory under bounds, and looked up by the references
//! descriptions use (`package://pkg/path`, `file://path`, relative paths).

use std::collections::BTreeMap;
use std::io::Read;

use crate::{ImportError, Result};

/// Most files an archive may hold (directories are not counted).
pub const MAX_ASSET_FILES: usize = 4096;
/// Most bytes the archive's files may hold once uncompressed, all together.
pub const MAX_ASSET_BYTES: u64 = 64 << 20;

/// The files of an assets archive, by their path inside it (`/`-separated, no leading `./`).
#[derive(Debug, Clone, Default)]
pub struct Assets {
    files: BTreeMap<String, Vec<u8>>,
}

fn bad(reason: String) -> ImportError {
    ImportError::Assets(reason)
}

impl Assets {
    /// Reads an archive: zip (`PK`), gzipped tar (`1f 8b`) or tar (`ustar` at byte 257).
    /// Refuses more than [`MAX_ASSET_FILES`] files or [`MAX_ASSET_BYTES`] uncompressed
    /// (counted as they inflate, so a zip bomb stops at the bound), absolute paths and `..`.
    pub fn from_archive(bytes: &[u8]) -> Result<Assets> {
        if bytes.starts_with(b"PK") {
            Assets::from_zip(bytes)
        } else if bytes.starts_with(&[0x1f, 0x8b]) {
            Assets::from_tar(flate2::read::GzDecoder::new(bytes))
        } else if bytes.len() >= 262 && &bytes[257..262] == b"ustar" {
            Assets::from_tar(bytes)
        } else {
            Err(bad(format!(
                "assets: expected a zip, tar or tar.gz archive; the {} bytes given are none of these",
                bytes.len()
            )))
        }
    }

    /// Files given directly (tests, the server's model library): path → bytes.
    pub fn from_files(files: impl IntoIterator<Item = (String, Vec<u8>)>) -> Assets {
        Assets {
            files: files.into_iter().collect(),
        }
    }

    /// Every file under `root` (recursively; hidden files and folders are skipped), by its
    /// path relative to `root`, with the archive's bounds.
    pub fn from_dir(root: &std::path::Path) -> Result<Assets> {
        let mut out = Budget::default();
        let mut folders = vec![root.to_path_buf()];
        while let Some(folder) = folders.pop() {
            let entries = std::fs::read_dir(&folder)
                .map_err(|e| bad(format!("assets: {}: {e}", folder.display())))?;
            let mut entries: Vec<_> = entries.filter_map(|e| e.ok()).collect();
            entries.sort_by_key(|e| e.file_name());
            for entry in entries {
                let path = entry.path();
                if entry.file_name().to_string_lossy().starts_with('.') {
                    continue;
                }
                let kind = entry
                    .file_type()
                    .map_err(|e| bad(format!("assets: {}: {e}", path.display())))?;
                if kind.is_dir() {
                    folders.push(path);
                } else if kind.is_file() {
                    let name = path
                        .strip_prefix(root)
                        .unwrap_or(&path)
                        .components()
                        .map(|c| c.as_os_str().to_string_lossy())
                        .collect::<Vec<_>>()
                        .join("/");
                    let file = std::fs::File::open(&path)
                        .map_err(|e| bad(format!("assets: {}: {e}", path.display())))?;
                    let declared = file.metadata().map_or(0, |m| m.len());
                    out.add(name, declared, file)?;
                }
            }
        }
        Ok(out.assets)
    }

    fn from_zip(bytes: &[u8]) -> Result<Assets> {
        let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes))
            .map_err(|e| bad(format!("assets: not a readable zip archive: {e}")))?;
        let mut out = Budget::default();
        for i in 0..archive.len() {
            let entry = archive
                .by_index(i)
                .map_err(|e| bad(format!("assets: zip entry {i}: {e}")))?;
            if entry.is_dir() {
                continue;
            }
            let name = entry
                .name()
                .map_err(|e| bad(format!("assets: zip entry {i}'s name: {e}")))?
                .into_owned();
            let declared = entry.size();
            out.add(name, declared, entry)?;
        }
        Ok(out.assets)
    }

    fn from_tar(reader: impl Read) -> Result<Assets> {
        let mut archive = tar::Archive::new(reader);
        let mut out = Budget::default();
        let entries = archive
            .entries()
            .map_err(|e| bad(format!("assets: not a readable tar archive: {e}")))?;
        for entry in entries {
            let entry = entry.map_err(|e| bad(format!("assets: tar entry: {e}")))?;
            if !entry.header().entry_type().is_file() {
                continue;
            }
            let name = entry
                .path()
                .map_err(|e| bad(format!("assets: tar entry name: {e}")))?
                .to_string_lossy()
                .into_owned();
            let declared = entry.header().size().unwrap_or(0);
            out.add(name, declared, entry)?;
        }
        Ok(out.assets)
    }

    /// Number of files.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// Whether there are no files.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// The file a description's reference names: `package://pkg/path` is looked up as
    /// `pkg/path`, then as `path` (the archive's root standing for the package);
    /// `file://path` and plain paths as they are (without a leading `/` or `./`).
    pub fn get(&self, reference: &str) -> Result<&[u8]> {
        let candidates: Vec<String> = if let Some(rest) = reference.strip_prefix("package://") {
            let rest = rest.trim_start_matches('/');
            let mut c = vec![normal(rest)];
            if let Some((_, path)) = rest.split_once('/') {
                c.push(normal(path));
            }
            c
        } else {
            vec![normal(
                reference.strip_prefix("file://").unwrap_or(reference),
            )]
        };
        for c in &candidates {
            if let Some(bytes) = self.files.get(c) {
                return Ok(bytes);
            }
        }
        // The archive's root may sit above or below the package's: one file whose path
        // ends with the reference's (or the other way round, at a `/`) is the one meant.
        let tail = |long: &str, short: &str| long.ends_with(&format!("/{short}"));
        let suffix_hits: Vec<&String> = self
            .files
            .keys()
            .filter(|k| candidates.iter().any(|c| tail(k, c) || tail(c, k)))
            .collect();
        if let [one] = suffix_hits.as_slice() {
            return Ok(&self.files[*one]);
        }
        let shown: Vec<&str> = self.files.keys().take(5).map(String::as_str).collect();
        Err(bad(format!(
            "assets: no file {} in the archive (looked for {}); it holds {} files{}",
            crate::quote(reference),
            candidates
                .iter()
                .map(|c| crate::quote(c))
                .collect::<Vec<_>>()
                .join(", "),
            self.files.len(),
            if shown.is_empty() {
                String::new()
            } else {
                format!(", e.g. {}", shown.join(", "))
            }
        )))
    }
}

/// A path inside an archive as it is looked up: no leading `./` or `/`, no empty parts.
fn normal(path: &str) -> String {
    path.split('/')
        .filter(|p| !p.is_empty() && *p != ".")
        .collect::<Vec<_>>()
        .join("/")
}

/// The files read so far and what the bounds still allow.
#[derive(Default)]
struct Budget {
    assets: Assets,
    bytes: u64,
}

impl Budget {
    /// Reads one file of `declared` bytes (the archive's word, a hint only).
    fn add(&mut self, name: String, declared: u64, entry: impl Read) -> Result<()> {
        if name.starts_with('/') || name.split(['/', '\\']).any(|p| p == "..") {
            return Err(bad(format!(
                "assets: {} escapes the archive's root (absolute, or with ..)",
                crate::quote(&name)
            )));
        }
        if self.assets.files.len() >= MAX_ASSET_FILES {
            return Err(bad(format!(
                "assets: more than {MAX_ASSET_FILES} files in the archive"
            )));
        }
        let left = MAX_ASSET_BYTES - self.bytes;
        // Sized by the archive's word, but never past the budget: a decompression bomb
        // that declares its size fills one buffer of at most the budget instead of
        // doubling a growing one past it (tests/tests/alloc_bounds.rs).
        let hint = usize::try_from(declared.min(left + 1)).unwrap_or(0);
        let mut data = Vec::with_capacity(hint);
        entry
            .take(left + 1)
            .read_to_end(&mut data)
            .map_err(|e| bad(format!("assets: {}: {e}", crate::quote(&name))))?;
        if data.len() as u64 > left {
            return Err(bad(format!(
                "assets: the archive's files hold more than {} MiB uncompressed (at {})",
                MAX_ASSET_BYTES >> 20,
                crate::quote(&name)
            )));
        }
        self.bytes += data.len() as u64;
        data.shrink_to_fit();
        self.assets.files.insert(normal(&name), data);
        Ok(())
    }
}
