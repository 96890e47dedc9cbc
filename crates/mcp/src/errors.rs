//! Turns [`ClientError`]s into tool-error messages an agent can act on: which server,
//! which of the adapter's ids (never the server's own id, which the agent never saw), and
//! what to do next.

use gymfleet_client::ClientError;

/// What a failed call was about: one of the adapter's envs or batches.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Subject<'a> {
    /// `"env_id"` or `"batch_id"`.
    pub(crate) kind: &'a str,
    /// The adapter's id, as the agent knows it.
    pub(crate) id: &'a str,
    /// The id on the server, to be replaced in the server's messages.
    pub(crate) server_id: &'a str,
    /// The server holding it.
    pub(crate) addr: &'a str,
}

/// The advice appended to every "cannot reach" message.
pub(crate) const SERVER_DOWN_HINT: &str = "The server may be down: start it (gymfleet-server \
     --listen ADDR), or point the adapter at a running one with --server ADDR (GYMFLEET_SERVER).";

/// A failure to reach the server at `addr` (without [`SERVER_DOWN_HINT`]), or `None` if
/// `err` is not one.
pub(crate) fn unreachable(err: &ClientError, addr: &str) -> Option<String> {
    match err {
        ClientError::Connect { reason, .. } => Some(format!(
            "cannot reach the gymfleet server at {addr}: {reason}."
        )),
        ClientError::Unavailable { message } => Some(format!(
            "the gymfleet server at {addr} is unavailable: {message}."
        )),
        _ => None,
    }
}

/// A failed call on `subject`.
pub(crate) fn on_subject(err: &ClientError, subject: Subject<'_>) -> String {
    let Subject {
        kind,
        id,
        server_id,
        addr,
    } = subject;
    if let Some(text) = unreachable(err, addr) {
        return format!("{text} {kind} \"{id}\" lives on that server. {SERVER_DOWN_HINT}");
    }
    let creator = if kind == "batch_id" {
        "batch_create_envs"
    } else {
        "create_robot_env"
    };
    match err {
        ClientError::NotFound { .. } => format!(
            "unknown {kind} \"{id}\": the server no longer has it (it was closed, or reclaimed \
             after idling). Create a new one with {creator}."
        ),
        other => rename_id(&other.to_string(), server_id, id),
    }
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
            kind: "env_id",
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
        };
        assert_eq!(
            on_subject(&err, subject()),
            "failed precondition: env \"sim_2\" diverged: reset it"
        );
    }

    #[test]
    fn not_found_names_the_adapter_id() {
        let err = ClientError::NotFound {
            message: "env \"sim_1\" not found".into(),
        };
        let text = on_subject(&err, subject());
        assert!(text.starts_with("unknown env_id \"sim_2\": "), "{text}");
        assert!(text.ends_with("with create_robot_env."), "{text}");
    }

    #[test]
    fn unreachable_servers_name_the_address() {
        let err = ClientError::Unavailable {
            message: "connection reset".into(),
        };
        let text = on_subject(&err, subject());
        assert!(
            text.starts_with("the gymfleet server at 127.0.0.1:9 is unavailable"),
            "{text}"
        );
        assert!(text.contains("may be down"), "{text}");
        let err = ClientError::Connect {
            addr: "127.0.0.1:9".into(),
            reason: "refused".into(),
        };
        assert_eq!(
            unreachable(&err, "127.0.0.1:9").unwrap(),
            "cannot reach the gymfleet server at 127.0.0.1:9: refused."
        );
    }
}
