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
