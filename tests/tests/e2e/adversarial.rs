//! The adversarial suite: documents, options, actions, ids, streams and concurrency as a
//! confused or hostile client sends them, over the raw generated stub (no client-side
//! checks in the way). Every case asserts its exact status code and a bounded message,
//! and after every case a known-good env, created before the first, still steps
//! bitwise as it did then.

// These requests are built in the flat form (`CreateEnvRequest.document_json`, …): the
// proto deprecates it for `options`, and the server still reads it (`server/src/convert/create.rs`).
#![allow(deprecated)]

use std::future::Future;
use std::pin::Pin;

use gymfleet_e2e::{TestServer, ARM2, PENDULUM};
use gymfleet_proto::v1 as pb;
use gymfleet_server::{ServerConfig, MAX_STATUS_MESSAGE_BYTES};
use pb::simulator_client::SimulatorClient;
use tonic::transport::Channel;
use tonic::Code;

type Raw = SimulatorClient<Channel>;
type Call = Pin<Box<dyn Future<Output = Result<(), tonic::Status>> + Send>>;

fn env_request(document: &str) -> pb::CreateEnvRequest {
    pb::CreateEnvRequest {
        document_json: document.to_string(),
        ..Default::default()
    }
}

fn batch_request(document: &str, n_envs: u32) -> pb::CreateBatchRequest {
    pb::CreateBatchRequest {
        document_json: document.to_string(),
        n_envs,
        ..Default::default()
    }
}

fn step(env_id: &str, values: Vec<f32>) -> pb::StepRequest {
    pb::StepRequest {
        env_id: env_id.to_string(),
        action_type: pb::ActionType::Torque as i32,
        values,
        ..Default::default()
    }
}

/// The known-good env's observations over a seeded reset and five steps, as bits.
async fn trajectory(raw: &mut Raw, env_id: &str) -> Vec<Vec<u32>> {
    let bits = |o: pb::Observation| -> Vec<u32> {
        o.joint_positions
            .iter()
            .chain(&o.joint_velocities)
            .chain(&o.end_effector_poses)
            .map(|v| v.to_bits())
            .collect()
    };
    let first = raw
        .reset(pb::ResetRequest {
            env_id: env_id.to_string(),
            seed: Some(7),
            ..Default::default()
        })
        .await
        .expect("the known-good env resets")
        .into_inner();
    let mut out = vec![bits(first)];
    for i in 0..5 {
        let torque = if i % 2 == 0 { 1.5 } else { -0.5 };
        let reply = raw
            .step(step(env_id, vec![torque]))
            .await
            .expect("the known-good env steps")
            .into_inner();
        out.push(bits(reply.observation.expect("observation")));
    }
    out
}

/// Runs `case`, asserts its code and that its message is bounded, then that the
/// known-good env steps as before.
async fn expect(
    name: &str,
    code: Code,
    case: Call,
    raw: &mut Raw,
    good: &str,
    reference: &[Vec<u32>],
) {
    let got = case.await;
    match (&got, code) {
        (Ok(()), Code::Ok) => {}
        (Ok(()), _) => panic!("{name}: expected {code:?}, got OK"),
        (Err(status), _) => {
            assert_eq!(status.code(), code, "{name}: {status:?}");
            assert!(
                !status.message().is_empty() && status.message().len() <= MAX_STATUS_MESSAGE_BYTES,
                "{name}: a message of {} bytes",
                status.message().len()
            );
        }
    }
    assert_eq!(
        trajectory(raw, good).await,
        reference,
        "{name}: the known-good env changed"
    );
}

/// A document whose only part is a mesh file of the request's assets.
const MESH_FILE_DOC: &str = r#"{"parts": [{"name": "m", "primitive": {"type": "mesh", "file": "arm.stl"}}],
    "assembly": {"instances": [{"part": "m", "name": "m"}]}}"#;

/// One file in a tar archive, its path as given (unchecked: hostile paths too).
fn tar_of(name: &str, bytes: &[u8]) -> Vec<u8> {
    let mut header = tar::Header::new_gnu();
    header.set_size(bytes.len() as u64);
    header.set_mode(0o644);
    // `set_path` refuses `..`: write the name field itself, as a hostile client would.
    header.as_old_mut().name[..name.len()].copy_from_slice(name.as_bytes());
    header.set_cksum();
    let mut out = tar::Builder::new(Vec::new());
    out.append(&header, bytes).expect("tar");
    out.into_inner().expect("tar")
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    use std::io::Write as _;
    let mut out = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    out.write_all(bytes).expect("gzip");
    out.finish().expect("gzip")
}

