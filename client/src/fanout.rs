//! Fanning calls out over a fleet's servers: running them concurrently, and naming the
//! server an error came from.

use std::future::Future;

use tokio::task::JoinSet;

use crate::client::Client;
use crate::error::{ClientError, Result};

/// `err` as it happened on `client`'s server.
pub(crate) fn on_server(client: &Client, err: ClientError) -> ClientError {
    ClientError::OnServer {
        server: client.addr().to_string(),
        error: Box::new(err),
    }
}

/// Runs the futures concurrently (each as a task, so their encoding and decoding can use
/// every runtime thread; one alone runs in the caller, with nothing to overlap) and
/// returns their outputs in order. A panicking future panics the caller; tasks still
/// running when the returned future is dropped are aborted.
pub(crate) async fn join_all<T, F>(futures: impl IntoIterator<Item = F>) -> Vec<Result<T>>
where
    F: Future<Output = Result<T>> + Send + 'static,
    T: Send + 'static,
{
    let mut futures: Vec<F> = futures.into_iter().collect();
    if futures.len() == 1 {
        return vec![futures.remove(0).await];
    }
    let mut set = JoinSet::new();
    let mut count = 0;
    for (i, future) in futures.into_iter().enumerate() {
        set.spawn(async move { (i, future.await) });
        count += 1;
    }
    let mut outputs: Vec<Option<Result<T>>> = (0..count).map(|_| None).collect();
    while let Some(joined) = set.join_next().await {
        match joined {
            Ok((i, output)) => outputs[i] = Some(output),
            Err(err) if err.is_panic() => std::panic::resume_unwind(err.into_panic()),
            // Cancelled: only when the runtime shuts down; the slot reports it below.
            Err(_) => {}
        }
    }
    outputs
        .into_iter()
        .map(|output| {
            output.unwrap_or_else(|| {
                Err(ClientError::Unavailable {
                    reason: crate::ErrorReason::Unspecified,
                    message: "the call was cancelled: the runtime is shutting down".to_string(),
                    code: tonic::Code::Cancelled,
                })
            })
        })
        .collect()
}
