//! [`ServerError`]'s mapping to `tonic::Status`: each error's code, the limit it refused a
//! call for, and its message, bounded to [`MAX_STATUS_MESSAGE_BYTES`].

use gymfleet_batch::BatchError;
use gymfleet_env::EnvError;
use gymfleet_proto::v1::ErrorReason;
use tonic::metadata::MetadataValue;
use tonic::{Code, Status};

use super::{EntityKind, ServerError, MAX_STATUS_MESSAGE_BYTES};
use crate::limit::Limit;

/// `message` cut to [`MAX_STATUS_MESSAGE_BYTES`] on a character boundary, saying so.
pub(super) fn bounded(message: String) -> String {
    if message.len() <= MAX_STATUS_MESSAGE_BYTES {
        return message;
    }
    let mut end = MAX_STATUS_MESSAGE_BYTES - 64;
    while !message.is_char_boundary(end) {
        end -= 1;
    }
    format!(
        "{}… (message cut; {} bytes in all)",
        &message[..end],
        message.len()
    )
}

impl From<ServerError> for Status {
    fn from(err: ServerError) -> Self {
        let message = match &err {
            // The env crate knows nothing of the server's flags: the step's refusal says
            // here which one raises it.
            ServerError::Env(EnvError::ContactWork(_)) => {
                format!("{err}; the limit is raised with {}", Limit::ContactWork)
            }
            ServerError::Batch(BatchError::Env {
                source: EnvError::ContactWork(_),
                ..
            }) => format!(
                "{err}; the batch's other envs took their step (ObserveBatch reads them); the \
                 limit is raised with {}",
                Limit::ContactWork
            ),
            _ => err.to_string(),
        };
        let mut status = Status::new(err.code(), bounded(message));
        with_reason(&mut status, err.reason(), err.limit());
        status
    }
}

/// Puts `reason` (and the limit's flag, for a limit's refusal) into `status`'s metadata
/// ([`gymfleet_proto::REASON_KEY`], [`gymfleet_proto::LIMIT_KEY`]).
pub(crate) fn with_reason(status: &mut Status, reason: ErrorReason, limit: Option<Limit>) {
    let metadata = status.metadata_mut();
    metadata.insert(
        gymfleet_proto::REASON_KEY,
        MetadataValue::from_static(reason.wire_name()),
    );
    if let Some(limit) = limit {
        if let Ok(flag) = MetadataValue::try_from(format!("--{}", limit.flag())) {
            metadata.insert(gymfleet_proto::LIMIT_KEY, flag);
        }
    }
}

/// The reason of an environment error.
fn env_reason(err: &EnvError) -> ErrorReason {
    match err {
        EnvError::Document(_)
        | EnvError::Physics(_)
        | EnvError::BadConfig { .. }
        | EnvError::BadTask { .. } => ErrorReason::InvalidDocument,
        EnvError::ActionLength { .. }
        | EnvError::NonFiniteAction { .. }
        | EnvError::UnknownActionType { .. }
        | EnvError::MocapPosesLength { .. }
        | EnvError::BadMocapPose { .. } => ErrorReason::InvalidAction,
        EnvError::StateFormat { .. }
        | EnvError::BadState { .. }
        | EnvError::BadJointState { .. } => ErrorReason::InvalidState,
        EnvError::UnknownEndEffector { .. }
        | EnvError::UnknownMocapBody { .. }
        | EnvError::UnknownHeightfield { .. }
        | EnvError::UnknownKeyframe { .. } => ErrorReason::UnknownName,
        EnvError::BadHeights { .. } => ErrorReason::InvalidField,
        EnvError::NeedsReset => ErrorReason::NeedsReset,
        EnvError::ContactWork(_) => ErrorReason::LimitExceeded,
    }
}

