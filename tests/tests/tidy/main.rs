//! Tidy checks on the source tree itself (as rust-analyzer keeps its own `tidy` tests):
//! no crate's top-level modules import each other in a loop (ARCHITECTURE.md,
//! "Invariants"), and the check is shown to catch one on a small fixture.
//!
//! A crate's top-level modules are the files and folders of its `src/` (a file
//! `src/a.rs` and its children `src/a/…` are module `a`); module `a` depends on `b` when
//! its code names `crate::b` (in a `use`, a `use crate::{b::…}` group, or a path). Comments
//! and string literals are skipped, so a doc link does not count. Children may name their
//! parent with `super::`, which stays inside the module.
//!
//! Beside it: `citations.rs` (every cited Markdown file is in the repository) and
//! `functions.rs` (no non-test function over 80 lines but the listed ones).

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

mod citations;
mod functions;

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
