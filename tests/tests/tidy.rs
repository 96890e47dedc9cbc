//! Tidy checks on the source tree itself (as rust-analyzer keeps its own `tidy` tests):
//! no crate's top-level modules import each other in a loop (ARCHITECTURE.md,
//! "Invariants"), and the check is shown to catch one on a small fixture.
//!
//! A crate's top-level modules are the files and folders of its `src/` (a file
//! `src/a.rs` and its children `src/a/…` are module `a`); module `a` depends on `b` when
//! its code names `crate::b` (in a `use`, a `use crate::{b::…}` group, or a path). Comments
//! and string literals are skipped, so a doc link does not count. Children may name their
//! parent with `super::`, which stays inside the module.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// Every crate of the workspace whose modules are checked, by its `src/` folder.
const CRATES: &[&str] = &[
    "crates/assembly/src",
    "crates/batch/src",
    "crates/env/src",
    "crates/import/src",
    "apps/load/src",
    "apps/mcp/src",
    "crates/physics/src",
    "crates/render/src",
    "server/src",
    "client/src",
    "client/python/src",
    "proto/src",
];

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// `src` with comments and string literals (plain and raw) removed.
fn code_only(src: &str) -> String {
    let b = src.as_bytes();
    let mut out = String::with_capacity(src.len());
    // What is dropped keeps its line breaks, so that lines still count (function lengths).
    let newlines = |text: &str| "\n".repeat(text.matches('\n').count());
    let mut i = 0;
    while i < b.len() {
        if b[i..].starts_with(b"//") {
            i = src[i..].find('\n').map_or(b.len(), |j| i + j);
        } else if b[i..].starts_with(b"/*") {
            let end = src[i + 2..].find("*/").map_or(b.len(), |j| i + 2 + j + 2);
            out.push_str(&newlines(&src[i..end]));
            i = end;
        } else if b[i] == b'r' && (b[i + 1..].starts_with(b"#") || b[i + 1..].starts_with(b"\"")) {
            let hashes = b[i + 1..].iter().take_while(|&&c| c == b'#').count();
            if b.get(i + 1 + hashes) == Some(&b'"') {
                let close = format!("\"{}", "#".repeat(hashes));
                let from = i + 2 + hashes;
                let end = src[from..]
                    .find(&close)
                    .map_or(b.len(), |j| from + j + close.len());
                out.push_str("\"\"");
                out.push_str(&newlines(&src[i..end]));
                i = end;
            } else {
                out.push('r');
                i += 1;
            }
        } else if b[i] == b'"' {
            let mut j = i + 1;
            while j < b.len() && b[j] != b'"' {
                j += if b[j] == b'\\' { 2 } else { 1 };
            }
            out.push_str("\"\"");
            out.push_str(&newlines(&src[i..j.min(b.len())]));
            i = j + 1;
        } else if b[i] == b'\'' && b.get(i + 2) == Some(&b'\'') {
            // A char literal such as '"' or '{'.
            i += 3;
        } else if b[i] == b'\'' && b.get(i + 1) == Some(&b'\\') {
            i = src[i + 2..].find('\'').map_or(b.len(), |j| i + 2 + j + 1);
        } else {
            let c = src[i..].chars().next().expect("in bounds");
            out.push(c);
            i += c.len_utf8();
        }
    }
    out
}

fn ident_at(s: &str) -> Option<&str> {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    (end > 0 && !s.starts_with(|c: char| c.is_ascii_digit())).then(|| &s[..end])
}

/// The top-level modules that `code` names through `crate::`.
fn crate_paths(code: &str) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for (at, _) in code.match_indices("crate::") {
        if at > 0 && code[..at].ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_') {
            continue; // `$crate::` in a macro, or part of a longer name
        }
        let rest = code[at + "crate::".len()..].trim_start();
        if let Some(group) = rest.strip_prefix('{') {
            // The group's top-level items: `a::X, b::{Y, Z}, c`.
            let mut depth = 0usize;
            let mut item_start = 0;
            for (k, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        names.extend(ident_at(group[item_start..k].trim_start()).map(String::from));
                        break;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        names.extend(ident_at(group[item_start..k].trim_start()).map(String::from));
                        item_start = k + 1;
                    }
                    _ => {}
                }
            }
        } else if let Some(name) = ident_at(rest) {
            names.insert(name.to_string());
        }
    }
    names
}

