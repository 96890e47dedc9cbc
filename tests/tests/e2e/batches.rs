//! Batches: shapes, reset/observe, autoreset, stream vs unary, concurrent clients.

use gymfleet_client::{ActionType, Autoreset, BatchOptions, Client};
use gymfleet_e2e::{TestServer, ARM2};

use crate::{actions, assert_close, bits};

fn arm_batch(n_envs: usize) -> BatchOptions {
    BatchOptions::new(ARM2, n_envs)
        .end_effectors(["forearm"])
        .seed(11)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn batch_of_16_arms_has_the_documented_shapes() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client
        .create_batch(arm_batch(16))
        .await
        .expect("create batch");
    let info = batch.info().clone();
    assert!(info.batch_id.starts_with("batch_"), "{}", info.batch_id);
    assert_eq!(
        (
            info.n_envs,
            info.action_dim,
            info.observation_dim,
            info.num_joints
        ),
        (16, 2, 11, 2)
    );
    assert_eq!(info.autoreset, Autoreset::Disabled);

    let reset = batch.reset(Some(11)).await.expect("reset");
    assert_eq!(reset.observations().len(), 16 * 11);
    for env in 0..16 {
        assert_close(&reset.obs(env)[..4], &[0.0; 4], 1e-4);
    }

    // Env i gets torques (i/8, -i/8): rows must differ by env, and equal actions on
    // identical envs must give identical rows.
    let mut acts = Vec::with_capacity(32);
    for env in 0..16 {
        let t = (env % 8) as f32 / 8.0;
        acts.extend_from_slice(&[t, -t]);
    }
    let mut last = None;
    for k in 1..=5u64 {
        let step = batch.step(ActionType::Torque, &acts).await.expect("step");
        assert_eq!(step.step_index(), k);
        assert_eq!(step.n_envs(), 16);
        assert_eq!(step.observations().len(), 16 * 11);
        assert_eq!(step.rewards().len(), 16);
        assert_eq!(step.terminated().len(), 16);
        assert_eq!(step.truncated().len(), 16);
        assert!(step.terminated().iter().chain(step.truncated()).all(|f| !f));
        assert!((0..16).all(|i| step.obs(i).len() == 11));
        assert!(step.final_env_indices().is_empty());
        assert_eq!(step.final_observation(0), None);
        last = Some(step);
    }
    let last = last.expect("stepped");
    assert_eq!(
        bits(last.obs(1)),
        bits(last.obs(9)),
        "same actions, same rows"
    );
    assert_ne!(
        bits(last.obs(1)),
        bits(last.obs(2)),
        "different actions, different rows"
    );
    assert!(last.obs(1)[0] > 0.0, "positive torque raises joint 0");

    let observed = batch.observe().await.expect("observe");
    assert_eq!(bits(observed.observations()), bits(last.observations()));
    batch.close().await.expect("close");
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn same_step_autoreset_returns_final_observations() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client
        .create_batch(arm_batch(4).max_steps(3).autoreset(Autoreset::SameStep))
        .await
        .expect("create batch");
    assert_eq!(batch.info().autoreset, Autoreset::SameStep);
    let first = batch.reset(None).await.expect("reset");
    let acts = vec![0.3_f32; 8];
    for _ in 0..2 {
        let step = batch.step(ActionType::Torque, &acts).await.expect("step");
        assert!(step.final_env_indices().is_empty());
    }
    let step = batch
        .step(ActionType::Torque, &acts)
        .await
        .expect("final step");
    assert_eq!(step.truncated(), [true; 4]);
    assert_eq!(step.final_env_indices(), [0, 1, 2, 3]);
    for env in 0..4 {
        let last = step.final_observation(env).expect("final observation");
        assert_eq!(last.len(), 11);
        assert!(last[0] != 0.0, "the final observation is the stepped one");
        assert_eq!(
            bits(step.obs(env)),
            bits(first.obs(env)),
            "row is the reset observation"
        );
    }
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn stream_and_unary_steps_are_bitwise_identical() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let unary = client
        .create_batch(arm_batch(16))
        .await
        .expect("unary batch");
    let streamed = client
        .create_batch(arm_batch(16))
        .await
        .expect("streamed batch");
    unary.reset(Some(5)).await.expect("reset");
    streamed.reset(Some(5)).await.expect("reset");

    const STEPS: u64 = 40;
    let plan: Vec<Vec<f32>> = (0..STEPS).map(|k| actions(k, 32, 0.5)).collect();

    let mut expected = Vec::new();
    for acts in &plan {
        expected.push(
            unary
                .step(ActionType::Torque, acts)
                .await
                .expect("unary step"),
        );
    }

    let mut stream = streamed.stream_with_window(6).await.expect("open stream");
    assert_eq!(stream.window(), 6);
    let mut got = Vec::new();
    // Pipelined: send everything (the window makes `send` collect early results).
    for acts in &plan {
        stream.send(ActionType::Torque, acts).await.expect("send");
    }
    assert_eq!(stream.pending(), STEPS as usize);
    while let Some(step) = stream.next().await {
        got.push(step.expect("streamed step"));
    }
    // And lock-step, through `step`.
    let extra = actions(999, 32, 0.5);
    let tail_stream = stream
        .step(ActionType::Torque, &extra)
        .await
        .expect("stream step");
    let tail_unary = unary
        .step(ActionType::Torque, &extra)
        .await
        .expect("unary step");
    assert!(stream.finish().await.expect("finish").is_empty());

    assert_eq!(got.len(), expected.len());
    for (k, (a, b)) in expected.iter().zip(&got).enumerate() {
        assert_eq!(b.step_index(), k as u64 + 1, "results come back in order");
        assert_eq!(bits(a.observations()), bits(b.observations()), "step {k}");
        assert_eq!(bits(a.rewards()), bits(b.rewards()));
        assert_eq!(a.terminated(), b.terminated());
        assert_eq!(a.truncated(), b.truncated());
    }
    assert_eq!(
        bits(tail_stream.observations()),
        bits(tail_unary.observations())
    );
    assert_eq!(tail_stream.step_index(), STEPS + 1);
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn eight_concurrent_clients_on_separate_batches() {
    let server = TestServer::start_default().await;
    let url = server.url();
    let tasks: Vec<_> = (0..8usize)
        .map(|i| {
            let url = url.clone();
            tokio::spawn(async move {
                let client = Client::connect(url).await?;
                let n_envs = 4 + i;
                let batch = client.create_batch(arm_batch(n_envs)).await?;
                assert_eq!(batch.info().n_envs, n_envs);
                let acts = actions(i as u64, n_envs * 2, 0.5);
                let mut stream = batch.stream().await?;
                for k in 0..15u64 {
                    let step = if k % 2 == 0 {
                        batch.step(ActionType::Torque, &acts).await?
                    } else {
                        stream.step(ActionType::Torque, &acts).await?
                    };
                    assert_eq!(step.step_index(), k + 1);
                    assert_eq!(step.observations().len(), n_envs * 11);
                    assert_eq!(step.rewards().len(), n_envs);
                }
                stream.finish().await?;
                batch.close().await?;
                Ok::<_, gymfleet_client::ClientError>(batch.info().batch_id.clone())
            })
        })
        .collect();
    let mut ids = Vec::new();
    for task in tasks {
        ids.push(
            task.await
                .expect("client task")
                .expect("client calls succeed"),
        );
    }
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), 8, "every batch has its own id");
    let info = server.client().await.server_info().await.expect("info");
    assert_eq!((info.batches, info.batch_envs), (0, 0), "all closed");
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn seeded_reset_noise_varies_envs_and_replays_by_seed() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client
        .create_batch(arm_batch(8).reset_noise(10.0))
        .await
        .expect("create a noisy batch");
    let first = batch
        .reset(Some(5))
        .await
        .expect("reset")
        .into_observations();
    let rows: Vec<&[f32]> = first.chunks_exact(11).collect();
    assert_ne!(bits(&rows[0][..2]), bits(&rows[1][..2]), "envs start apart");
    for row in &rows {
        assert!(
            row[0].abs() <= 10.0 && (-10.0..=0.0).contains(&row[1]),
            "{row:?}"
        );
        assert_eq!(&row[2..4], &[0.0, 0.0], "velocities start at zero");
    }
    let again = batch
        .reset(Some(5))
        .await
        .expect("reset")
        .into_observations();
    assert_eq!(
        bits(&first),
        bits(&again),
        "the same seed replays the starts"
    );
    let other = batch
        .reset(Some(6))
        .await
        .expect("reset")
        .into_observations();
    assert_ne!(bits(&first), bits(&other));
    batch.close().await.expect("close");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_partial_reset_reseeds_only_the_listed_envs() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client
        .create_batch(arm_batch(4).reset_noise(10.0))
        .await
        .expect("create a noisy batch");
    let start = batch
        .reset(Some(5))
        .await
        .expect("reset")
        .into_observations();
    batch
        .step(ActionType::Torque, &actions(4, 8, 1e-4))
        .await
        .expect("step");
    let moved = batch.observe().await.expect("observe").into_observations();
    let partial = batch
        .reset_envs(Some(5), 0, &[1, 3])
        .await
        .expect("partial reset")
        .into_observations();
    for env in 0..4 {
        let row = |v: &[f32]| bits(&v[env * 11..(env + 1) * 11]);
        let expected = if env % 2 == 1 { &start } else { &moved };
        assert_eq!(row(&partial), row(expected), "env {env}");
    }
    let err = batch
        .reset_envs(None, 0, &[2, 4])
        .await
        .expect_err("4 is out of range");
    assert_eq!(
        err.to_string(),
        "invalid argument: env_indices[1]: env 4 is out of range: the batch has 4 envs"
    );
    batch.close().await.expect("close");
}
