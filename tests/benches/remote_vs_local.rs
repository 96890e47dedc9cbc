//! Remote `StepBatch` (gRPC over loopback, through `gymfleet-client`) against in-process
//! `EnvBatch::step` of the same batch, at 16, 256 and 1024 arm2 envs, with 1 and 2 pool
//! threads. Throughput is in env-steps.
//!
//! Variants, all on a pool of the same size:
//! - `local`: `EnvBatch::step` called on the bench thread (which also runs chunks while
//!   it waits, as any in-process caller does);
//! - `local_on_pool`: the same call made from a `StepPool::spawn` job, answered through
//!   a channel — the server's execution model without the network;
//! - `direct`: the server's own service called without a network
//!   (`gymfleet_server::DirectService`): edge conversion, registry, pool hand-off and
//!   reply, with no encoding, HTTP/2 or client; `local_on_pool` → `direct` is the
//!   service's own cost, `direct` → `remote` the transport's;
//! - `remote`: unary `StepBatch`;
//! - `remote_stream`: `StreamBatch` with 4 steps in flight;
//! - `rpc_roundtrip`: one `GetServerInfo` call, the floor of the remote overhead.
//!
//! `reply_codec/{16,256,1024}` encodes a real batch step's reply (`BatchStepResult`, from an
//! in-process step of the same arm2 batch) with prost and decodes it again: the payload's own
//! share of the remote path, apart from HTTP/2 and the wake-ups.
//!
//! Both sides use same-step autoreset with 200-step episodes, so they cycle through the
//! same states however many iterations criterion runs.

// These requests are built in the flat form (`CreateEnvRequest.document_json`, …): the
// proto deprecates it for `options`, and the server still reads it (`server/src/convert/create.rs`).
#![allow(deprecated)]
#![allow(missing_docs)]

use std::sync::mpsc;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use gymfleet_batch::{Autoreset, BatchStepOutput, EnvBatch, StepPool};
use gymfleet_client::BatchOptions;
use gymfleet_e2e::{TestServer, ARM2};
use gymfleet_env::{ActionType, EnvConfig, RobotEnv};
use gymfleet_proto::v1 as pb;
use gymfleet_server::{DirectService, ServerConfig, Tenant};
use pb::simulator_server::Simulator;
use prost::Message;

const SIZES: [usize; 3] = [16, 256, 1024];
const THREADS: [usize; 2] = [1, 2];
const MAX_STEPS: u32 = 200;

fn actions(n_envs: usize) -> Vec<f32> {
    (0..n_envs * 2)
        .map(|i| ((i * 37 % 17) as f32 / 17.0 - 0.5) * 0.4)
        .collect()
}

