//! [`ServerError`] (what a request can meet), its one mapping to `tonic::Status` with its
//! code and [`gymfleet_proto::v1::ErrorReason`] (in `status.rs`), and [`StartupError`]
//! (what stops a server from starting, in `startup.rs`).
//!
//! Every domain error reaches the wire through the exhaustive `From` impl at the bottom:
//! a new variant anywhere (here, in `EnvError` or in `BatchError`) fails to compile until
//! someone decides its status code.

use std::fmt;

use gymfleet_batch::BatchError;
use gymfleet_env::EnvError;

use crate::limit::Limit;
use crate::tenant::Tenant;

mod startup;
mod status;

pub use startup::StartupError;
pub(crate) use status::with_reason;

/// Longest status message the server sends: anything longer is cut here, whatever
/// built it (the sources shorten what they echo; this is the guarantee).
pub const MAX_STATUS_MESSAGE_BYTES: usize = 4096;

/// `text` as an error message quotes it ([`gymfleet_assembly::quoted`]): in full when
/// short, otherwise its start and how long it was.
pub(crate) struct Echo<'a>(pub(crate) &'a str);

impl fmt::Display for Echo<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&gymfleet_assembly::quoted(self.0))
    }
}

/// What a server-side id names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EntityKind {
    /// A single environment, `"sim_<n>"`.
    Env,
    /// A batch, `"batch_<n>"`.
    Batch,
}

impl fmt::Display for EntityKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            EntityKind::Env => "environment",
            EntityKind::Batch => "batch",
        })
    }
}

