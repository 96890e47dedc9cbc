//! [`ClientError`]: what a call can fail with, by gRPC status class, plus the fleet's
//! own failures (a lost server, a call that failed on one server of several).

use std::ops::Range;

pub use gymfleet_proto::v1::ErrorReason;
use tonic::{Code, Status};

/// Why a client call failed. Server errors carry the server's message, which names the
/// offending field (with its JSON path for documents) or id. [`ClientError::code`] gives
/// the gRPC status code a server error came with.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ClientError {
    /// The server could not be reached (nothing listens there, a refused or failed TLS
    /// handshake, no answer). Its message is [`cannot_connect`]'s, with this library's
    /// advice ([`POINT_THE_LIBRARY`]).
    #[error("{}", cannot_connect(addr, reason, POINT_THE_LIBRARY))]
    Connect {
        /// The address as given.
        addr: String,
        /// Why.
        reason: String,
    },
    /// The client's own settings make a connection impossible: a malformed address, a
    /// token that is not printable ASCII, a TLS file that cannot be read.
    #[error("cannot connect to {addr}: {reason}")]
    Setting {
        /// The address as given.
        addr: String,
        /// What is wrong.
        reason: String,
    },
    /// NOT_FOUND: the env or batch id is unknown, closed, or was reclaimed after idling.
    #[error("not found: {message}")]
    NotFound {
        /// The server's message, naming the id.
        message: String,
        /// Why, for machines ([`ClientError::reason`]).
        reason: ErrorReason,
    },
    /// INVALID_ARGUMENT (or OUT_OF_RANGE): a bad document, configuration or action.
    #[error("invalid argument: {message}")]
    InvalidArgument {
        /// The server's message, with the field's path and what was expected.
        message: String,
        /// Why, for machines ([`ClientError::reason`]).
        reason: ErrorReason,
    },
    /// FAILED_PRECONDITION: the call is not possible in the current state, e.g. stepping
    /// an env whose physics diverged before resetting it.
    #[error("failed precondition: {message}")]
    FailedPrecondition {
        /// The server's message.
        message: String,
        /// Why, for machines ([`ClientError::reason`]).
        reason: ErrorReason,
    },
    /// RESOURCE_EXHAUSTED: a server limit was hit; the message says which and how to
    /// raise it.
    #[error("resource exhausted: {message}")]
    ResourceExhausted {
        /// The server's message.
        message: String,
        /// RESOURCE_EXHAUSTED, or OUT_OF_RANGE (how tonic reports an over-size message).
        code: Code,
        /// Why, for machines ([`ClientError::reason`]).
        reason: ErrorReason,
        /// The server flag that raises the limit (`gymfleet-limit`), e.g. `--max-envs`.
        limit: Option<String>,
    },
    /// UNAVAILABLE, CANCELLED or ABORTED: the server is gone, shutting down, or the call
    /// was cut short. Retrying may help.
    #[error("unavailable: {message}")]
    Unavailable {
        /// The transport's or server's message.
        message: String,
        /// UNAVAILABLE, CANCELLED, ABORTED, or UNKNOWN for a connection lost mid-call.
        code: Code,
        /// Why, for machines ([`ClientError::reason`]): the server's, when it sent one
        /// (it is shutting down); unspecified for the transport's.
        reason: ErrorReason,
    },
    /// DEADLINE_EXCEEDED: no reply within the call's deadline. Whether the server did the
    /// work is unknown (a batch may have stepped some envs): reset before going on.
    #[error("deadline exceeded: {message}")]
    DeadlineExceeded {
        /// The server's or the caller's message.
        message: String,
    },
    /// UNAUTHENTICATED: the server requires a token and got none, or a bad one.
    #[error("unauthenticated: {message}")]
    Unauthenticated {
        /// The server's message.
        message: String,
        /// Why, for machines ([`ClientError::reason`]).
        reason: ErrorReason,
    },
    /// INTERNAL, UNKNOWN or DATA_LOSS: a server bug.
    #[error("internal server error: {message}")]
    Internal {
        /// The server's message.
        message: String,
        /// INTERNAL, UNKNOWN or DATA_LOSS.
        code: Code,
        /// Why, for machines ([`ClientError::reason`]).
        reason: ErrorReason,
    },
    /// The server answered something this client does not understand: an unexpected
    /// status code, or a reply of the wrong shape.
    #[error("protocol error: {message}")]
    Protocol {
        /// What was wrong.
        message: String,
        /// The unexpected status code; `Code::Ok` for a reply of the wrong shape.
        code: Code,
    },
    /// A server of a fleet failed (it is unreachable, or no longer knows the shard batch)
    /// while it held envs of a fleet batch: their state is gone. The other servers are
    /// unaffected; [`crate::FleetBatch::drop_lost`] lets the caller go on without them.
    #[error("server {server} failed ({reason}): lost envs {} of fleet batch", format_ranges(.envs))]
    ServerLost {
        /// The address of the failed server.
        server: String,
        /// The lost envs, as ranges of the fleet batch's original env indices.
        envs: Vec<Range<usize>>,
        /// What the call to it failed with.
        reason: String,
    },
    /// A fleet call failed on one server, without losing env state (e.g. while creating a
    /// fleet batch, or a step the server refused).
    #[error("server {server}: {error}")]
    OnServer {
        /// The address of the server.
        server: String,
        /// What the call to it failed with.
        error: Box<ClientError>,
    },
    /// A fleet is misconfigured: no endpoints, a malformed or duplicate endpoint, or no
    /// server with simulation threads.
    #[error("fleet: {message}")]
    Fleet {
        /// What is wrong.
        message: String,
    },
}

