//! [`ServerError`]'s mapping to `tonic::Status`: each error's code, the limit it refused a
//! call for, and its message, bounded to [`MAX_STATUS_MESSAGE_BYTES`].

use gymfleet_batch::BatchError;
use gymfleet_env::EnvError;
use tonic::{Code, Status};

use super::{ServerError, MAX_STATUS_MESSAGE_BYTES};
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

/// The status code of an environment error.
fn env_code(err: &EnvError) -> Code {
    match err {
        EnvError::Document(_)
        | EnvError::Physics(_)
        | EnvError::UnknownEndEffector { .. }
        | EnvError::BadConfig { .. }
        | EnvError::BadTask { .. }
        | EnvError::ActionLength { .. }
        | EnvError::NonFiniteAction { .. }
        | EnvError::UnknownActionType { .. }
        | EnvError::StateFormat { .. }
        | EnvError::BadState { .. }
        | EnvError::BadJointState { .. }
        | EnvError::UnknownMocapBody { .. }
        | EnvError::UnknownHeightfield { .. }
        | EnvError::BadHeights { .. }
        | EnvError::UnknownKeyframe { .. }
        | EnvError::MocapPosesLength { .. }
        | EnvError::BadMocapPose { .. } => Code::InvalidArgument,
        EnvError::NeedsReset => Code::FailedPrecondition,
        EnvError::ContactWork(_) => Code::ResourceExhausted,
    }
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
        Status::new(err.code(), bounded(message))
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

    /// The status code this error goes out with.
    pub(crate) fn code(&self) -> Code {
        match self {
            ServerError::InvalidArgument { .. } => Code::InvalidArgument,
            ServerError::Env(env) => env_code(env),
            ServerError::Batch(batch) => match batch {
                BatchError::NoEnvs
                | BatchError::ActionLength { .. }
                | BatchError::NonFiniteAction { .. }
                | BatchError::MocapPosesLength { .. }
                | BatchError::EnvIndices { .. }
                | BatchError::StateCount { .. } => Code::InvalidArgument,
                BatchError::TooManyEnvs { .. } => Code::ResourceExhausted,
                BatchError::Env { source, .. } | BatchError::Keyframe(source) => env_code(source),
                BatchError::PoolStart { .. } | BatchError::Panicked { .. } => Code::Internal,
            },
            ServerError::NotFound { .. } | ServerError::UnknownModel { .. } => Code::NotFound,
            ServerError::NotRandomized { .. } => Code::FailedPrecondition,
            ServerError::EnvIndex { .. } | ServerError::Render(_) | ServerError::Import(_) => {
                Code::InvalidArgument
            }
            ServerError::TooManyEnvs { .. }
            | ServerError::TenantQuota { .. }
            | ServerError::TooComplex { .. }
            | ServerError::TooMuchWork { .. }
            | ServerError::ContactsAtStart { .. }
            | ServerError::ReplyTooLarge { .. }
            | ServerError::StatesTooLarge { .. }
            | ServerError::BatchTooLarge { .. }
            | ServerError::DocumentTooLarge { .. } => Code::ResourceExhausted,
            ServerError::Panicked { .. }
            | ServerError::JobLost { .. }
            | ServerError::Reflection(_)
            | ServerError::Tls(_)
            | ServerError::Bind { .. }
            | ServerError::ModelLibrary { .. }
            | ServerError::Io(_)
            | ServerError::Transport(_) => Code::Internal,
            ServerError::ShuttingDown => Code::Unavailable,
        }
    }
}