/// Every `.rs` file under `dir`, with the top-level module it belongs to.
fn module_files(src: &Path) -> Vec<(String, PathBuf)> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in fs::read_dir(dir).expect("a readable source folder") {
            let path = entry.expect("a folder entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    walk(src, &mut files);
    files
        .into_iter()
        .filter_map(|path| {
            let first = path.strip_prefix(src).ok()?.components().next()?;
            let name = first
                .as_os_str()
                .to_str()?
                .trim_end_matches(".rs")
                .to_string();
            (name != "lib" && name != "main").then_some((name, path))
        })
        .collect()
}

/// The crate's module graph: each top-level module and the others it names.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, path) in module_files(src) {
        let text = fs::read_to_string(&path).expect("a readable source file");
        graph
            .entry(module)
            .or_default()
            .extend(crate_paths(&code_only(&text)));
    }
    let modules: BTreeSet<String> = graph.keys().cloned().collect();
    for (module, uses) in &mut graph {
        uses.retain(|u| u != module && modules.contains(u));
    }
    graph
}

/// The graph's cycles: its strongly connected components of more than one module
/// (Tarjan's algorithm), each sorted.
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Tarjan<'g> {
        graph: &'g BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        found: Vec<Vec<String>>,
    }
    impl<'g> Tarjan<'g> {
        fn visit(&mut self, v: &'g str) {
            let n = self.index.len();
            self.index.insert(v, n);
            self.low.insert(v, n);
            self.stack.push(v);
            for w in &self.graph[v] {
                let w = w.as_str();
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let low = self.low[v].min(self.low[w]);
                    self.low.insert(v, low);
                } else if self.stack.contains(&w) {
                    let low = self.low[v].min(self.index[w]);
                    self.low.insert(v, low);
                }
            }
            if self.low[v] == self.index[v] {
                let mut component = Vec::new();
                while let Some(w) = self.stack.pop() {
                    component.push(w.to_string());
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    self.found.push(component);
                }
            }
        }
    }
    let mut t = Tarjan {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !t.index.contains_key(v.as_str()) {
            t.visit(v);
        }
    }
    t.found
}

#[test]
fn no_crate_has_modules_that_import_each_other_in_a_loop() {
    let root = repo_root();
    let mut report = Vec::new();
    for src in CRATES {
        let graph = module_graph(&root.join(src));
        assert!(
            graph.len() > 1 || *src == "proto/src",
            "{src}: no modules found"
        );
        for cycle in cycles(&graph) {
            let edges: Vec<String> = cycle
                .iter()
                .flat_map(|m| {
                    graph[m]
                        .iter()
                        .filter(|u| cycle.contains(u))
                        .map(move |u| format!("{m} -> {u}"))
                })
                .collect();
            report.push(format!(
                "{src}: {} ({})",
                cycle.join(", "),
                edges.join("; ")
            ));
        }
    }
    assert!(
        report.is_empty(),
        "modules that import each other in a loop:\n{}",
        report.join("\n")
    );
}

