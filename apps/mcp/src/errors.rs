//! [`McpError`], the adapter's one error type, and how a [`ClientError`] becomes a tool
//! error an agent can act on: which server, which of the adapter's ids (never the
//! server's own id, which the agent never saw), and what to do next.

use gymfleet_client::{ClientError, ErrorReason};
use rmcp::model::{ContentBlock, IntoContents};

/// Everything that can go wrong in the adapter. A tool returns it as a tool error
/// (`isError: true`) whose text is the message; at startup, `main` prints it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(crate) enum McpError {
    /// A tool argument is unusable (the document, an option or an action); the message
    /// names the argument, what was expected and what was given.
    #[error("{message}")]
    BadArgument {
        /// What is wrong.
        message: String,
    },
    /// An id of the other kind: an env's where a batch's is expected, or the reverse.
    #[error("{}", wrong_kind(id, *expected))]
    WrongIdKind {
        /// The id as given.
        id: String,
        /// The kind the tool takes.
        expected: IdKind,
    },
    /// An id that names no open env or batch of this adapter.
    #[error(
        "unknown {} \"{id}\": no open {} has this id (open: {open}). Create one with {}.",
        kind.field(),
        kind.noun(),
        kind.creator()
    )]
    UnknownId {
        /// The id as given.
        id: String,
        /// The kind the tool takes.
        kind: IdKind,
        /// The open ids of that kind, listed.
        open: String,
    },
    /// No server could be reached to create on.
    #[error("{} {SERVER_DOWN_HINT}", failures.join(" "))]
    NoServerReachable {
        /// Why each server could not be reached.
        failures: Vec<String>,
    },
    /// A server refused or failed the call; the message has the adapter's ids.
    #[error("{message}")]
    Server {
        /// The server's message, rephrased for the agent.
        message: String,
    },
    /// The adapter could not start or keep serving (a bad flag, a port in use).
    #[error("{message}")]
    Startup {
        /// What failed.
        message: String,
    },
}

impl McpError {
    /// A [`McpError::BadArgument`].
    pub(crate) fn bad_argument(message: impl Into<String>) -> Self {
        McpError::BadArgument {
            message: message.into(),
        }
    }

    /// A [`McpError::Startup`].
    pub(crate) fn startup(message: impl Into<String>) -> Self {
        McpError::Startup {
            message: message.into(),
        }
    }
}

/// A tool error is text content.
impl IntoContents for McpError {
    fn into_contents(self) -> Vec<ContentBlock> {
        vec![ContentBlock::text(self.to_string())]
    }
}

/// Result alias for this crate.
pub(crate) type Result<T, E = McpError> = std::result::Result<T, E>;

/// The two kinds of id the adapter hands out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum IdKind {
    /// `sim_<n>`.
    Env,
    /// `batch_<n>`.
    Batch,
}

impl IdKind {
    /// The argument's name: `env_id` or `batch_id`.
    pub(crate) fn field(self) -> &'static str {
        match self {
            IdKind::Env => "env_id",
            IdKind::Batch => "batch_id",
        }
    }

    fn noun(self) -> &'static str {
        match self {
            IdKind::Env => "environment",
            IdKind::Batch => "batch",
        }
    }

    fn creator(self) -> &'static str {
        match self {
            IdKind::Env => "create_robot_env",
            IdKind::Batch => "batch_create_envs",
        }
    }
}

fn wrong_kind(id: &str, expected: IdKind) -> String {
    match expected {
        IdKind::Env => format!(
            "\"{id}\" is a batch_id, not an env_id: use batch_step, batch_reset and \
             batch_close for batches"
        ),
        IdKind::Batch => format!(
            "\"{id}\" is an env_id, not a batch_id: use gym_step, gym_reset, gym_observe \
             and gym_close for single environments"
        ),
    }
}

/// What a failed call was about: one of the adapter's envs or batches.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Subject<'a> {
    /// An env or a batch.
    pub(crate) kind: IdKind,
    /// The adapter's id, as the agent knows it.
    pub(crate) id: &'a str,
    /// The id on the server, to be replaced in the server's messages.
    pub(crate) server_id: &'a str,
    /// The server holding it.
    pub(crate) addr: &'a str,
}

/// The advice appended to every "cannot reach" message: with a failed connect before it,
/// the words every gymfleet client uses (`gymfleet_client::cannot_connect`, with the
/// adapter's way of pointing elsewhere; a test checks that the two agree).
pub(crate) const SERVER_DOWN_HINT: &str = "Is the server running? To use another one, pass \
     --server ADDR to the adapter (or set GYMFLEET_SERVER); gymfleet-server --listen ADDR \
     starts one.";

