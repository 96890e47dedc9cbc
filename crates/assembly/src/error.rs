//! Document errors: every problem carries the JSON path of the offending field.

use std::fmt;

/// One problem in a document: where it is and what was expected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Issue {
    /// JSON path of the offending field, e.g. `assembly.joints[1].child`.
    pub path: String,
    /// What is wrong and what was expected.
    pub message: String,
}

impl Issue {
    pub(crate) fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        Issue {
            path: path.into(),
            message: message.into(),
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
    issues
        .iter()
        .map(Issue::to_string)
        .collect::<Vec<_>>()
        .join("; ")
}

/// Result alias for this crate.
pub type Result<T, E = AssemblyError> = std::result::Result<T, E>;
