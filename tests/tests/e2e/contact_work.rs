//! Bounded contact work (`--max-contact-work`): issue O1's pile of 300 overlapping cubes is
//! refused at creation, a step over the limit fails with RESOURCE_EXHAUSTED and leaves its
//! env where it was, the flag raises the limit, and a Close that meets a running step is
//! honoured when the step ends.

use std::time::Duration;

use crate::exhausted;
use gymfleet_client::{with_deadline, ActionType, BatchOptions, ClientError, EnvOptions};
use gymfleet_e2e::TestServer;
use gymfleet_server::{ServerConfig, DEFAULT_MAX_CONTACT_WORK};
use serde_json::json;

/// Issue O1's document: `n` cubes of 2 mm, the default density, no joints, all at
/// (0, 0, 10) mm (the first one grounded, the others free and overlapping it).
fn cube_pile(n: usize) -> String {
    let instances: Vec<_> = (0..n)
        .map(|i| {
            json!({"part": "Cube", "name": format!("cube{i}"),
                   "position": {"x": 0, "y": 0, "z": 10}})
        })
        .collect();
    json!({
        "parts": [{"name": "Cube", "primitive": {"type": "cube", "size": {"x": 2, "y": 2, "z": 2}}}],
        "assembly": {"instances": instances, "joints": []}
    })
    .to_string()
}

/// A floor and a free 10 mm cube falling onto it from 20 mm.
fn falling_cube() -> String {
    json!({
        "parts": [
            {"name": "Floor", "primitive": {"type": "plane"}},
            {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 10, "y": 10, "z": 10}}}
        ],
        "assembly": {"instances": [
            {"part": "Floor", "name": "floor"},
            {"part": "Cube", "name": "cube", "position": {"x": -5, "y": -5, "z": 20}}
        ], "joints": []}
    })
    .to_string()
}