/// What every gymfleet client says when it cannot connect to a server: the address, the
/// cause, "Is the server running?", and `how` the user points that program at another
/// server (its `--server` flag, its address parameter, `GYMFLEET_SERVER`):
///
/// `cannot connect to the gymfleet server at ADDR: CAUSE. Is the server running? To use
/// another one, HOW.`
///
/// The Python package, the load client and the MCP adapter call it with their own `how`;
/// the TypeScript client writes the same sentence.
pub fn cannot_connect(addr: &str, reason: &str, how: &str) -> String {
    let reason = reason.trim_end_matches('.');
    format!(
        "cannot connect to the gymfleet server at {addr}: {reason}. Is the server running? \
         To use another one, {how}."
    )
}

/// How a program using this library points it at another server, as
/// [`ClientError::Connect`] says it.
pub const POINT_THE_LIBRARY: &str =
    "pass its address to Client::connect (a fleet: its FleetEndpoints)";

/// `0..16, 48..96`, with a lone env written as its index.
fn format_ranges(ranges: &[Range<usize>]) -> String {
    let parts: Vec<String> = ranges
        .iter()
        .map(|r| {
            if r.len() == 1 {
                r.start.to_string()
            } else {
                format!("{}..{}", r.start, r.end)
            }
        })
        .collect();
    if parts.is_empty() {
        "none".to_string()
    } else {
        parts.join(", ")
    }
}

/// What kind of failure a [`ClientError`] is: a plain enum to match exhaustively, where
/// the error itself is `#[non_exhaustive]` (an error variant added later maps to one of
/// these, or adds one here, which then fails to compile wherever a match misses it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorKind {
    /// [`ClientError::Connect`] and [`ClientError::Setting`].
    Connect,
    /// [`ClientError::NotFound`].
    NotFound,
    /// [`ClientError::InvalidArgument`].
    InvalidArgument,
    /// [`ClientError::FailedPrecondition`].
    FailedPrecondition,
    /// [`ClientError::ResourceExhausted`].
    ResourceExhausted,
    /// [`ClientError::Unavailable`].
    Unavailable,
    /// [`ClientError::DeadlineExceeded`].
    DeadlineExceeded,
    /// [`ClientError::Unauthenticated`].
    Unauthenticated,
    /// [`ClientError::Internal`].
    Internal,
    /// [`ClientError::Protocol`].
    Protocol,
    /// [`ClientError::ServerLost`].
    ServerLost,
    /// [`ClientError::Fleet`].
    Fleet,
}