/// A failure to reach the server at `addr` (without [`SERVER_DOWN_HINT`]), or `None` if
/// `err` is not one.
pub(crate) fn unreachable(err: &ClientError, addr: &str) -> Option<String> {
    match err {
        ClientError::Connect { reason, .. } => Some(format!(
            "cannot connect to the gymfleet server at {addr}: {}.",
            reason.trim_end_matches('.')
        )),
        ClientError::Unavailable { message, .. } => Some(format!(
            "the gymfleet server at {addr} is unavailable: {message}."
        )),
        ClientError::DeadlineExceeded { message } => Some(format!(
            "the gymfleet server at {addr} did not answer in time: {message}."
        )),
        _ => None,
    }
}

/// A failed call on `subject`: the reason decides what the agent is told (an id the
/// server no longer has gets the adapter's words and what to do); the message is the
/// server's, with the adapter's ids.
pub(crate) fn on_subject(err: &ClientError, subject: Subject<'_>) -> McpError {
    let Subject {
        kind,
        id,
        server_id,
        addr,
    } = subject;
    let field = kind.field();
    let message = if let Some(text) = unreachable(err, addr) {
        format!("{text} {field} \"{id}\" lives on that server. {SERVER_DOWN_HINT}")
    } else {
        match err.reason() {
            Some(ErrorReason::EnvNotFound | ErrorReason::BatchNotFound) => format!(
                "unknown {field} \"{id}\": the server no longer has it (it was closed, or \
                 reclaimed after idling). Create a new one with {}.",
                kind.creator()
            ),
            // The message is for people: the server's ids in it become the adapter's.
            _ => rename_id(&err.to_string(), server_id, id),
        }
    };
    McpError::Server { message }
}

/// `text` with every whole occurrence of the id `from` replaced by `to` (`sim_1` is
/// replaced in `"sim_1"` but not inside `sim_12`).
pub(crate) fn rename_id(text: &str, from: &str, to: &str) -> String {
    if from.is_empty() || from == to {
        return text.to_string();
    }
    let is_id_char = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    for (at, _) in text.match_indices(from) {
        let end = at + from.len();
        let before = text[..at].chars().next_back();
        let after = text[end..].chars().next();
        out.push_str(&text[copied..at]);
        if before.is_some_and(is_id_char) || after.is_some_and(is_id_char) {
            out.push_str(from);
        } else {
            out.push_str(to);
        }
        copied = end;
    }
    out.push_str(&text[copied..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn subject() -> Subject<'static> {
        Subject {
            kind: IdKind::Env,
            id: "sim_2",
            server_id: "sim_1",
            addr: "127.0.0.1:9",
        }
    }

    #[test]
    fn server_ids_become_adapter_ids() {
        assert_eq!(
            rename_id("env \"sim_1\" diverged; sim_12 did not", "sim_1", "sim_2"),
            "env \"sim_2\" diverged; sim_12 did not"
        );
        assert_eq!(rename_id("sim_1", "sim_1", "sim_7"), "sim_7");
        let err = ClientError::FailedPrecondition {
            message: "env \"sim_1\" diverged: reset it".into(),
            reason: ErrorReason::NeedsReset,
        };
        assert_eq!(
            on_subject(&err, subject()).to_string(),
            "failed precondition: env \"sim_2\" diverged: reset it"
        );
    }

    #[test]
    fn not_found_names_the_adapter_id() {
        let err = ClientError::NotFound {
            message: "env \"sim_1\" not found".into(),
            reason: ErrorReason::EnvNotFound,
        };
        let text = on_subject(&err, subject()).to_string();
        assert!(text.starts_with("unknown env_id \"sim_2\": "), "{text}");
        assert!(text.ends_with("with create_robot_env."), "{text}");
    }

    #[test]
    fn unreachable_servers_name_the_address() {
        let err = ClientError::Unavailable {
            message: "connection reset".into(),
            code: gymfleet_client::Code::Unavailable,
            reason: ErrorReason::Unspecified,
        };
        let text = on_subject(&err, subject()).to_string();
        assert!(
            text.starts_with("the gymfleet server at 127.0.0.1:9 is unavailable"),
            "{text}"
        );
        assert!(text.ends_with(SERVER_DOWN_HINT), "{text}");
        let err = ClientError::Connect {
            addr: "127.0.0.1:9".into(),
            reason: "refused".into(),
        };
        assert_eq!(
            unreachable(&err, "127.0.0.1:9").unwrap(),
            "cannot connect to the gymfleet server at 127.0.0.1:9: refused."
        );
        // With the hint, the words of every gymfleet client.
        const POINT_THE_ADAPTER: &str = "pass --server ADDR to the adapter (or set \
             GYMFLEET_SERVER); gymfleet-server --listen ADDR starts one";
        assert_eq!(
            format!(
                "{} {SERVER_DOWN_HINT}",
                unreachable(&err, "127.0.0.1:9").unwrap()
            ),
            gymfleet_client::cannot_connect("127.0.0.1:9", "refused", POINT_THE_ADAPTER)
        );
    }
}