const PILE_REFUSED: &str = "document_json: where the document puts its bodies they touch in \
    44850 contact pairs with 179400 contact points, so its first step would be 897000 contact \
    point-substeps (179400 points × 5 substeps), over the server's limit of 100000 per env \
    step; move the bodies apart, use fewer substeps, or raise --max-contact-work \
    (GYMFLEET_MAX_CONTACT_WORK)";

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_pile_of_overlapping_cubes_is_refused_at_creation_naming_the_flag() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let info = client.server_info().await.expect("info");
    assert_eq!(
        info.limits.max_contact_work,
        DEFAULT_MAX_CONTACT_WORK as u64
    );
    assert_eq!(DEFAULT_MAX_CONTACT_WORK, 100_000, "PILE_REFUSED quotes it");
    let err = client
        .create_env(EnvOptions::new(cube_pile(300)))
        .await
        .unwrap_err();
    assert_eq!(exhausted(err), PILE_REFUSED);
    let err = client
        .create_batch(BatchOptions::new(cube_pile(300), 4))
        .await
        .unwrap_err();
    assert_eq!(exhausted(err), PILE_REFUSED);
    // Nothing was created, nothing is held.
    let info = client.server_info().await.expect("info");
    assert_eq!((info.envs, info.batches, info.batch_envs), (0, 0, 0));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_flag_raises_the_limit_for_a_single_env_and_a_batch() {
    let server = TestServer::start(ServerConfig {
        threads: 2,
        max_contact_work: 1_000_000,
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(cube_pile(300)))
        .await
        .expect("897 000 point-substeps are within 1 000 000");
    env.step(ActionType::Torque, &[]).await.expect("one step");
    env.close().await.expect("close");
    let batch = client
        .create_batch(BatchOptions::new(cube_pile(300), 2))
        .await
        .expect("a batch of it too");
    let step = batch.step(ActionType::Torque, &[]).await.expect("a step");
    assert_eq!(step.n_envs(), 2);
    batch.close().await.expect("close");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_step_over_the_limit_fails_and_leaves_the_env_where_it_was() {
    // The landing cube touches the floor in 4 points: 20 point-substeps, over 19.
    let server = TestServer::start(ServerConfig {
        threads: 1,
        max_contact_work: 19,
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(falling_cube()).max_steps(10_000))
        .await
        .expect("nothing touches at the start");
    let mut last = env.observe().await.expect("observe");
    let mut steps = 0;
    let err = loop {
        assert!(steps < 400, "the cube never landed");
        match env.step(ActionType::Torque, &[]).await {
            Ok(step) => last = step.observation,
            Err(err) => break err,
        }
        steps += 1;
    };
    let expected = "the step found 1 contact pairs with 4 contact points: 20 contact \
        point-substeps (4 points × 5 substeps), over the limit of 19 per env step; the env \
        was left where its last step left it (reset it, or set another state); the limit is \
        raised with --max-contact-work (GYMFLEET_MAX_CONTACT_WORK)";
    assert_eq!(exhausted(err), expected);
    // Where the last good step left it, and still open: the client holds it.
    assert_eq!(env.observe().await.expect("observe"), last);
    let again = env.step(ActionType::Torque, &[]).await.unwrap_err();
    assert_eq!(exhausted(again), expected);
    env.reset(None).await.expect("a reset is always possible");
    env.step(ActionType::Torque, &[])
        .await
        .expect("in the air again");

    // In a batch: the env over the limit (both, here) is left where it was, and the error
    // names it.
    let batch = client
        .create_batch(BatchOptions::new(falling_cube(), 2).max_steps(10_000))
        .await
        .expect("batch");
    for _ in 0..steps {
        batch
            .step(ActionType::Torque, &[0.0; 0])
            .await
            .expect("falling");
    }
    let before = batch.observe().await.expect("observe").into_observations();
    let err = batch.step(ActionType::Torque, &[]).await.unwrap_err();
    assert_eq!(
        exhausted(err),
        format!(
            "env 0: {}; the batch's other envs took their step (ObserveBatch reads them); \
             the limit is raised with --max-contact-work (GYMFLEET_MAX_CONTACT_WORK)",
            expected
                .split("; the limit is raised")
                .next()
                .expect("the env's part")
        )
    );
    assert_eq!(
        batch.observe().await.expect("observe").into_observations(),
        before
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_close_that_meets_a_running_step_is_honoured_when_the_step_ends() {
    // 500 overlapping cubes, no limit: a step of about a second in a debug build. Room for
    // one env: the next one fits only once the closed one's capacity is free.
    let server = TestServer::start(ServerConfig {
        threads: 1,
        max_envs: 1,
        max_contact_work: 0,
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(cube_pile(500)))
        .await
        .expect("env");
    let stepping = tokio::spawn({
        let env = env.clone();
        async move { env.step(ActionType::Torque, &[]).await }
    });
    tokio::time::sleep(Duration::from_millis(100)).await;
    // The Close waits for the step and its caller gives up first: the server still closes
    // the env once the step ends.
    let closed = with_deadline(Duration::from_millis(50), env.close()).await;
    assert!(
        matches!(closed, Err(ClientError::DeadlineExceeded { .. })),
        "the step was still running: {closed:?}"
    );
    // The client still held the env for the running step: that step ends normally.
    stepping
        .await
        .expect("task")
        .expect("the running step ends normally");
    let mut open = u64::MAX;
    for _ in 0..100 {
        open = client.server_info().await.expect("info").envs;
        if open == 0 {
            break;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    assert_eq!(open, 0, "the env the client closed is gone");
    assert!(matches!(
        env.observe().await,
        Err(ClientError::NotFound { .. })
    ));
    let mut next = None;
    for _ in 0..100 {
        match client.create_env(EnvOptions::new(falling_cube())).await {
            Ok(env) => {
                next = Some(env);
                break;
            }
            Err(ClientError::ResourceExhausted { .. }) => {
                tokio::time::sleep(Duration::from_millis(20)).await;
            }
            Err(other) => panic!("{other:?}"),
        }
    }
    assert!(next.is_some(), "the closed env's capacity was freed");
}