#[test]
fn the_check_finds_a_loop_and_ignores_comments_strings_and_children() {
    let dir = std::env::temp_dir().join(format!("gymfleet-tidy-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(dir.join("a")).unwrap();
    let files = [
        (
            "lib.rs",
            "mod a;\nmod b;\nmod c;\nmod d;\nuse crate::a::A;\n",
        ),
        ("a.rs", "mod inner;\npub struct A;\n"),
        // A child of `a` naming `b` makes `a` depend on `b`.
        (
            "a/inner.rs",
            "use super::A;\nfn f() -> crate::b::B { todo!() }\n",
        ),
        ("b.rs", "use crate::{c::C, d};\npub struct B(C);\n"),
        (
            "c.rs",
            "/// Links [`crate::a::A`] in a doc comment.\npub struct C;\n",
        ),
        ("d.rs", "const S: &str = \"crate::a\";\n// crate::b\n"),
    ];
    for (name, text) in files {
        fs::write(dir.join(name), text).unwrap();
    }
    let graph = module_graph(&dir);
    assert_eq!(graph["a"], BTreeSet::from(["b".to_string()]));
    assert_eq!(
        graph["b"],
        BTreeSet::from(["c".to_string(), "d".to_string()])
    );
    assert!(graph["c"].is_empty(), "doc links do not count");
    assert!(graph["d"].is_empty(), "strings and comments do not count");
    assert!(cycles(&graph).is_empty());

    // Now `c` names `a` in code: a → b → c → a.
    fs::write(dir.join("c.rs"), "pub struct C(crate::a::A);\n").unwrap();
    let graph = module_graph(&dir);
    assert_eq!(
        cycles(&graph),
        vec![vec!["a".to_string(), "b".to_string(), "c".to_string()]]
    );
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn code_only_keeps_code_and_drops_comments_and_literals() {
    let src = "let x = r#\"crate::a \"quoted\"\"#; /* crate::b */ let c = '\"'; crate::d::f();";
    assert_eq!(
        crate_paths(&code_only(src)),
        BTreeSet::from(["d".to_string()])
    );
}

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
    let this = root.join("tests/tests/tidy.rs");
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

/// The longest a non-test function may be, in lines from its `fn` to its closing brace.
const MAX_FN_LINES: usize = 80;

/// Functions longer than [`MAX_FN_LINES`] today, each at most as long as it is now: the
/// list may only shrink (a listed function that grows, or one no longer over the bound,
/// fails the check, so that its entry goes). Each is to be split along its seams (issue
/// M4); the reason says which.
const LONG_FNS: &[(&str, &str, usize, &str)] = &[
    (
        "crates/import/src/mjcf/geoms.rs",
        "geom",
        106,
        "the instance's parts: contact attributes, material, records",
    ),
    (
        "crates/env/src/terms/resolve.rs",
        "resolve",
        247,
        "a term kind per arm: serde enums",
    ),
    (
        "crates/import/src/mjcf/bodies.rs",
        "body",
        231,
        "inertial, frames, children",
    ),
    (
        "crates/env/src/terms/quantity.rs",
        "quantity",
        225,
        "a quantity per arm: serde enums",
    ),
    (
        "crates/physics/src/build.rs",
        "build",
        213,
        "bodies, joints, colliders, limits",
    ),
    (
        "crates/import/src/mjcf/joints.rs",
        "joint",
        202,
        "a joint kind per arm",
    ),
    (
        "crates/assembly/src/validate/joints.rs",
        "joints",
        175,
        "one check per function",
    ),
    (
        "crates/env/src/env.rs",
        "new",
        172,
        "config, task, observation layout",
    ),
    (
        "crates/assembly/src/validate/instances.rs",
        "instances",
        152,
        "one check per function",
    ),
    (
        "server/src/serve.rs",
        "serve_bound",
        151,
        "services, listeners, shutdown",
    ),
    (
        "crates/env/src/task.rs",
        "resolve",
        149,
        "a task kind per arm",
    ),
    (
        "crates/physics/src/state.rs",
        "check_dynamic_state",
        140,
        "one check per part",
    ),
    (
        "crates/import/src/urdf/joints.rs",
        "joint",
        139,
        "a joint kind per arm",
    ),
    (
        "crates/import/src/urdf/links.rs",
        "collision",
        120,
        "a shape per arm",
    ),
    (
        "crates/assembly/src/validate/joints.rs",
        "topology",
        118,
        "tree, loops, ordering",
    ),
    (
        "crates/assembly/src/document/primitive.rs",
        "visit_map",
        118,
        "a field per arm",
    ),
    (
        "crates/physics/src/state.rs",
        "restore_dynamic_state",
        104,
        "one part per function",
    ),
    (
        "crates/assembly/src/tendons.rs",
        "tendons",
        103,
        "fixed and spatial tendons",
    ),
    (
        "crates/physics/src/randomize.rs",
        "apply_draws",
        98,
        "one quantity per function",
    ),
    (
        "crates/assembly/src/validate.rs",
        "validate",
        98,
        "the stages in turn",
    ),
    (
        "crates/assembly/src/contacts.rs",
        "contacts",
        95,
        "pairs, excludes, defaults",
    ),
    (
        "crates/assembly/src/actuators.rs",
        "actuators",
        95,
        "an actuator kind per arm",
    ),
    (
        "crates/import/src/mjcf/attributes.rs",
        "local_frame",
        89,
        "a frame form per arm",
    ),
    (
        "crates/import/src/mjcf/attributes.rs",
        "option",
        88,
        "an option group per arm",
    ),
    (
        "crates/assembly/src/validate/parts.rs",
        "mesh",
        88,
        "one check per function",
    ),
    (
        "crates/import/src/mjcf/keyframes.rs",
        "keyframe",
        86,
        "a field per arm",
    ),
    (
        "crates/physics/src/contact_filter.rs",
        "contact_filter",
        85,
        "filters in turn",
    ),
    (
        "crates/physics/src/state.rs",
        "dynamic_state",
        84,
        "one part per function",
    ),
    (
        "crates/import/src/urdf/links.rs",
        "link",
        82,
        "visual, collision, inertial",
    ),
];

/// The byte ranges of `code`'s `#[cfg(test)]` modules (their braces included).
fn test_modules(code: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(at) = code[from..].find("#[cfg(test)]") {
        let start = from + at;
        let after = &code[start..];
        let Some(brace) = after.find('{') else { break };
        // Only a module: `#[cfg(test)] mod name {`.
        if after[..brace].contains("mod ") {
            if let Some(end) = matching_brace(code, start + brace) {
                out.push((start, end));
            }
        }
        from = start + 1;
    }
    out
}

/// The index of the brace that closes the one at `open`.
fn matching_brace(code: &str, open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (i, c) in code[open..].char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return Some(open + i);
                }
            }
            _ => {}
        }
    }
    None
}