impl ClientError {
    /// What kind of failure this is; a fleet call's failure on one server
    /// ([`ClientError::OnServer`]) is the kind of that server's error.
    pub fn kind(&self) -> ErrorKind {
        match self {
            ClientError::Connect { .. } | ClientError::Setting { .. } => ErrorKind::Connect,
            ClientError::NotFound { .. } => ErrorKind::NotFound,
            ClientError::InvalidArgument { .. } => ErrorKind::InvalidArgument,
            ClientError::FailedPrecondition { .. } => ErrorKind::FailedPrecondition,
            ClientError::ResourceExhausted { .. } => ErrorKind::ResourceExhausted,
            ClientError::Unavailable { .. } => ErrorKind::Unavailable,
            ClientError::DeadlineExceeded { .. } => ErrorKind::DeadlineExceeded,
            ClientError::Unauthenticated { .. } => ErrorKind::Unauthenticated,
            ClientError::Internal { .. } => ErrorKind::Internal,
            ClientError::Protocol { .. } => ErrorKind::Protocol,
            ClientError::ServerLost { .. } => ErrorKind::ServerLost,
            ClientError::Fleet { .. } => ErrorKind::Fleet,
            ClientError::OnServer { error, .. } => error.kind(),
        }
    }

    /// The message carried by the error (the server's, for server errors).
    pub fn message(&self) -> &str {
        match self {
            ClientError::Connect { reason, .. } | ClientError::Setting { reason, .. } => reason,
            ClientError::NotFound { message, .. }
            | ClientError::InvalidArgument { message, .. }
            | ClientError::FailedPrecondition { message, .. }
            | ClientError::ResourceExhausted { message, .. }
            | ClientError::Unavailable { message, .. }
            | ClientError::DeadlineExceeded { message }
            | ClientError::Unauthenticated { message, .. }
            | ClientError::Internal { message, .. }
            | ClientError::Protocol { message, .. }
            | ClientError::Fleet { message } => message,
            ClientError::ServerLost { reason, .. } => reason,
            ClientError::OnServer { error, .. } => error.message(),
        }
    }

    /// The gRPC status code of a call that failed with one (for a fleet error, the code
    /// of the server's error); `None` for errors the client found itself (connecting, a
    /// fleet's configuration, a lost server). A client-side deadline counts as
    /// DEADLINE_EXCEEDED.
    pub fn code(&self) -> Option<Code> {
        match self {
            ClientError::NotFound { .. } => Some(Code::NotFound),
            ClientError::InvalidArgument { .. } => Some(Code::InvalidArgument),
            ClientError::FailedPrecondition { .. } => Some(Code::FailedPrecondition),
            ClientError::DeadlineExceeded { .. } => Some(Code::DeadlineExceeded),
            ClientError::Unauthenticated { .. } => Some(Code::Unauthenticated),
            ClientError::ResourceExhausted { code, .. }
            | ClientError::Unavailable { code, .. }
            | ClientError::Internal { code, .. } => Some(*code),
            ClientError::Protocol { code, .. } => (*code != Code::Ok).then_some(*code),
            ClientError::OnServer { error, .. } => error.code(),
            ClientError::Connect { .. }
            | ClientError::Setting { .. }
            | ClientError::ServerLost { .. }
            | ClientError::Fleet { .. } => None,
        }
    }

