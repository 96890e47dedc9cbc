//! [`LoadError`]: why a load run could not be configured or carried out. Errors of single
//! step calls are not here: they are counted in the run's figures, not fatal.

use std::path::PathBuf;

/// How a user points `gymfleet-load` at another server, as connection errors say.
const POINT_THE_TOOL: &str = "pass --server ADDR (or set GYMFLEET_SERVER)";

/// What can stop `gymfleet-load`: a bad command line (a usage error, exit status 2), or a
/// failure to set the run up or write its results (exit status 1).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LoadError {
    /// Two flags that exclude each other were both given.
    #[error("{flag} cannot be used with {other}")]
    Conflict {
        /// The flag, as written on the command line.
        flag: &'static str,
        /// The flag it conflicts with.
        other: &'static str,
    },
    /// A flag has a value outside what it accepts.
    #[error("{flag} {reason}")]
    BadFlag {
        /// The flag, as written on the command line.
        flag: &'static str,
        /// What was expected and what was given.
        reason: String,
    },
    /// `--model` names neither a built-in model nor an existing file.
    #[error("unknown model '{name}': not pendulum|arm2|arm6|chain20|fourbar and no such file")]
    UnknownModel {
        /// The name as given.
        name: String,
    },
    /// `--model` names a file that could not be read.
    #[error("cannot read model file '{}': {reason}", path.display())]
    ModelFile {
        /// The path as given.
        path: PathBuf,
        /// The operating system's reason.
        reason: String,
    },
    /// The run needs the embedded server or in-process stepping, and this build was made
    /// without the `embedded` feature.
    #[error("{what} needs the `embedded` feature; this build is a pure network client: pass --server ADDR")]
    NotEmbedded {
        /// What was asked for.
        what: &'static str,
    },
    /// Setting the run up failed: connecting, creating envs or batches, starting the
    /// embedded server or the in-process pool.
    #[error("setup failed ({stage}): {reason}")]
    Setup {
        /// What was being set up, e.g. `client 3 on 127.0.0.1:50051`.
        stage: String,
        /// Why it failed (the server's message for server errors).
        reason: String,
    },
    /// The results could not be written.
    #[error("cannot write '{}': {reason}", path.display())]
    Output {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
}

impl LoadError {
    /// True for errors in the command line itself (exit status 2), false for failures
    /// while running (exit status 1).
    pub fn is_usage(&self) -> bool {
        matches!(
            self,
            LoadError::Conflict { .. }
                | LoadError::BadFlag { .. }
                | LoadError::UnknownModel { .. }
                | LoadError::ModelFile { .. }
                | LoadError::NotEmbedded { .. }
        )
    }

    pub(crate) fn setup(stage: impl Into<String>, reason: impl ToString) -> Self {
        LoadError::Setup {
            stage: stage.into(),
            reason: reason.to_string(),
        }
    }

    /// A failed connect in `stage`: for a server that cannot be reached, the words every
    /// gymfleet client uses, with this tool's way of pointing elsewhere.
    pub(crate) fn connect(stage: impl Into<String>, err: gymfleet_client::ClientError) -> Self {
        let reason = match &err {
            gymfleet_client::ClientError::Connect { addr, reason } => {
                gymfleet_client::cannot_connect(addr, reason, POINT_THE_TOOL)
            }
            other => other.to_string(),
        };
        LoadError::Setup {
            stage: stage.into(),
            reason,
        }
    }

    pub(crate) fn bad_flag(flag: &'static str, reason: impl Into<String>) -> Self {
        LoadError::BadFlag {
            flag,
            reason: reason.into(),
        }
    }
}

/// Result alias for this crate.
pub type Result<T, E = LoadError> = std::result::Result<T, E>;
