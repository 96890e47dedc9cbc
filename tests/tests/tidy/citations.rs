//! Nothing in the repository cites a Markdown file that is not in it.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use super::repo_root;

/// Folders the citation check skips: build outputs, dependencies and vendored or
/// generated trees (they cite their own upstream's files).
const NOT_OURS: &[&str] = &[
    ".git",
    "target",
    "node_modules",
    "vendor",
    "fuzz/target",
    "client/js/src/gen",
    "client/assets",
];

fn text_files(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).expect("readable folder").flatten() {
        let path = entry.path();
        let rel = path
            .strip_prefix(root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if NOT_OURS
            .iter()
            .any(|skip| rel == *skip || rel.ends_with(&format!("/{skip}")))
        {
            continue;
        }
        if path.is_dir() {
            text_files(root, &path, out);
        } else if fs::read_to_string(&path).is_ok() {
            out.push(path);
        }
    }
}

/// The `NAME.md` words of `text`: maximal runs of path characters ending in `.md`.
fn cited_md(text: &str) -> Vec<&str> {
    let is_path = |c: char| c.is_ascii_alphanumeric() || "_./-".contains(c);
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while let Some(at) = text[i..].find(".md") {
        let end = i + at + 3;
        let boundary = bytes
            .get(end)
            .is_none_or(|b| !(b.is_ascii_alphanumeric() || *b == b'_'));
        if boundary {
            let start = text[..i + at]
                .char_indices()
                .rev()
                .find(|(_, c)| !is_path(*c))
                .map_or(0, |(k, c)| k + c.len_utf8());
            if start < i + at {
                out.push(&text[start..end]);
            }
        }
        i = end;
    }
    out
}

/// Nothing in the repository cites a Markdown file that is not in it (the specification
/// and style guide the project started from live in docs/ since issue DOC). A citation
/// resolves as a path from the root, from the citing file's folder, or as the name of a
/// Markdown file somewhere in the tree (prose says "its PATCHES.md").
#[test]
fn every_cited_markdown_file_is_in_the_repository() {
    let root = repo_root();
    let mut files = Vec::new();
    text_files(&root, &root, &mut files);
    let md: BTreeSet<String> = files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| {
            p.strip_prefix(&root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/")
        })
        .collect();
    let mut names: BTreeSet<&str> = md.iter().map(|p| p.rsplit('/').next().unwrap()).collect();
    // The vendored crates' own notes (vendor/<crate>/PATCHES.md) are ours to cite.
    let vendored: Vec<String> = fs::read_dir(root.join("vendor"))
        .into_iter()
        .flatten()
        .flatten()
        .flat_map(|crate_dir| {
            fs::read_dir(crate_dir.path())
                .into_iter()
                .flatten()
                .flatten()
        })
        .map(|f| f.file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".md"))
        .collect();
    names.extend(vendored.iter().map(String::as_str));
    let mut missing = BTreeSet::new();
    // Inside the tree only: `../shared/X.md` names a file beside the checkout.
    let inside = |path: PathBuf| {
        path.canonicalize()
            .is_ok_and(|p| p.is_file() && p.starts_with(root.canonicalize().unwrap()))
    };
    // This file's own fixtures are not citations.
    let this = root.join("tests/tests/tidy/citations.rs");
    for file in files.iter().filter(|f| **f != this) {
        let text = fs::read_to_string(file).unwrap();
        let dir = file.parent().unwrap();
        for cited in cited_md(&text) {
            let cited = cited.trim_start_matches("./");
            let name = cited.rsplit('/').next().unwrap();
            if md.contains(cited)
                || inside(root.join(cited))
                || inside(dir.join(cited))
                || names.contains(name)
            {
                continue;
            }
            let rel = file.strip_prefix(&root).unwrap().display().to_string();
            missing.insert(format!("{rel} cites {cited}"));
        }
    }
    assert!(
        missing.is_empty(),
        "citations of files not in the repository:\n{missing:#?}"
    );
}

#[test]
fn the_citation_check_finds_md_names_and_ignores_longer_words() {
    assert_eq!(
        cited_md("see ../shared/PRODUCT.md §2, docs/design.md. Not .mdx or x.mdbook"),
        ["../shared/PRODUCT.md", "docs/design.md"]
    );
}