    /// Why the call failed, for machines: the server's [`ErrorReason`] (a fleet call's
    /// failure on one server: that server's), or the reason of the server's own check
    /// that a client-side check stands in for (a fleet batch's action checks:
    /// `InvalidAction`). `None` for what the client found itself (connecting, a deadline,
    /// a fleet's configuration, a lost server) and for a server that sent none.
    pub fn reason(&self) -> Option<ErrorReason> {
        let reason = match self {
            ClientError::NotFound { reason, .. }
            | ClientError::InvalidArgument { reason, .. }
            | ClientError::FailedPrecondition { reason, .. }
            | ClientError::ResourceExhausted { reason, .. }
            | ClientError::Unavailable { reason, .. }
            | ClientError::Unauthenticated { reason, .. }
            | ClientError::Internal { reason, .. } => *reason,
            ClientError::OnServer { error, .. } => return error.reason(),
            ClientError::Connect { .. }
            | ClientError::Setting { .. }
            | ClientError::DeadlineExceeded { .. }
            | ClientError::Protocol { .. }
            | ClientError::ServerLost { .. }
            | ClientError::Fleet { .. } => return None,
        };
        (reason != ErrorReason::Unspecified).then_some(reason)
    }

    /// The server flag that raises the limit a RESOURCE_EXHAUSTED refusal was for, e.g.
    /// `--max-envs`, when the server named it.
    pub fn limit(&self) -> Option<&str> {
        match self {
            ClientError::ResourceExhausted { limit, .. } => limit.as_deref(),
            ClientError::OnServer { error, .. } => error.limit(),
            _ => None,
        }
    }

    /// The server a fleet error names, if it names one.
    pub fn server(&self) -> Option<&str> {
        match self {
            ClientError::ServerLost { server, .. } | ClientError::OnServer { server, .. } => {
                Some(server)
            }
            ClientError::Connect { addr, .. } | ClientError::Setting { addr, .. } => Some(addr),
            _ => None,
        }
    }

    pub(crate) fn protocol(message: impl Into<String>) -> Self {
        ClientError::Protocol {
            message: message.into(),
            code: Code::Ok,
        }
    }
}

impl From<Status> for ClientError {
    fn from(status: Status) -> Self {
        let message = status.message().to_string();
        let metadata = |key: &str| {
            status
                .metadata()
                .get(key)
                .and_then(|v| v.to_str().ok())
                .map(str::to_string)
        };
        let reason = metadata(gymfleet_proto::REASON_KEY).map_or(ErrorReason::Unspecified, |r| {
            ErrorReason::from_wire_name(&r)
        });
        match status.code() {
            Code::NotFound => ClientError::NotFound { message, reason },
            Code::InvalidArgument => ClientError::InvalidArgument { message, reason },
            Code::FailedPrecondition => ClientError::FailedPrecondition { message, reason },
            // tonic reports an over-size message as OUT_OF_RANGE.
            code @ (Code::ResourceExhausted | Code::OutOfRange) => ClientError::ResourceExhausted {
                message,
                code,
                reason,
                limit: metadata(gymfleet_proto::LIMIT_KEY),
            },
            // tonic's own deadline (`ClientBuilder::timeout`, or the server's reading of
            // `grpc-timeout`) ends a call as CANCELLED "Timeout expired".
            Code::Cancelled if message == "Timeout expired" => ClientError::DeadlineExceeded {
                message: "no answer within the call's deadline".to_string(),
            },
            code @ (Code::Unavailable | Code::Cancelled | Code::Aborted) => {
                ClientError::Unavailable {
                    message,
                    code,
                    reason,
                }
            }
            Code::DeadlineExceeded => ClientError::DeadlineExceeded { message },
            Code::Unauthenticated => ClientError::Unauthenticated { message, reason },
            // A connection the server closed mid-call (it stopped or restarted) surfaces as
            // UNKNOWN "transport error": the server is gone, not broken.
            Code::Unknown if is_transport_error(&status) => ClientError::Unavailable {
                message,
                code: Code::Unknown,
                reason,
            },
            code @ (Code::Internal | Code::Unknown | Code::DataLoss) => ClientError::Internal {
                message,
                code,
                reason,
            },
            code @ (Code::Ok
            | Code::AlreadyExists
            | Code::PermissionDenied
            | Code::Unimplemented) => ClientError::Protocol {
                message: format!("unexpected status {code:?}: {message}"),
                code,
            },
        }
    }
}

