//! Saved states over the network: save on one server, load or fork on another, and the
//! continuation is bitwise the original's; bad states are refused with their reason.

use gymfleet_client::{
    ActionType, Autoreset, BatchOptions, ClientError, EnvOptions, EnvState, ReachTask, Task,
};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};
use gymfleet_server::ServerConfig;

use crate::{actions, assert_mentions, assert_not_found, bits};

/// arm2 with a reach task whose target is drawn per episode, reset noise and short
/// episodes: the state must carry the generator, the target and the episode count.
fn arm2() -> EnvOptions {
    EnvOptions::new(ARM2)
        .end_effectors(["forearm"])
        .seed(5)
        .max_steps(30)
        .reset_noise(4.0)
        .task(Task::from(ReachTask {
            end_effector: "forearm".into(),
            target_box: Some(([15.0, 0.0, 30.0], [30.0, 0.0, 45.0])),
            ..ReachTask::default()
        }))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_state_forks_and_loads_on_another_server_and_continues_bitwise() {
    let (a, b) = (
        TestServer::start_default().await,
        TestServer::start_default().await,
    );
    let (ca, cb) = (a.client().await, b.client().await);
    let env = ca.create_env(arm2()).await.expect("create");
    let layout = env.info().observation_layout.clone();
    for t in 0..20 {
        env.step(ActionType::Torque, &actions(t, 2, 0.05))
            .await
            .expect("step");
    }
    let state = env.save_state().await.expect("save");

    // Three copies on the other server, and an env of other seed loaded with the state.
    let fork = cb.fork(&state, 3, Autoreset::SameStep).await.expect("fork");
    assert_eq!((fork.info().n_envs, fork.info().action_dim), (3, 2));
    let other = cb.create_env(arm2().seed(77)).await.expect("create");
    let loaded = other.load_state(&state).await.expect("load");
    assert_eq!(
        bits(&loaded.to_flat(&layout)),
        bits(&env.observe().await.expect("observe").to_flat(&layout))
    );

    // 40 steps: past the episode's end at 30, so resets draw from the carried generator.
    for t in 20..60 {
        let action = actions(t, 2, 0.05);
        let mut original = env.step(ActionType::Torque, &action).await.expect("step");
        let same = other.step(ActionType::Torque, &action).await.expect("step");
        let copies: Vec<f32> = action.iter().cycle().take(6).copied().collect();
        let forked = fork.step(ActionType::Torque, &copies).await.expect("step");
        assert_eq!(
            bits(&same.observation.to_flat(&layout)),
            bits(&original.observation.to_flat(&layout))
        );
        for i in 0..3 {
            // The fork autoresets in the step; the single envs are reset by hand.
            let row = forked.final_observation(i).unwrap_or(forked.obs(i));
            assert_eq!(
                bits(row),
                bits(&original.observation.to_flat(&layout)),
                "copy {i}, step {t}"
            );
        }
        if original.done {
            let first = env.reset(None).await.expect("reset");
            other.reset(None).await.expect("reset");
            for i in 0..3 {
                assert_eq!(
                    bits(forked.obs(i)),
                    bits(&first.to_flat(&layout)),
                    "copy {i} reset"
                );
            }
            original.observation = first;
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn some_envs_of_a_batch_save_and_load() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client
        .create_batch(BatchOptions::from_env(arm2(), 4))
        .await
        .expect("batch");
    for t in 0..10 {
        batch
            .step(ActionType::Torque, &actions(t, 8, 0.05))
            .await
            .expect("step");
    }
    let states = batch.save_states(&[0, 2]).await.expect("save");
    assert_eq!(states.len(), 2);
    let at_save = batch.observe().await.expect("observe");
    for t in 10..15 {
        batch
            .step(ActionType::Torque, &actions(t, 8, 0.05))
            .await
            .expect("step");
    }
    // Crosswise: env 1 gets env 2's state, env 3 env 0's.
    let obs = batch
        .load_states(&[1, 3], &[states[1].clone(), states[0].clone()])
        .await
        .expect("load");
    assert_eq!(bits(obs.obs(1)), bits(at_save.obs(2)));
    assert_eq!(bits(obs.obs(3)), bits(at_save.obs(0)));
    // Every env at once.
    let all = batch.save_states(&[]).await.expect("save all");
    assert_eq!(all.len(), 4);
    batch.load_states(&[], &all).await.expect("load all");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_states_are_refused_with_their_reason() {
    let server = TestServer::start(ServerConfig {
        max_batch_size: 8,
        max_envs: 10,
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let env = client.create_env(arm2()).await.expect("create");
    let state = env.save_state().await.expect("save");

    let garbage = EnvState::from_bytes(b"{\"not\": \"a state\"}".to_vec());
    let err = env.load_state(&garbage).await.unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_eq!(
        err.message(),
        "state: not a gymfleet env state: it starts with [7b, 22, 6e, 6f], not \"GFST\""
    );
    let mut corrupt = state.as_bytes().to_vec();
    let last = corrupt.len() - 1;
    corrupt[last] ^= 1;
    let err = env
        .load_state(&EnvState::from_bytes(corrupt))
        .await
        .unwrap_err();
    assert_mentions(
        &err,
        &["state: checksum mismatch", "corrupted or truncated"],
    );
    let truncated = EnvState::from_bytes(state.as_bytes()[..40].to_vec());
    assert_mentions(
        &env.load_state(&truncated).await.unwrap_err(),
        &["state: checksum mismatch"],
    );

    let pendulum = client
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await
        .expect("create");
    let err = pendulum.load_state(&state).await.unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_eq!(
        err.message(),
        "state.document: the state was saved from an env of another document"
    );
    let err = client
        .create_env(arm2().substeps(7))
        .await
        .expect("create")
        .load_state(&state)
        .await
        .unwrap_err();
    assert_eq!(
        err.message(),
        "state.config.substeps: the state was saved from an env with another substeps"
    );

    let err = client
        .fork(&state, 0, Autoreset::Disabled)
        .await
        .unwrap_err();
    assert_eq!(
        err.message(),
        "n_envs: expected at least 1 environment, got 0"
    );
    let err = client
        .fork(&state, 9, Autoreset::Disabled)
        .await
        .unwrap_err();
    assert!(
        matches!(err, ClientError::ResourceExhausted { .. }),
        "{err:?}"
    );
    assert_mentions(&err, &["--max-batch-size"]);
    let err = client
        .fork(&garbage, 2, Autoreset::Disabled)
        .await
        .unwrap_err();
    assert_mentions(&err, &["not a gymfleet env state"]);
    let err = client
        .fork(&state, 8, Autoreset::Disabled)
        .await
        .unwrap_err();
    assert!(
        matches!(err, ClientError::ResourceExhausted { .. }),
        "{err:?}"
    );
    assert_mentions(&err, &["--max-envs"]);

    env.close().await.expect("close");
    assert_not_found(&env.save_state().await.unwrap_err(), &["sim_"]);
    assert_not_found(&env.load_state(&state).await.unwrap_err(), &["sim_"]);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn server_limits_apply_to_a_states_document_and_a_batchs_states() {
    let roomy = TestServer::start_default().await;
    let state = roomy
        .client()
        .await
        .create_env(arm2())
        .await
        .expect("create")
        .save_state()
        .await
        .expect("save");
    let strict = TestServer::start(ServerConfig {
        max_document_bytes: 100,
        ..ServerConfig::default()
    })
    .await;
    let err = strict
        .client()
        .await
        .fork(&state, 1, Autoreset::Disabled)
        .await
        .unwrap_err();
    assert!(
        matches!(err, ClientError::ResourceExhausted { .. }),
        "{err:?}"
    );
    assert_mentions(
        &err,
        &[
            "state.document: ",
            "bytes exceeds the server's limit of 100 bytes",
        ],
    );

    // States of 60 arm2 envs (1.3 kB each: each carries the document) are more than 64 KiB.
    let small = TestServer::start(ServerConfig {
        max_message_bytes: 64 * 1024,
        ..ServerConfig::default()
    })
    .await;
    let client = small.client().await;
    let batch = client
        .create_batch(BatchOptions::from_env(arm2(), 60))
        .await
        .expect("batch");
    let err = batch.save_states(&[]).await.unwrap_err();
    assert!(
        matches!(err, ClientError::ResourceExhausted { .. }),
        "{err:?}"
    );
    assert_mentions(
        &err,
        &["env_indices: the 60 states come to", "--max-message-bytes"],
    );
    assert_eq!(batch.save_states(&[0, 1]).await.expect("two fit").len(), 2);
}