/// Everything that can go wrong with a request.
#[derive(Debug, thiserror::Error)]
pub enum ServerError {
    /// A request field is unusable before it reaches the domain (an unset action type,
    /// an unknown enum value, a zero batch size).
    #[error("{field}: {reason}")]
    InvalidArgument {
        /// The request field, e.g. `action_type`.
        field: &'static str,
        /// What was expected and what was given.
        reason: String,
    },
    /// Building, resetting or stepping an environment failed.
    #[error(transparent)]
    Env(#[from] EnvError),
    /// Building or stepping a batch failed.
    #[error(transparent)]
    Batch(#[from] BatchError),
    /// The id names nothing open.
    #[error(
        "{kind} {} not found: it was closed, reclaimed after idling, or never existed",
        Echo(id)
    )]
    NotFound {
        /// What kind of id it is.
        kind: EntityKind,
        /// The id as given.
        id: String,
    },
    /// The env was created without `randomize`, so it has no draws to report.
    #[error("{} was created without randomize: it draws no factors", Echo(id))]
    NotRandomized {
        /// The env (or `batch_<n>[i]`).
        id: String,
    },
    /// A picture that cannot be made (its size or camera).
    #[error("{0}")]
    Render(#[from] gymfleet_render::RenderError),
    /// A description (MJCF, URDF) that could not be converted into assembly JSON.
    #[error("document_json: {0}")]
    Import(#[from] gymfleet_import::ImportError),
    /// A batch env index past the batch's end.
    #[error("env_index: {index} is out of range: the batch has {n_envs} envs")]
    EnvIndex {
        /// The index given.
        index: usize,
        /// The batch's size.
        n_envs: usize,
    },
    /// A document (or env) larger than a structural limit: refused before anything is
    /// built.
    #[error("{what}: {count} exceeds the server's limit of {max}; raise it with {limit}")]
    TooComplex {
        /// What was counted, e.g. `assembly.joints`.
        what: &'static str,
        /// How many the request has.
        count: usize,
        /// The limit.
        max: usize,
        /// The limit, e.g. [`Limit::Joints`].
        limit: Limit,
    },
    /// Envs whose every step would cost more than `--max-step-work`.
    #[error(
        "a step of {n_envs} env(s) × {substeps} substeps × {dofs} DOFs is {work} DOF-substeps \
         of work, over the server's limit of {max} per call; use fewer envs or substeps, or \
         raise {}",
        Limit::StepWork
    )]
    TooMuchWork {
        /// `n_envs × substeps × dofs`.
        work: usize,
        /// Envs stepped per call.
        n_envs: usize,
        /// Integration substeps per step.
        substeps: usize,
        /// DOFs per env (at least 1).
        dofs: usize,
        /// The limit.
        max: usize,
    },
    /// A document whose bodies, where it puts them, already touch in more contacts than a
    /// step may solve (`--max-contact-work`): refused at creation, by one collision
    /// detection of the initial state.
    #[error(
        "document_json: where the document puts its bodies they touch in {pairs} contact \
         pairs with {points} contact points, so its first step would be {work} contact \
         point-substeps ({points} points × {substeps} substeps), over the server's limit of \
         {max} per env step; move the bodies apart, use fewer substeps, or raise {}",
        Limit::ContactWork
    )]
    ContactsAtStart {
        /// Contact pairs with a contact point.
        pairs: usize,
        /// Contact points.
        points: usize,
        /// Substeps per step.
        substeps: u32,
        /// `points × substeps`.
        work: usize,
        /// The limit.
        max: usize,
    },
    /// A batch whose step replies could exceed the message limit.
    #[error(
        "n_envs: a step of {n_envs} envs × {observation_dim} observation values can need \
         {bytes} bytes, over the server's message limit of {max}; use smaller batches, or \
         raise {} on the server and the client",
        Limit::MessageBytes
    )]
    ReplyTooLarge {
        /// The largest reply a step could need.
        bytes: usize,
        /// The limit.
        max: usize,
        /// The batch size.
        n_envs: usize,
        /// Values per observation.
        observation_dim: usize,
    },
    /// Creating would exceed `--max-envs`.
    #[error(
        "too many environments: this request needs {requested} more, {held} of the server's \
         limit of {max} are held; close some, or raise the limit with {}",
        Limit::Envs
    )]
    TooManyEnvs {
        /// Environments the request would add.
        requested: usize,
        /// Environments held when it was refused.
        held: usize,
        /// The limit.
        max: usize,
    },
    /// Creating would exceed the caller's `--tenant-max-envs`.
    #[error(
        "too many environments for tenant {tenant}: this request needs {requested} more, \
         {held} of its quota of {max} are held; close some, or ask the operator to raise \
         {}",
        Limit::TenantEnvs
    )]
    TenantQuota {
        /// The tenant.
        tenant: Tenant,
        /// Environments the request would add.
        requested: usize,
        /// Environments the tenant held when it was refused.
        held: usize,
        /// The quota.
        max: usize,
    },
    /// A batch larger than `--max-batch-size`.
    #[error(
        "n_envs: {n_envs} exceeds the server's max batch size of {max}; split the batch, or \
         raise the limit with {}",
        Limit::BatchSize
    )]
    BatchTooLarge {
        /// The requested size.
        n_envs: usize,
        /// The limit.
        max: usize,
    },
    /// The states a `SaveBatchState` would return exceed the message limit.
    #[error(
        "env_indices: the {count} states come to {bytes} bytes, over the server's message \
         limit of {max}; save fewer envs per call, or raise {} on the server and the \
         client",
        Limit::MessageBytes
    )]
    StatesTooLarge {
        /// The states' total size.
        bytes: usize,
        /// The limit.
        max: usize,
        /// How many states.
        count: usize,
    },
    /// A document larger than `--max-document-bytes`.
    #[error(
        "{field}: {bytes} bytes exceeds the server's limit of {max} bytes; raise it \
         with {}",
        Limit::DocumentBytes
    )]
    DocumentTooLarge {
        /// `document_json`, or `state.document` for a state's document.
        field: &'static str,
        /// The document's size.
        bytes: usize,
        /// The limit.
        max: usize,
    },
    /// A pool job panicked: a server bug. The env or batch it ran on, if any, was closed.
    #[error("{}", panicked_message(operation, id.as_deref(), message))]
    Panicked {
        /// The RPC, e.g. `Step`.
        operation: &'static str,
        /// The env or batch it ran on (and that was closed), if any.
        id: Option<String>,
        /// The panic payload, if it was a string.
        message: String,
    },
    /// A pool job ended without answering (it cannot, short of a panic in the pool).
    #[error("internal error: {operation} was dropped by the worker pool without an answer")]
    JobLost {
        /// The RPC, e.g. `Step`.
        operation: &'static str,
    },
    /// The server is shutting down and takes no new work on this stream.
    #[error("the server is shutting down")]
    ShuttingDown,
    /// A request names a model the library does not have.
    #[error(
        "model: {} is not in this server's model library (known: {known})",
        Echo(name)
    )]
    UnknownModel {
        /// The name as given.
        name: String,
        /// The library's names, comma-separated (or "none: start the server with --models DIR").
        known: String,
    },
}

fn panicked_message(operation: &str, id: Option<&str>, message: &str) -> String {
    match id {
        Some(id) => format!(
            "internal error: {operation} on {id} panicked ({message}); {id} was closed because \
             its state can no longer be trusted; this is a server bug, please report it"
        ),
        None => format!(
            "internal error: {operation} panicked ({message}); nothing was created; this is a \
             server bug, please report it"
        ),
    }
}

impl ServerError {
    /// Whether the env or batch this error came from can no longer be trusted: a step
    /// panicked inside the batch's chunks (the batch crate reports it as an error rather
    /// than a panic). The server closes such an entry, as it does after a panic.
    pub(crate) fn poisons_entry(&self) -> bool {
        matches!(self, ServerError::Batch(BatchError::Panicked { .. }))
    }
}