/// Whether `status` is tonic's report of a failed connection rather than a server's answer.
fn is_transport_error(status: &Status) -> bool {
    use std::error::Error as _;
    status
        .source()
        .is_some_and(|s| s.downcast_ref::<tonic::transport::Error>().is_some())
        || status.message().starts_with("transport error")
}

/// Result alias for this crate.
pub type Result<T, E = ClientError> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_codes_map_to_variants_with_the_message() {
        let cases = [
            (Code::NotFound, "NotFound"),
            (Code::InvalidArgument, "InvalidArgument"),
            (Code::OutOfRange, "ResourceExhausted"),
            (Code::ResourceExhausted, "ResourceExhausted"),
            (Code::FailedPrecondition, "FailedPrecondition"),
            (Code::Unavailable, "Unavailable"),
            (Code::Cancelled, "Unavailable"),
            (Code::DeadlineExceeded, "DeadlineExceeded"),
            (Code::Unauthenticated, "Unauthenticated"),
            (Code::Internal, "Internal"),
            (Code::Unimplemented, "Protocol"),
        ];
        for (code, variant) in cases {
            let err = ClientError::from(Status::new(code, "sim_3 says hi"));
            assert!(
                format!("{err:?}").starts_with(variant),
                "{code:?} -> {err:?}"
            );
            assert!(err.message().contains("sim_3 says hi"));
            assert_eq!(err.code(), Some(code), "{err:?} keeps its code");
            // The kind names the variant.
            assert_eq!(format!("{:?}", err.kind()), variant, "{err:?}");
        }
        let err = ClientError::from(Status::new(Code::Cancelled, "Timeout expired"));
        assert!(
            matches!(err, ClientError::DeadlineExceeded { .. }),
            "{err:?}"
        );
        assert_eq!(err.code(), Some(Code::DeadlineExceeded));
    }

    #[test]
    fn a_failure_on_one_server_of_a_fleet_is_of_that_failure_s_kind() {
        let inner = ClientError::from(Status::new(Code::NotFound, "no batch_7"));
        let err = ClientError::OnServer {
            server: "h:1".to_string(),
            error: Box::new(inner),
        };
        assert_eq!(err.kind(), ErrorKind::NotFound);
        let fleet = ClientError::Fleet {
            message: "no endpoints".to_string(),
        };
        assert_eq!(fleet.kind(), ErrorKind::Fleet);
        let lost = ClientError::ServerLost {
            server: "h:1".to_string(),
            envs: vec![0..4, 8..12],
            reason: "gone".to_string(),
        };
        assert_eq!(lost.kind(), ErrorKind::ServerLost);
    }

    #[test]
    fn a_connection_lost_mid_call_is_unavailable_not_a_server_bug() {
        // Regression: a server stopped during a call gave "internal server error:
        // transport error", and the MCP adapter did not say the server may be down.
        let err = ClientError::from(Status::new(Code::Unknown, "transport error"));
        assert!(matches!(err, ClientError::Unavailable { .. }), "{err:?}");
        let err = ClientError::from(Status::new(Code::Unknown, "a panic"));
        assert!(matches!(err, ClientError::Internal { .. }), "{err:?}");
    }

    #[test]
    fn lost_servers_name_the_server_and_the_env_ranges() {
        let err = ClientError::ServerLost {
            server: "127.0.0.1:41234".into(),
            envs: vec![32..64, 70..71],
            reason: "unavailable: connection refused".into(),
        };
        assert_eq!(
            err.to_string(),
            "server 127.0.0.1:41234 failed (unavailable: connection refused): \
             lost envs 32..64, 70 of fleet batch"
        );
        assert_eq!(err.server(), Some("127.0.0.1:41234"));
        let err = ClientError::OnServer {
            server: "a:1".into(),
            error: Box::new(ClientError::InvalidArgument {
                message: "bad".into(),
                reason: ErrorReason::InvalidAction,
            }),
        };
        assert_eq!(err.to_string(), "server a:1: invalid argument: bad");
        assert_eq!(err.message(), "bad");
    }
}
