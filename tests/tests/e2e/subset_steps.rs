//! Stepping some envs of a batch over the network (`StepBatchRequest.env_indices`, what an
//! asynchronous trainer sends): unary and on a stream, each env's rows are those a
//! whole-batch step gives it, bit for bit, through same-step autoresets; a bad list is
//! INVALID_ARGUMENT and steps nothing.

use gymfleet_client::{ActionType, Autoreset, BatchOptions, ClientError};
use gymfleet_e2e::{TestServer, ARM2};

use crate::{assert_mentions, bits};

const N: usize = 5;
const STEPS: usize = 8;

fn options() -> BatchOptions {
    BatchOptions::new(ARM2, N)
        .end_effectors(["forearm"])
        .seed(3)
        .reset_noise(15.0)
        .max_steps(3)
        .autoreset(Autoreset::SameStep)
}

fn action(e: usize, k: usize) -> [f32; 2] {
    let x = (e * 5 + k * 3) as f32;
    [2e-3 * x.sin(), -2e-3 * x.cos()]
}

/// Env `e`'s row, reward and final row (if it finished) at one of its steps, as bits.
type Seen = (Vec<u32>, u32, Option<Vec<u32>>);

fn seen(step: &gymfleet_client::BatchStep, row: usize, env: usize) -> Seen {
    (
        bits(step.obs(row)),
        step.rewards()[row].to_bits(),
        step.final_observation(env).map(bits),
    )
}

/// The groups of the `round`th subset step: uneven, changing, ascending.
fn group(round: usize, done: &[usize]) -> Vec<u32> {
    (0..N)
        .filter(|&e| done[e] < STEPS && !(e * 2 + round).is_multiple_of(3))
        .map(|e| e as u32)
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn subsets_step_each_env_as_whole_steps_do_unary_and_streamed() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let whole = client.create_batch(options()).await.expect("create");
    whole.reset(Some(3)).await.expect("reset");
    let mut want: Vec<Vec<Seen>> = vec![Vec::new(); N];
    for k in 0..STEPS {
        let actions: Vec<f32> = (0..N).flat_map(|e| action(e, k)).collect();
        let step = whole
            .step(ActionType::Torque, &actions)
            .await
            .expect("step");
        assert!(step.env_indices().is_empty());
        for (e, seen_by) in want.iter_mut().enumerate() {
            seen_by.push(seen(&step, e, e));
        }
    }
    assert!(
        want.iter().flatten().any(|s| s.2.is_some()),
        "episodes ended"
    );

    for streamed in [false, true] {
        let batch = client.create_batch(options()).await.expect("create");
        batch.reset(Some(3)).await.expect("reset");
        let mut stream = batch.stream_with_window(2).await.expect("stream");
        let mut got: Vec<Vec<Seen>> = vec![Vec::new(); N];
        let mut done = vec![0; N];
        let mut round = 0;
        while done.iter().any(|&d| d < STEPS) {
            let envs = group(round, &done);
            round += 1;
            if envs.is_empty() {
                continue;
            }
            let actions: Vec<f32> = envs
                .iter()
                .flat_map(|&e| action(e as usize, done[e as usize]))
                .collect();
            let step = if streamed {
                stream
                    .send_envs(ActionType::Torque, &envs, &actions)
                    .await
                    .expect("send");
                stream.next().await.expect("a result").expect("stepped")
            } else {
                batch
                    .step_envs(ActionType::Torque, &envs, &actions)
                    .await
                    .expect("step")
            };
            assert_eq!(step.env_indices(), &envs[..]);
            assert_eq!(step.n_envs(), envs.len());
            for (row, &e) in envs.iter().enumerate() {
                got[e as usize].push(seen(&step, row, e as usize));
                done[e as usize] += 1;
            }
        }
        assert_eq!(got, want, "streamed: {streamed}");
        stream.finish().await.expect("finish");
        batch.close().await.expect("close");
    }
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_bad_subset_is_invalid_argument_and_steps_nothing() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client.create_batch(options()).await.expect("create");
    let before = batch.reset(Some(3)).await.expect("reset");
    for (envs, actions, needles) in [
        (
            vec![9],
            vec![0.0; 2],
            ["env_indices[0]: env 9 is out of range: the batch has 5 envs"],
        ),
        (
            vec![2, 1],
            vec![0.0; 4],
            ["env_indices[1]: expected ascending, distinct indices, got 1 after 2"],
        ),
        (
            vec![0, 3],
            vec![0.0; 2],
            ["actions: expected 4 values (2 envs × 2 DOF), got 2"],
        ),
    ] {
        let err = batch
            .step_envs(ActionType::Torque, &envs, &actions)
            .await
            .expect_err("refused");
        assert!(
            matches!(err, ClientError::InvalidArgument { .. }),
            "{err:?}"
        );
        assert_mentions(&err, &needles);
    }
    let after = batch.observe().await.expect("observe");
    assert_eq!(bits(after.observations()), bits(before.observations()));
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stream_steps_nothing_after_a_failed_step_and_keeps_the_results_before_it() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client.create_batch(options()).await.expect("create");
    batch.reset(Some(3)).await.expect("reset");
    let mut stream = batch.stream_with_window(4).await.expect("stream");
    let good: Vec<f32> = [action(0, 0), action(1, 0)].concat();
    stream
        .send_envs(ActionType::Torque, &[0, 1], &good)
        .await
        .expect("send a good step");
    stream
        .send_envs(ActionType::Torque, &[2], &[f32::NAN, 0.0])
        .await
        .expect("send a bad step");
    // Behind the bad one, possibly before the server read it: not stepped either way.
    let behind = stream
        .send_envs(ActionType::Torque, &[3, 4], &[0.1; 4])
        .await;
    let first = stream
        .next()
        .await
        .expect("a result")
        .expect("the good step");
    assert_eq!(first.env_indices(), &[0, 1]);
    let err = stream
        .next()
        .await
        .expect("a result")
        .expect_err("the bad step");
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_mentions(&err, &["expected a finite number"]);
    if let Err(err) = behind {
        assert_mentions(
            &err,
            &["the batch stream has ended", "this step was not sent"],
        );
    }
    let refused = stream
        .send_envs(ActionType::Torque, &[3], &[0.0; 2])
        .await
        .expect_err("the stream has ended");
    assert_mentions(&refused, &["the batch stream has ended"]);
    // Envs 0 and 1 stepped once; 2, 3 and 4 did not move.
    let now = batch.observe().await.expect("observe");
    for e in 0..2 {
        assert_eq!(bits(now.obs(e)), bits(first.obs(e)), "env {e}");
    }
    let unary = client.create_batch(options()).await.expect("create");
    let start = unary.reset(Some(3)).await.expect("reset");
    for e in 2..N {
        assert_eq!(bits(now.obs(e)), bits(start.obs(e)), "env {e} did not step");
    }
    server.stop().await.expect("clean shutdown");
}