/// `[[[…]]]` nested `depth` deep.
fn nested(depth: usize) -> String {
    format!("{}{}", "[".repeat(depth), "]".repeat(depth))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hostile_requests_get_their_exact_code_and_leave_everyone_else_alone() {
    let server = TestServer::start(ServerConfig {
        threads: 2,
        max_document_bytes: 1 << 20,
        ..ServerConfig::default()
    })
    .await;
    let channel = Channel::from_shared(server.url())
        .unwrap()
        .connect()
        .await
        .unwrap();
    let mut raw = Raw::new(channel).max_decoding_message_size(64 << 20);
    let good = raw
        .create_env(env_request(PENDULUM))
        .await
        .expect("known-good env")
        .into_inner()
        .env_id;
    let reference = trajectory(&mut raw, &good).await;
    let arm = raw
        .create_env(env_request(ARM2))
        .await
        .expect("an arm")
        .into_inner()
        .env_id;
    let arm_state = raw
        .save_state(pb::EnvRef { env_id: arm })
        .await
        .expect("the arm's state")
        .into_inner()
        .state;
    let batch = raw
        .create_batch(batch_request(ARM2, 4))
        .await
        .expect("a batch to abuse")
        .into_inner()
        .batch_id;
    let long_id = "sim_".to_string() + &"9".repeat(200_000);

    let r = || raw.clone();
    let cases: Vec<(&str, Code, Call)> = vec![
        // Documents.
        ("empty document", Code::InvalidArgument, {
            let mut c = r();
            Box::pin(async move { c.create_env(env_request("")).await.map(drop) })
        }),
        ("not JSON", Code::InvalidArgument, {
            let mut c = r();
            Box::pin(async move { c.create_env(env_request("{parts: ]")).await.map(drop) })
        }),
        ("JSON nested 100 000 deep", Code::InvalidArgument, {
            let mut c = r();
            let doc = nested(100_000);
            Box::pin(async move { c.create_env(env_request(&doc)).await.map(drop) })
        }),
        ("a number past f64", Code::InvalidArgument, {
            let mut c = r();
            let doc = PENDULUM.replacen("\"z\": 40", "\"z\": 1e999", 1);
            assert_ne!(doc, PENDULUM, "the edit applies");
            Box::pin(async move { c.create_env(env_request(&doc)).await.map(drop) })
        }),
        (
            "a document over --max-document-bytes",
            Code::ResourceExhausted,
            {
                let mut c = r();
                let doc = format!("{PENDULUM}{}", " ".repeat(2 << 20));
                Box::pin(async move { c.create_env(env_request(&doc)).await.map(drop) })
            },
        ),
        // Assets (an archive of mesh files, read by the server).
        (
            "assets: a tar.gz of 80 MiB of zeros",
            Code::InvalidArgument,
            {
                let mut c = r();
                let mut request = env_request(MESH_FILE_DOC);
                request.assets = gzip(&tar_of("arm.stl", &vec![0u8; 80 << 20]));
                assert!(request.assets.len() < 1 << 20, "a small bomb");
                Box::pin(async move { c.create_env(request).await.map(drop) })
            },
        ),
        ("assets: 8 MB of noise", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(MESH_FILE_DOC);
            request.assets = (0..8_000_000u32)
                .map(|i| (i.wrapping_mul(2_654_435_761) >> 24) as u8)
                .collect();
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        (
            "assets: a path out of the archive",
            Code::InvalidArgument,
            {
                let mut c = r();
                let mut request = env_request(MESH_FILE_DOC);
                request.assets = tar_of("../../etc/arm.stl", b"solid x\nendsolid x\n");
                Box::pin(async move { c.create_env(request).await.map(drop) })
            },
        ),
        ("a mesh of 70 000 vertices", Code::InvalidArgument, {
            let mut c = r();
            let vertices: Vec<[u32; 3]> = (0..70_000).map(|i| [i % 97, i % 89, i % 83]).collect();
            let doc = serde_json::json!({
                "parts": [{"name": "m", "primitive": {"type": "mesh", "vertices": vertices}}],
                "assembly": {"instances": [{"part": "m", "name": "m"}]}
            })
            .to_string();
            Box::pin(async move { c.create_env(env_request(&doc)).await.map(drop) })
        }),
        ("a message over the gRPC limit", Code::OutOfRange, {
            let c = r();
            let doc = "x".repeat(65 << 20);
            Box::pin(async move {
                c.max_encoding_message_size(128 << 20)
                    .create_env(env_request(&doc))
                    .await
                    .map(drop)
            })
        }),
        (
            "an unknown end effector, 100 kB long",
            Code::InvalidArgument,
            {
                let mut c = r();
                let mut request = env_request(PENDULUM);
                request.end_effector_ids = vec!["e".repeat(100_000)];
                Box::pin(async move { c.create_env(request).await.map(drop) })
            },
        ),
        // Options.
        ("dt = NaN", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(PENDULUM);
            request.dt = f64::NAN;
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        ("dt = 1e308", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(PENDULUM);
            request.dt = 1e308;
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        ("substeps = u32::MAX", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(PENDULUM);
            request.substeps = u32::MAX;
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        ("reset_noise = inf", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(PENDULUM);
            request.reset_noise = Some(f64::INFINITY);
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        ("negative PD gains", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(PENDULUM);
            request.pd_gains = Some(pb::PdGains {
                kp: vec![-1.0],
                kd: vec![f64::NAN],
            });
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        ("seed = u64::MAX, seed_offset = u64::MAX", Code::Ok, {
            let mut c = r();
            let mut request = batch_request(ARM2, 3);
            request.seed = Some(u64::MAX);
            request.seed_offset = u64::MAX;
            Box::pin(async move {
                let id = c.create_batch(request).await?.into_inner().batch_id;
                c.close_batch(pb::BatchRef { batch_id: id }).await.map(drop)
            })
        }),
        ("n_envs = 0", Code::InvalidArgument, {
            let mut c = r();
            Box::pin(async move { c.create_batch(batch_request(ARM2, 0)).await.map(drop) })
        }),
        ("n_envs = u32::MAX", Code::ResourceExhausted, {
            let mut c = r();
            Box::pin(async move {
                c.create_batch(batch_request(ARM2, u32::MAX))
                    .await
                    .map(drop)
            })
        }),
        ("an unknown autoreset value", Code::InvalidArgument, {
            let mut c = r();
            let mut request = batch_request(ARM2, 2);
            request.autoreset = 77;
            Box::pin(async move { c.create_batch(request).await.map(drop) })
        }),
        (
            "reset of env indices out of range and repeated",
            Code::InvalidArgument,
            {
                let mut c = r();
                let batch = batch.clone();
                Box::pin(async move {
                    c.reset_batch(pb::ResetBatchRequest {
                        batch_id: batch,
                        seed: Some(1),
                        seed_offset: 0,
                        env_indices: vec![1, 1, u32::MAX],
                        ..Default::default()
                    })
                    .await
                    .map(drop)
                })
            },
        ),
        // Task and randomisation numbers.
        ("a reach target with NaN", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(ARM2);
            request.end_effector_ids = vec!["forearm".into()];
            request.task = Some(pb::Task {
                kind: Some(pb::task::Kind::Reach(pb::ReachTask {
                    end_effector: "forearm".into(),
                    target: Some(pb::Vec3 {
                        x: f64::NAN,
                        y: 0.0,
                        z: 40.0,
                    }),
                    ..Default::default()
                })),
                action_cost: 0.0,
            });
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        ("a reach target box of ±1e308", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(ARM2);
            request.end_effector_ids = vec!["forearm".into()];
            request.task = Some(pb::Task {
                kind: Some(pb::task::Kind::Reach(pb::ReachTask {
                    end_effector: "forearm".into(),
                    target_box: Some(pb::Box3 {
                        min: Some(pb::Vec3 {
                            x: -1e308,
                            y: -1e308,
                            z: -1e308,
                        }),
                        max: Some(pb::Vec3 {
                            x: 1e308,
                            y: 1e308,
                            z: 1e308,
                        }),
                    }),
                    ..Default::default()
                })),
                action_cost: 0.0,
            });
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        (
            "an infinite track tolerance and a NaN action cost",
            Code::InvalidArgument,
            {
                let mut c = r();
                let mut request = env_request(ARM2);
                request.task = Some(pb::Task {
                    kind: Some(pb::task::Kind::Track(pb::TrackTask {
                        targets: vec![0.0, 0.0],
                        tolerance: f64::INFINITY,
                        terminate_on_success: false,
                    })),
                    action_cost: f32::NAN,
                });
                Box::pin(async move { c.create_env(request).await.map(drop) })
            },
        ),
        ("a mass scale up to infinity", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(ARM2);
            request.randomize = Some(pb::Randomization {
                mass_scale: Some(pb::Range {
                    min: 0.5,
                    max: f64::INFINITY,
                }),
                ..Default::default()
            });
            Box::pin(async move { c.create_env(request).await.map(drop) })
        }),
        ("a mass scale down to 1e-300", Code::InvalidArgument, {
            let mut c = r();
            let mut request = env_request(ARM2);
            request.randomize = Some(pb::Randomization {
                mass_scale: Some(pb::Range {
                    min: 1e-300,
                    max: 1.0,
                }),
                ..Default::default()
            });
            Box::pin(async move {
                let id = c.create_env(request).await?.into_inner().env_id;
                c.reset(pb::ResetRequest {
                    env_id: id.clone(),
                    seed: Some(3),
                    ..Default::default()
                })
                .await?;
                c.step(step(&id, vec![0.1, 0.1])).await.map(drop)
            })
        }),
        // Actions.
        ("no action type", Code::InvalidArgument, {
            let mut c = r();
            let mut request = step(&good, vec![0.0]);
            request.action_type = 0;
            Box::pin(async move { c.step(request).await.map(drop) })
        }),
        ("an unknown action type", Code::InvalidArgument, {
            let mut c = r();
            let mut request = step(&good, vec![0.0]);
            request.action_type = 9999;
            Box::pin(async move { c.step(request).await.map(drop) })
        }),
        ("too many action values", Code::InvalidArgument, {
            let mut c = r();
            let request = step(&good, vec![0.0; 1_000_000]);
            Box::pin(async move { c.step(request).await.map(drop) })
        }),
        ("a NaN action", Code::InvalidArgument, {
            let mut c = r();
            let request = step(&good, vec![f32::NAN]);
            Box::pin(async move { c.step(request).await.map(drop) })
        }),
        ("an infinite action", Code::InvalidArgument, {
            let mut c = r();
            let request = step(&good, vec![f32::INFINITY]);
            Box::pin(async move { c.step(request).await.map(drop) })
        }),
        ("a batch step of the wrong length", Code::InvalidArgument, {
            let mut c = r();
            let batch = batch.clone();
            Box::pin(async move {
                c.step_batch(pb::StepBatchRequest {
                    batch_id: batch,
                    action_type: pb::ActionType::Torque as i32,
                    actions: vec![0.0; 7],
                    ..Default::default()
                })
                .await
                .map(drop)
            })
        }),
        // Ids.
        ("an empty id", Code::NotFound, {
            let mut c = r();
            Box::pin(async move { c.step(step("", vec![0.0])).await.map(drop) })
        }),
        ("a 200 kB id", Code::NotFound, {
            let mut c = r();
            let id = long_id.clone();
            let request = step(&id, vec![0.0]);
            Box::pin(async move { c.step(request).await.map(drop) })
        }),
        ("a batch id as an env id", Code::NotFound, {
            let mut c = r();
            let batch = batch.clone();
            let request = step(&batch, vec![0.0]);
            Box::pin(async move { c.step(request).await.map(drop) })
        }),
        ("an env id as a batch id", Code::NotFound, {
            let mut c = r();
            let good = good.clone();
            Box::pin(async move {
                c.observe_batch(pb::BatchRef { batch_id: good })
                    .await
                    .map(drop)
            })
        }),
        ("ids with control characters", Code::NotFound, {
            let mut c = r();
            Box::pin(async move {
                c.close(pb::EnvRef {
                    env_id: "sim_1\u{0}\n\u{202e}".to_string(),
                })
                .await
                .map(drop)
            })
        }),
        // Saved states.
        (
            "8 MB of noise loaded as a state into the known-good env",
            Code::InvalidArgument,
            {
                let mut c = r();
                let good = good.clone();
                let noise: Vec<u8> = (0..8_000_000u32)
                    .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
                    .collect();
                Box::pin(async move {
                    c.load_state(pb::LoadStateRequest {
                        env_id: good,
                        state: noise,
                    })
                    .await
                    .map(drop)
                })
            },
        ),
        (
            "an arm's state loaded into the known-good pendulum",
            Code::InvalidArgument,
            {
                let mut c = r();
                let (good, state) = (good.clone(), arm_state.clone());
                Box::pin(async move {
                    c.load_state(pb::LoadStateRequest {
                        env_id: good,
                        state,
                    })
                    .await
                    .map(drop)
                })
            },
        ),
        ("a fork of 4 billion copies", Code::ResourceExhausted, {
            let mut c = r();
            let state = arm_state.clone();
            Box::pin(async move {
                c.fork(pb::ForkRequest {
                    state,
                    n_envs: u32::MAX,
                    autoreset: 0,
                })
                .await
                .map(drop)
            })
        }),
        ("a fork with an unknown autoreset", Code::InvalidArgument, {
            let mut c = r();
            let state = arm_state.clone();
            Box::pin(async move {
                c.fork(pb::ForkRequest {
                    state,
                    n_envs: 1,
                    autoreset: 99,
                })
                .await
                .map(drop)
            })
        }),
        ("100 000 empty states for a batch", Code::InvalidArgument, {
            let mut c = r();
            let batch_id = batch.clone();
            Box::pin(async move {
                c.load_batch_state(pb::LoadBatchStateRequest {
                    batch_id,
                    env_indices: Vec::new(),
                    states: vec![Vec::new(); 100_000],
                })
                .await
                .map(drop)
            })
        }),
        (
            "saving a batch's env 4 294 967 295",
            Code::InvalidArgument,
            {
                let mut c = r();
                let batch_id = batch.clone();
                Box::pin(async move {
                    c.save_batch_state(pb::BatchStateRequest {
                        batch_id,
                        env_indices: vec![u32::MAX],
                    })
                    .await
                    .map(drop)
                })
            },
        ),
        // Streams.
        ("a stream naming an unknown batch", Code::NotFound, {
            let mut c = r();
            Box::pin(async move {
                let requests = tokio_stream::iter(vec![pb::StepBatchRequest {
                    batch_id: "batch_999999".into(),
                    action_type: pb::ActionType::Torque as i32,
                    actions: vec![0.0; 8],
                    ..Default::default()
                }]);
                let mut replies = c.stream_batch(requests).await?.into_inner();
                match replies.message().await {
                    Ok(Some(_)) => Ok(()),
                    Ok(None) => Err(tonic::Status::unknown("stream ended without an answer")),
                    Err(status) => Err(status),
                }
            })
        }),
        (
            "a stream whose second request is bad",
            Code::InvalidArgument,
            {
                let mut c = r();
                let batch = batch.clone();
                Box::pin(async move {
                    let good_step = pb::StepBatchRequest {
                        batch_id: batch.clone(),
                        action_type: pb::ActionType::Torque as i32,
                        actions: vec![0.0; 8],
                        ..Default::default()
                    };
                    let bad_step = pb::StepBatchRequest {
                        actions: vec![f32::NAN; 8],
                        ..good_step.clone()
                    };
                    let requests = tokio_stream::iter(vec![good_step.clone(), bad_step, good_step]);
                    let mut replies = c.stream_batch(requests).await?.into_inner();
                    replies.message().await?.expect("the first step's answer");
                    match replies.message().await {
                        Ok(_) => Err(tonic::Status::unknown("the bad step was answered")),
                        Err(status) => Err(status),
                    }
                })
            },
        ),
    ];
    let count = cases.len();
    for (name, code, case) in cases {
        expect(name, code, case, &mut raw, &good, &reference).await;
    }
    assert!(count >= 30, "{count} cases");

    // Concurrency: 32 callers step the same env while one closes it; each gets OK or
    // NOT_FOUND, none an internal error, and the known-good env is untouched.
    let victim = raw
        .create_env(env_request(PENDULUM))
        .await
        .expect("victim")
        .into_inner()
        .env_id;
    let mut tasks = tokio::task::JoinSet::new();
    for i in 0..32 {
        let mut c = raw.clone();
        let victim = victim.clone();
        tasks.spawn(async move {
            if i == 16 {
                c.close(pb::EnvRef { env_id: victim }).await.map(drop)
            } else {
                c.reset(pb::ResetRequest {
                    env_id: victim.clone(),
                    seed: Some(i),
                    ..Default::default()
                })
                .await?;
                c.step(step(&victim, vec![0.5])).await.map(drop)
            }
        });
    }
    while let Some(joined) = tasks.join_next().await {
        if let Err(status) = joined.expect("task") {
            assert!(
                matches!(status.code(), Code::NotFound | Code::FailedPrecondition),
                "{status:?}"
            );
        }
    }
    assert_eq!(trajectory(&mut raw, &good).await, reference);
    server.stop().await.expect("clean shutdown");
}