impl ServerError {
    /// The limit this error refused a call for, if it is a limit's refusal.
    pub fn limit(&self) -> Option<Limit> {
        Some(match self {
            ServerError::TooManyEnvs { .. } => Limit::Envs,
            ServerError::TenantQuota { .. } => Limit::TenantEnvs,
            ServerError::BatchTooLarge { .. } => Limit::BatchSize,
            ServerError::DocumentTooLarge { .. } => Limit::DocumentBytes,
            ServerError::ReplyTooLarge { .. } | ServerError::StatesTooLarge { .. } => {
                Limit::MessageBytes
            }
            ServerError::TooMuchWork { .. } => Limit::StepWork,
            ServerError::ContactsAtStart { .. }
            | ServerError::Env(EnvError::ContactWork(_))
            | ServerError::Batch(BatchError::Env {
                source: EnvError::ContactWork(_),
                ..
            }) => Limit::ContactWork,
            ServerError::TooComplex { limit, .. } => *limit,
            _ => return None,
        })
    }

    /// Why, for machines: the [`ErrorReason`] this error goes out with.
    pub fn reason(&self) -> ErrorReason {
        match self {
            ServerError::InvalidArgument { .. }
            | ServerError::EnvIndex { .. }
            | ServerError::Render(_) => ErrorReason::InvalidField,
            ServerError::Import(_) => ErrorReason::InvalidDocument,
            ServerError::Env(env) => env_reason(env),
            ServerError::Batch(batch) => match batch {
                BatchError::NoEnvs | BatchError::EnvIndices { .. } => ErrorReason::InvalidField,
                BatchError::ActionLength { .. }
                | BatchError::NonFiniteAction { .. }
                | BatchError::MocapPosesLength { .. } => ErrorReason::InvalidAction,
                BatchError::StateCount { .. } => ErrorReason::InvalidState,
                BatchError::TooManyEnvs { .. } => ErrorReason::LimitExceeded,
                BatchError::Env { source, .. } | BatchError::Keyframe(source) => env_reason(source),
                BatchError::PoolStart { .. } | BatchError::Panicked { .. } => ErrorReason::Internal,
            },
            ServerError::NotFound {
                kind: EntityKind::Env,
                ..
            } => ErrorReason::EnvNotFound,
            ServerError::NotFound {
                kind: EntityKind::Batch,
                ..
            } => ErrorReason::BatchNotFound,
            ServerError::UnknownModel { .. } => ErrorReason::ModelNotFound,
            ServerError::NotRandomized { .. } => ErrorReason::NotRandomized,
            ServerError::TooManyEnvs { .. }
            | ServerError::TenantQuota { .. }
            | ServerError::TooComplex { .. }
            | ServerError::TooMuchWork { .. }
            | ServerError::ContactsAtStart { .. }
            | ServerError::ReplyTooLarge { .. }
            | ServerError::StatesTooLarge { .. }
            | ServerError::BatchTooLarge { .. }
            | ServerError::DocumentTooLarge { .. } => ErrorReason::LimitExceeded,
            ServerError::Panicked { .. } | ServerError::JobLost { .. } => ErrorReason::Internal,
            ServerError::ShuttingDown => ErrorReason::ShuttingDown,
        }
    }

    /// The status code this error goes out with: its reason's class.
    pub(crate) fn code(&self) -> Code {
        code_of(self.reason())
    }
}

/// The status code of each reason (the proto's `ErrorReason` says which goes with which).
fn code_of(reason: ErrorReason) -> Code {
    match reason {
        ErrorReason::InvalidDocument
        | ErrorReason::InvalidAction
        | ErrorReason::InvalidState
        | ErrorReason::UnknownName
        | ErrorReason::InvalidField => Code::InvalidArgument,
        ErrorReason::EnvNotFound | ErrorReason::BatchNotFound | ErrorReason::ModelNotFound => {
            Code::NotFound
        }
        ErrorReason::NeedsReset | ErrorReason::NotRandomized => Code::FailedPrecondition,
        ErrorReason::LimitExceeded => Code::ResourceExhausted,
        ErrorReason::Unauthenticated => Code::Unauthenticated,
        ErrorReason::ShuttingDown => Code::Unavailable,
        ErrorReason::Internal | ErrorReason::Unspecified => Code::Internal,
    }
}
