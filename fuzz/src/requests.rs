//! The server's request doors (issue R2): a `CreateEnvRequest` and a `StepBatchRequest`,
//! decoded by prost from untrusted bytes and handed to the server's own service
//! ([`gymfleet_server::DirectService`]: edge conversion, limits, registry, pool) without
//! a network. Shared by the libFuzzer binaries and `tests/tests/fuzz_corpora.rs`.
//!
//! Besides "no panic" each asserts: no call ends INTERNAL (the server catches a panic in
//! a pool job and answers INTERNAL, which would hide it from the fuzzer), every status
//! message stays under the server's bound, an env that was created steps and closes, and
//! a batch step's reply has the batch's shape.

// These requests are built in the flat form (`CreateEnvRequest.document_json`, …): the
// proto deprecates it for `options`, and the server still reads it (`server/src/convert/create.rs`).
#![allow(deprecated)]

use std::sync::OnceLock;

use gymfleet_proto::v1 as pb;
use gymfleet_server::{DirectService, ServerConfig, Tenant, MAX_STATUS_MESSAGE_BYTES};
use pb::simulator_server::Simulator;
use prost::Message;
use tonic::{Code, Status};

use crate::targets::Reached;

/// Envs in the step target's batch.
pub const STEP_BATCH_ENVS: usize = 4;

/// One service for every input of a process: its pool, and the batch the step target
/// steps (`models/pendulum.json`, [`STEP_BATCH_ENVS`] envs with autoreset).
struct Harness {
    runtime: tokio::runtime::Runtime,
    service: DirectService,
    batch: pb::BatchInfo,
}

fn harness() -> &'static Harness {
    static HARNESS: OnceLock<Harness> = OnceLock::new();
    HARNESS.get_or_init(|| {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a tokio runtime");
        let config = ServerConfig {
            threads: 1,
            ..ServerConfig::default()
        };
        let service = runtime.block_on(async { DirectService::new(config) });
        let service = service.expect("a direct service");
        let create = pb::CreateBatchRequest {
            document_json: include_str!("../../models/pendulum.json").into(),
            n_envs: STEP_BATCH_ENVS as u32,
            max_steps: 50,
            ..Default::default()
        };
        let batch = runtime
            .block_on(
                service
                    .simulator()
                    .create_batch(DirectService::request(create, &Tenant::anonymous())),
            )
            .expect("the step target's batch")
            .into_inner();
        Harness {
            runtime,
            service,
            batch,
        }
    })
}

/// Checks a refusal: not INTERNAL (a caught panic or a bug), and a bounded message.
fn refused(status: &Status) -> Reached {
    assert_ne!(
        status.code(),
        Code::Internal,
        "INTERNAL (a caught panic?): {}",
        status.message()
    );
    assert!(
        status.message().len() <= MAX_STATUS_MESSAGE_BYTES,
        "a status message of {} bytes",
        status.message().len()
    );
    Reached::Validation
}

/// `CreateEnv` with the decoded request; an env it creates is stepped once and closed.
pub fn create_env_request(data: &[u8]) -> Reached {
    let Ok(request) = pb::CreateEnvRequest::decode(data) else {
        return Reached::Parsing;
    };
    let h = harness();
    let sim = h.service.simulator();
    let tenant = Tenant::anonymous();
    h.runtime.block_on(async {
        let info = match sim
            .create_env(DirectService::request(request, &tenant))
            .await
        {
            Ok(info) => info.into_inner(),
            Err(status) => return refused(&status),
        };
        let step = pb::StepRequest {
            env_id: info.env_id.clone(),
            action_type: pb::ActionType::Torque as i32,
            values: vec![0.0; info.action_dim as usize],
            ..Default::default()
        };
        if let Err(status) = sim.step(DirectService::request(step, &tenant)).await {
            refused(&status);
        }
        let close = pb::EnvRef {
            env_id: info.env_id,
        };
        sim.close(DirectService::request(close, &tenant))
            .await
            .expect("an env that was created closes");
        Reached::Stepping
    })
}

/// `StepBatch` with the decoded request, on the harness's batch when it names none.
pub fn step_batch_request(data: &[u8]) -> Reached {
    let Ok(mut request) = pb::StepBatchRequest::decode(data) else {
        return Reached::Parsing;
    };
    let h = harness();
    if request.batch_id.is_empty() {
        request.batch_id = h.batch.batch_id.clone();
    }
    let stepped = h.runtime.block_on(
        h.service
            .simulator()
            .step_batch(DirectService::request(request, &Tenant::anonymous())),
    );
    let reply = match stepped {
        Ok(reply) => reply.into_inner(),
        Err(status) => return refused(&status),
    };
    let n = STEP_BATCH_ENVS;
    let observation_dim = h.batch.observation_dim as usize;
    assert_eq!(reply.rewards.len(), n);
    assert_eq!(reply.terminated.len(), n);
    assert_eq!(reply.truncated.len(), n);
    assert_eq!(reply.observations.len(), n * observation_dim);
    assert_eq!(
        reply.final_observations.len(),
        reply.final_env_indices.len() * observation_dim
    );
    Reached::Stepping
}