fn bench_remote_vs_local(c: &mut Criterion) {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("tokio runtime");
    let mut group = c.benchmark_group("step_batch_arm2");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));

    for threads in THREADS {
        let server = rt.block_on(TestServer::start(ServerConfig {
            threads,
            idle_ttl: Duration::ZERO,
            ..ServerConfig::default()
        }));
        let client = rt.block_on(server.client());
        let pool = StepPool::new(threads).expect("pool");
        let config = EnvConfig {
            max_steps: MAX_STEPS,
            ..EnvConfig::with_end_effectors(["forearm"])
        };
        let template = RobotEnv::from_json(ARM2, config).expect("arm2");
        let direct = rt
            .block_on(async {
                DirectService::new(ServerConfig {
                    threads,
                    ..ServerConfig::default()
                })
            })
            .expect("direct service");
        let tenant = Tenant::anonymous();

        // The cost of one round trip with no simulation: the floor of remote overhead.
        group.throughput(Throughput::Elements(1));
        group.bench_function(
            BenchmarkId::new("rpc_roundtrip", format!("{threads}t")),
            |b| {
                b.iter_custom(|iters| {
                    rt.block_on(async {
                        let start = Instant::now();
                        for _ in 0..iters {
                            client.server_info().await.expect("server info");
                        }
                        start.elapsed()
                    })
                })
            },
        );

        for n_envs in SIZES {
            let acts = actions(n_envs);
            group.throughput(Throughput::Elements(n_envs as u64));
            let label = format!("{threads}t");

            let mut batch =
                EnvBatch::new(&template, n_envs, Autoreset::SameStep).expect("local batch");
            let mut out = BatchStepOutput::default();
            group.bench_function(BenchmarkId::new(format!("local/{label}"), n_envs), |b| {
                b.iter(|| {
                    batch
                        .step(&pool, ActionType::Torque, &acts, &mut out)
                        .expect("local step")
                })
            });

            let mut on_pool = Some((
                EnvBatch::new(&template, n_envs, Autoreset::SameStep).expect("local batch"),
                BatchStepOutput::default(),
            ));
            group.bench_function(
                BenchmarkId::new(format!("local_on_pool/{label}"), n_envs),
                |b| {
                    b.iter(|| {
                        let (mut batch, mut out) = on_pool.take().expect("batch");
                        let (tx, rx) = mpsc::channel();
                        let (job_pool, job_acts) = (pool.clone(), acts.clone());
                        pool.spawn(move || {
                            batch
                                .step(&job_pool, ActionType::Torque, &job_acts, &mut out)
                                .expect("pool step");
                            let _ = tx.send((batch, out));
                        });
                        on_pool = Some(rx.recv().expect("pool answer"));
                    })
                },
            );

            let create = pb::CreateBatchRequest {
                document_json: ARM2.into(),
                end_effector_ids: vec!["forearm".into()],
                max_steps: MAX_STEPS,
                n_envs: n_envs as u32,
                autoreset: pb::Autoreset::SameStep as i32,
                ..Default::default()
            };
            let direct_batch = rt
                .block_on(
                    direct
                        .simulator()
                        .create_batch(DirectService::request(create, &tenant)),
                )
                .expect("direct batch")
                .into_inner()
                .batch_id;
            group.bench_function(BenchmarkId::new(format!("direct/{label}"), n_envs), |b| {
                b.iter_custom(|iters| {
                    rt.block_on(async {
                        let start = Instant::now();
                        for _ in 0..iters {
                            let step = pb::StepBatchRequest {
                                batch_id: direct_batch.clone(),
                                action_type: pb::ActionType::Torque as i32,
                                actions: acts.clone(),
                                ..Default::default()
                            };
                            direct
                                .simulator()
                                .step_batch(DirectService::request(step, &tenant))
                                .await
                                .expect("direct step");
                        }
                        start.elapsed()
                    })
                })
            });

            let options = BatchOptions::new(ARM2, n_envs)
                .end_effectors(["forearm"])
                .max_steps(MAX_STEPS)
                .autoreset(gymfleet_client::Autoreset::SameStep);
            let remote = rt
                .block_on(client.create_batch(options.clone()))
                .expect("remote batch");
            group.bench_function(BenchmarkId::new(format!("remote/{label}"), n_envs), |b| {
                b.iter_custom(|iters| {
                    rt.block_on(async {
                        let start = Instant::now();
                        for _ in 0..iters {
                            remote
                                .step(gymfleet_client::ActionType::Torque, &acts)
                                .await
                                .expect("remote step");
                        }
                        start.elapsed()
                    })
                })
            });

            let streamed = rt
                .block_on(client.create_batch(options))
                .expect("remote batch");
            group.bench_function(
                BenchmarkId::new(format!("remote_stream/{label}"), n_envs),
                |b| {
                    b.iter_custom(|iters| {
                        rt.block_on(async {
                            let mut stream = streamed.stream_with_window(4).await.expect("stream");
                            let start = Instant::now();
                            for _ in 0..iters {
                                stream
                                    .send(gymfleet_client::ActionType::Torque, &acts)
                                    .await
                                    .expect("send");
                                // Keep at most `window` results unconsumed.
                                while stream.pending() > stream.window() {
                                    stream.next().await.expect("pending").expect("step");
                                }
                            }
                            stream.finish().await.expect("finish");
                            start.elapsed()
                        })
                    })
                },
            );
            rt.block_on(remote.close()).expect("close");
            rt.block_on(streamed.close()).expect("close");
        }
        rt.block_on(server.stop()).expect("server stops");
    }
    group.finish();
}

fn bench_reply_codec(c: &mut Criterion) {
    let pool = StepPool::new(1).expect("pool");
    let config = EnvConfig {
        max_steps: MAX_STEPS,
        ..EnvConfig::with_end_effectors(["forearm"])
    };
    let template = RobotEnv::from_json(ARM2, config).expect("arm2");
    let mut group = c.benchmark_group("reply_codec");
    group.sample_size(20);
    for n_envs in SIZES {
        let mut batch = EnvBatch::new(&template, n_envs, Autoreset::SameStep).expect("batch");
        let mut out = BatchStepOutput::default();
        batch
            .step(&pool, ActionType::Torque, &actions(n_envs), &mut out)
            .expect("step");
        let reply = pb::BatchStepResult {
            batch_id: "b-0123456789abcdef".to_string(),
            step_index: 1,
            observations: out.observations.clone(),
            rewards: out.rewards.clone(),
            terminated: out.terminated.clone(),
            truncated: out.truncated.clone(),
            final_env_indices: out.final_env_indices.clone(),
            final_observations: out.final_observations.clone(),
            terms: out.terms.clone(),
            ..Default::default()
        };
        group.throughput(Throughput::Bytes(reply.encoded_len() as u64));
        group.bench_function(BenchmarkId::from_parameter(n_envs), |b| {
            b.iter(|| {
                let bytes = reply.encode_to_vec();
                pb::BatchStepResult::decode(bytes.as_slice()).expect("decode")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_remote_vs_local, bench_reply_codec);
criterion_main!(benches);