/// `(name, lines)` of every function with a body in `src` outside test modules and
/// `#[test]` functions: lines from the `fn` line to the closing brace's line.
fn function_lengths(src: &str) -> Vec<(String, usize)> {
    let code = code_only(src);
    let tests = test_modules(&code);
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(at) = code[from..].find("fn ") {
        let start = from + at;
        from = start + 3;
        let word_start =
            start == 0 || !code[..start].ends_with(|c: char| c.is_alphanumeric() || c == '_');
        let Some(name) = ident_at(&code[start + 3..]) else {
            continue;
        };
        if !word_start || tests.iter().any(|&(a, b)| a <= start && start <= b) {
            continue;
        }
        let before = &code[..start];
        let attrs = &before[before.rfind(['}', ';']).map_or(0, |i| i + 1)..];
        if attrs.contains("#[test]") || attrs.contains("::test") {
            continue;
        }
        // The body: the first `{` before any `;` (a declaration without a body has none).
        let rest = &code[start..];
        let (Some(brace), semi) = (rest.find('{'), rest.find(';')) else {
            continue;
        };
        if semi.is_some_and(|s| s < brace) {
            continue;
        }
        let Some(end) = matching_brace(&code, start + brace) else {
            continue;
        };
        let lines = code[start..=end].matches('\n').count() + 1;
        out.push((name.to_string(), lines));
    }
    out
}

/// No non-test function of the workspace's crates is longer than [`MAX_FN_LINES`], except
/// those of [`LONG_FNS`], and those no longer than they are listed (issue M4).
#[test]
fn functions_fit_on_a_screen() {
    let root = repo_root();
    let mut problems = Vec::new();
    let mut seen = BTreeSet::new();
    for krate in CRATES {
        for (_, path) in module_files(&root.join(krate)) {
            let rel = path
                .strip_prefix(&root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            let src = fs::read_to_string(&path).unwrap();
            for (name, lines) in function_lengths(&src) {
                if lines <= MAX_FN_LINES {
                    continue;
                }
                if std::env::var_os("TIDY_PRINT_LENGTHS").is_some() {
                    eprintln!("LEN {rel} {name} {lines}");
                }
                match LONG_FNS.iter().find(|(f, n, _, _)| *f == rel && *n == name) {
                    Some((_, _, allowed, _)) if lines <= *allowed => {
                        seen.insert((rel.clone(), name.clone()));
                    }
                    Some((_, _, allowed, _)) => problems.push(format!(
                        "{rel}: fn {name} grew to {lines} lines (listed at {allowed}; the bound is {MAX_FN_LINES}): split it"
                    )),
                    None => problems.push(format!(
                        "{rel}: fn {name} is {lines} lines (the bound is {MAX_FN_LINES}): split it along its seams"
                    )),
                }
            }
        }
    }
    for (file, name, _, _) in LONG_FNS {
        if !seen.contains(&(file.to_string(), name.to_string())) {
            problems.push(format!(
                "{file}: fn {name} is listed in LONG_FNS but is no longer over {MAX_FN_LINES} lines (or is gone): remove its entry"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_length_check_counts_bodies_and_skips_tests_and_declarations() {
    let src = "fn a() {\n    let s = \"{\n\";\n}\ntrait T { fn decl(&self); }\n\
               #[test]\nfn t() {\n}\n#[cfg(test)]\nmod tests {\n    fn helper() {\n    }\n}\n\
               pub(crate) fn b() -> u8 { 1 }\n";
    assert_eq!(
        function_lengths(src),
        [("a".to_string(), 4), ("b".to_string(), 1)]
    );
}