/// Result alias for this crate.
pub type Result<T, E = ServerError> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use gymfleet_env::AssemblyError;
    use tonic::{Code, Status};

    use super::*;

    fn status(err: ServerError) -> Status {
        Status::from(err)
    }

    #[test]
    fn domain_errors_map_to_their_status_codes() {
        let bad_doc = EnvError::Document(AssemblyError::Invalid { issues: Vec::new() });
        assert_eq!(status(bad_doc.into()).code(), Code::InvalidArgument);
        assert_eq!(
            status(EnvError::NeedsReset.into()).code(),
            Code::FailedPrecondition
        );
        let in_batch = BatchError::Env {
            env: 3,
            source: EnvError::ActionLength {
                expected: 2,
                got: 1,
            },
        };
        let s = status(in_batch.into());
        assert_eq!(s.code(), Code::InvalidArgument);
        assert!(
            s.message().starts_with("env 3: values: expected 2"),
            "{}",
            s.message()
        );
        let pool = BatchError::Panicked {
            first: 0,
            last: 3,
            message: "boom".into(),
        };
        assert_eq!(status(pool.into()).code(), Code::Internal);
    }

    #[test]
    fn every_error_status_carries_its_reason_and_a_limits_flag() {
        let reason = |s: &Status| {
            s.metadata()
                .get(gymfleet_proto::REASON_KEY)
                .map(|v| v.to_str().expect("ascii").to_string())
        };
        let s = status(ServerError::NotFound {
            kind: EntityKind::Batch,
            id: "batch_9".into(),
        });
        assert_eq!(reason(&s).as_deref(), Some("BATCH_NOT_FOUND"));
        let s = status(EnvError::NeedsReset.into());
        assert_eq!(reason(&s).as_deref(), Some("NEEDS_RESET"));
        assert!(s.metadata().get(gymfleet_proto::LIMIT_KEY).is_none());
        let s = status(ServerError::BatchTooLarge { n_envs: 5, max: 4 });
        assert_eq!(reason(&s).as_deref(), Some("LIMIT_EXCEEDED"));
        assert_eq!(
            s.metadata()
                .get(gymfleet_proto::LIMIT_KEY)
                .and_then(|v| v.to_str().ok()),
            Some("--max-batch-size")
        );
        let s = status(
            BatchError::Env {
                env: 1,
                source: EnvError::NonFiniteAction {
                    index: 0,
                    value: f32::NAN,
                },
            }
            .into(),
        );
        assert_eq!(reason(&s).as_deref(), Some("INVALID_ACTION"));
        let s = status(ServerError::ShuttingDown);
        assert_eq!(reason(&s).as_deref(), Some("SHUTTING_DOWN"));
        assert_eq!(s.code(), Code::Unavailable);
    }

    #[test]
    fn not_found_names_the_id() {
        let s = status(ServerError::NotFound {
            kind: EntityKind::Batch,
            id: "batch_9".into(),
        });
        assert_eq!(s.code(), Code::NotFound);
        assert!(
            s.message().starts_with("batch \"batch_9\" not found"),
            "{}",
            s.message()
        );
    }

    #[test]
    fn long_ids_are_shortened_in_messages() {
        let id = "x".repeat(100_000);
        let s = status(ServerError::NotFound {
            kind: EntityKind::Env,
            id: id.clone(),
        });
        assert_eq!(
            s.message(),
            format!(
                "environment \"{}\"… (100000 bytes in all) not found: it was closed, \
                 reclaimed after idling, or never existed",
                "x".repeat(96)
            )
        );
        // Multi-byte characters are cut on a character boundary.
        let wide = "é".repeat(200);
        let shown = Echo(&wide).to_string();
        assert!(shown.ends_with("… (400 bytes in all)"), "{shown}");
        assert_eq!(Echo("sim_1").to_string(), "\"sim_1\"");
    }

    #[test]
    fn no_status_message_exceeds_the_bound() {
        let s = status(ServerError::InvalidArgument {
            field: "x",
            reason: "é".repeat(10_000),
        });
        assert!(
            s.message().len() <= MAX_STATUS_MESSAGE_BYTES,
            "{}",
            s.message().len()
        );
        assert!(
            s.message().ends_with("… (message cut; 20003 bytes in all)"),
            "{}",
            s.message()
        );
    }

    #[test]
    fn limits_say_how_to_raise_them() {
        let cases = [
            (
                ServerError::TooManyEnvs {
                    requested: 2,
                    held: 9,
                    max: 10,
                },
                "--max-envs",
            ),
            (
                ServerError::BatchTooLarge { n_envs: 5, max: 4 },
                "--max-batch-size",
            ),
            (
                ServerError::TenantQuota {
                    tenant: Tenant::named("team-a"),
                    requested: 1,
                    held: 4,
                    max: 4,
                },
                "--tenant-max-envs",
            ),
            (
                ServerError::DocumentTooLarge {
                    field: "document_json",
                    bytes: 5,
                    max: 4,
                },
                "--max-document-bytes",
            ),
        ];
        for (err, flag) in cases {
            let s = status(err);
            assert_eq!(s.code(), Code::ResourceExhausted);
            assert!(s.message().contains(flag), "{}", s.message());
        }
    }

    #[test]
    fn panics_are_internal_and_say_what_was_closed() {
        let s = status(ServerError::Panicked {
            operation: "Step",
            id: Some("sim_4".into()),
            message: "index out of bounds".into(),
        });
        assert_eq!(s.code(), Code::Internal);
        assert!(s
            .message()
            .contains("Step on sim_4 panicked (index out of bounds)"));
        assert!(s.message().contains("sim_4 was closed"));
        assert_eq!(status(ServerError::ShuttingDown).code(), Code::Unavailable);
    }
}
