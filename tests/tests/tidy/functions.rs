//! Functions that fit on a screen: no non-test function over [`MAX_FN_LINES`] lines, but
//! the listed ones, which may only shrink.

use std::collections::BTreeSet;
use std::fs;

use super::{code_only, ident_at, module_files, repo_root, CRATES};

/// The longest a non-test function may be, in lines from its `fn` to its closing brace.
const MAX_FN_LINES: usize = 80;

/// Functions allowed over [`MAX_FN_LINES`], each at most as long as it is listed, with the
/// reason: the list may only shrink (a listed function that grows, or one no longer over
/// the bound, fails the check, so that its entry goes). Empty since the terms and
/// quantities became serde enums (issue M4): a new entry needs a reason a reviewer accepts.
const LONG_FNS: &[(&str, &str, usize, &str)] = &[];

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
