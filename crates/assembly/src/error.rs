//! Document errors: every problem carries the JSON path of the offending field.

use std::fmt;

/// Most characters of a name (or id) echoed back in a message.
pub const MAX_ECHOED_CHARS: usize = 96;
/// Most names listed in a message ("known: …").
pub const MAX_LISTED_NAMES: usize = 10;
/// Most characters of one issue's message, and of its path.
const MAX_ISSUE_CHARS: usize = 1000;
/// Most issues an [`AssemblyError::Invalid`] message shows (all stay in `issues`).
const MAX_SHOWN_ISSUES: usize = 20;

/// A number as a message shows it: short whatever its size.
///
/// ```
/// assert_eq!(gymfleet_assembly::shown(-2.5), "-2.5");
/// assert_eq!(gymfleet_assembly::shown(1e300), "1e300");
/// ```
pub fn shown(value: f64) -> String {
    if value.is_finite() && value.abs() < 1e9 {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// `name` quoted as messages echo it: in full when short, else its start and its length,
/// so that no document can make an error message large.
///
/// ```
/// assert_eq!(gymfleet_assembly::quoted("arm"), "\"arm\"");
/// let long = "x".repeat(1000);
/// assert!(gymfleet_assembly::quoted(&long).ends_with("… (1000 bytes in all)"));
/// ```
pub fn quoted(name: &str) -> String {
    match name.char_indices().nth(MAX_ECHOED_CHARS) {
        None => format!("{name:?}"),
        Some((end, _)) => format!("{:?}… ({} bytes in all)", &name[..end], name.len()),
    }
}

/// Names quoted and joined with `, `: at most [`MAX_LISTED_NAMES`], then
/// `and N more`; `none` for no names.
pub fn quoted_list<S: AsRef<str>>(names: &[S]) -> String {
    if names.is_empty() {
        return "none".to_string();
    }
    let mut text = names
        .iter()
        .take(MAX_LISTED_NAMES)
        .map(|n| quoted(n.as_ref()))
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > MAX_LISTED_NAMES {
        text.push_str(&format!(", and {} more", names.len() - MAX_LISTED_NAMES));
    }
    text
}

/// `text` cut to `max` characters (on a character boundary), saying so.
fn capped(text: String, max: usize) -> String {
    match text.char_indices().nth(max) {
        None => text,
        Some((end, _)) => format!("{}… (cut; {} bytes in all)", &text[..end], text.len()),
    }
}

/// One problem in a document: where it is and what was expected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Issue {
    /// JSON path of the offending field, e.g. `assembly.joints[1].child`.
    pub path: String,
    /// What is wrong and what was expected.
    pub message: String,
}

impl Issue {
    /// An issue; a path or message longer than 1000 characters is cut.
    pub(crate) fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        Issue {
            path: capped(path.into(), MAX_ISSUE_CHARS),
            message: capped(message.into(), MAX_ISSUE_CHARS),
        }
    }
}

impl fmt::Display for Issue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

/// Why a document was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AssemblyError {
    /// The document is not valid JSON, or does not have the document's shape.
    #[error("{issue}")]
    Malformed {
        /// The first structural problem serde met.
        issue: Issue,
    },
    /// The document parsed, but its contents are inconsistent. Every problem found is listed.
    #[error("{}", join(issues))]
    Invalid {
        /// All problems, in document order.
        issues: Vec<Issue>,
    },
}

impl AssemblyError {
    /// All issues of the error (one for a malformed document).
    pub fn issues(&self) -> &[Issue] {
        match self {
            AssemblyError::Malformed { issue } => std::slice::from_ref(issue),
            AssemblyError::Invalid { issues } => issues,
        }
    }

    /// The JSON path of the first issue.
    pub fn path(&self) -> &str {
        self.issues().first().map_or("", |i| i.path.as_str())
    }
}

fn join(issues: &[Issue]) -> String {
    let mut text = issues
        .iter()
        .take(MAX_SHOWN_ISSUES)
        .map(Issue::to_string)
        .collect::<Vec<_>>()
        .join("; ");
    if issues.len() > MAX_SHOWN_ISSUES {
        text.push_str(&format!(
            "; and {} more issues",
            issues.len() - MAX_SHOWN_ISSUES
        ));
    }
    text
}

/// Result alias for this crate.
pub type Result<T, E = AssemblyError> = std::result::Result<T, E>;

/// Checks a list of named definitions at `list` (e.g. `assembly.sites`): at most `max`, and
/// each name (`{list}[k].name`) non-empty and unique among the `kind`s. Returns whether
/// the count is within `max` (past it nothing else is checked); the problems go to
/// `issues`, and `named[k]` says whether definition `k`'s name is fine.
pub(crate) fn check_names(
    list: &str,
    kind: &str,
    names: &[&str],
    max: usize,
    issues: &mut Vec<Issue>,
) -> bool {
    if names.len() > max {
        issues.push(Issue::new(
            list,
            format!("expected at most {max} {kind}s, got {}", names.len()),
        ));
        return false;
    }
    let mut seen: std::collections::HashSet<&str> = std::collections::HashSet::new();
    for (k, name) in names.iter().enumerate() {
        if name.is_empty() {
            issues.push(Issue::new(
                format!("{list}[{k}].name"),
                "expected a non-empty name",
            ));
        } else if !seen.insert(name) {
            issues.push(Issue::new(
                format!("{list}[{k}].name"),
                format!(
                    "{} names an earlier {kind} too; {kind} names must be unique",
                    quoted(name)
                ),
            ));
        }
    }
    true
}
