//! Fleet sharding: three real servers on loopback with 1, 2 and 3 threads driven as one
//! by `gymfleet_client::Fleet`. Placement follows capacity, results equal a one-server
//! batch bitwise, a lost server is named with its envs, and the survivors go on.

use gymfleet_client::{
    ActionType, Autoreset, BatchOptions, BatchStep, ClientError, EnvOptions, Fleet, FleetBatch,
    FleetEndpoints,
};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};
use gymfleet_server::ServerConfig;

use crate::{actions, bits};

const N_ENVS: usize = 96;
const ACTION_DIM: usize = 2;

pub(crate) async fn server_with_threads(threads: usize) -> TestServer {
    TestServer::start(ServerConfig {
        threads,
        ..ServerConfig::default()
    })
    .await
}

/// Servers with 1, 2 and 3 threads.
async fn three_servers() -> Vec<TestServer> {
    let mut servers = Vec::new();
    for threads in 1..=3 {
        servers.push(server_with_threads(threads).await);
    }
    servers
}

async fn fleet_of(servers: &[TestServer]) -> Fleet {
    let endpoints = FleetEndpoints::new(servers.iter().map(|s| s.addr().to_string()))
        .expect("distinct endpoints");
    Fleet::connect(endpoints).await.expect("connect the fleet")
}

/// Arms that truncate every 4 steps and reset within the step, so that final
/// observations and flags cross shard boundaries.
fn arms(n_envs: usize) -> BatchOptions {
    BatchOptions::new(ARM2, n_envs)
        .end_effectors(["forearm"])
        .seed(11)
        .seed_offset(3)
        .max_steps(4)
        .autoreset(Autoreset::SameStep)
}

/// Asserts that row `row` of `fleet` is bitwise row `reference_row` of `reference`, with
/// the same reward, flags, final observation and termination reason.
#[track_caller]
fn assert_same_env(fleet: &BatchStep, row: usize, reference: &BatchStep, reference_row: usize) {
    let what = format!("fleet row {row} vs reference row {reference_row}");
    assert_eq!(
        bits(fleet.obs(row)),
        bits(reference.obs(reference_row)),
        "{what}"
    );
    assert_eq!(
        fleet.rewards()[row].to_bits(),
        reference.rewards()[reference_row].to_bits(),
        "{what}"
    );
    assert_eq!(
        fleet.terminated()[row],
        reference.terminated()[reference_row],
        "{what}"
    );
    assert_eq!(
        fleet.truncated()[row],
        reference.truncated()[reference_row],
        "{what}"
    );
    assert_eq!(
        fleet.final_observation(row).map(bits),
        reference.final_observation(reference_row).map(bits),
        "{what}"
    );
    assert_eq!(
        fleet.termination_reason(row),
        reference.termination_reason(reference_row),
        "{what}"
    );
}

/// The rows of the envs at `indices` (original indices) of a full-batch action vector.
fn rows_of(all: &[f32], indices: &[usize]) -> Vec<f32> {
    indices
        .iter()
        .flat_map(|&i| all[i * ACTION_DIM..(i + 1) * ACTION_DIM].iter().copied())
        .collect()
}

async fn batch_envs_per_server(servers: &[TestServer]) -> Vec<u64> {
    let mut held = Vec::new();
    for server in servers {
        let info = server.client().await.server_info().await.expect("info");
        held.push(info.batch_envs);
    }
    held
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_fleet_batch_is_split_by_threads_and_steps_like_one_server_bitwise() {
    let servers = three_servers().await;
    let reference_server = server_with_threads(2).await;
    let fleet = fleet_of(&servers).await;
    assert_eq!(fleet.servers().len(), 3);

    let mut batch = fleet.create_batch(arms(N_ENVS)).await.expect("fleet batch");
    let placement = batch.placement();
    let got: Vec<(String, std::ops::Range<usize>)> = placement
        .iter()
        .map(|p| (p.server.clone(), p.envs.clone()))
        .collect();
    let want: Vec<(String, std::ops::Range<usize>)> = vec![
        (servers[0].addr().to_string(), 0..16),
        (servers[1].addr().to_string(), 16..48),
        (servers[2].addr().to_string(), 48..96),
    ];
    assert_eq!(got, want, "96 envs over 1, 2 and 3 threads");
    assert!(placement.iter().all(|p| p.lost.is_none()));
    assert_eq!(batch_envs_per_server(&servers).await, [16, 32, 48]);
    let info = batch.info().clone();
    assert_eq!(
        (info.n_envs, info.action_dim, info.observation_dim),
        (N_ENVS, ACTION_DIM, 11)
    );
    assert_eq!(batch.env_indices(), (0..N_ENVS).collect::<Vec<_>>());
    for (shard, p) in batch.shards().zip(&placement) {
        assert_eq!(shard.server(), p.server);
        assert_eq!(shard.id(), p.batch_id);
    }

    let reference_client = reference_server.client().await;
    let reference = reference_client
        .create_batch(arms(N_ENVS))
        .await
        .expect("reference batch");

    let fleet_reset = batch.reset(Some(5)).await.expect("fleet reset");
    let reference_reset = reference.reset(Some(5)).await.expect("reference reset");
    assert_eq!(
        bits(fleet_reset.observations()),
        bits(reference_reset.observations())
    );

    let (mut truncations, mut finals) = (0, 0);
    for k in 0..10u64 {
        let acts = actions(k, N_ENVS * ACTION_DIM, 0.5);
        let from_fleet = batch.step(ActionType::Torque, &acts).await.expect("step");
        let from_one = reference
            .step(ActionType::Torque, &acts)
            .await
            .expect("reference step");
        assert_eq!(from_fleet.n_envs(), N_ENVS);
        assert_eq!(from_fleet.step_index(), from_one.step_index());
        assert_eq!(from_fleet.final_env_indices(), from_one.final_env_indices());
        for env in 0..N_ENVS {
            assert_same_env(&from_fleet, env, &from_one, env);
        }
        truncations += from_fleet.truncated().iter().filter(|t| **t).count();
        finals += from_fleet.final_env_indices().len();
    }
    assert!(
        truncations >= N_ENVS && finals >= N_ENVS,
        "episodes ended and were reset across shards: {truncations} truncations, {finals} final observations"
    );
    let observed = batch.observe().await.expect("observe");
    let reference_observed = reference.observe().await.expect("reference observe");
    assert_eq!(
        bits(observed.observations()),
        bits(reference_observed.observations())
    );

    // Wrong lengths and non-finite actions are refused before any shard steps.
    let err = batch.step(ActionType::Torque, &[0.0; 3]).await.unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    let mut bad = vec![0.0; N_ENVS * ACTION_DIM];
    bad[2 * 50 + 1] = f32::NAN;
    let err = batch.step(ActionType::Torque, &bad).await.unwrap_err();
    assert_eq!(
        err.message(),
        "actions[101] (env 50, value 1): expected a finite number, got NaN",
        "the server's wording, with the fleet's env index"
    );
    let after = batch.observe().await.expect("observe");
    assert_eq!(bits(after.observations()), bits(observed.observations()));

    // Single envs go to the least-loaded server: 16 envs per thread everywhere, so the
    // first, then the second (17/1 > 32/2).
    let env = fleet
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await
        .expect("fleet env");
    assert_eq!(env.server(), servers[0].addr().to_string());
    let second = fleet
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await
        .expect("second fleet env");
    assert_eq!(second.server(), servers[1].addr().to_string());
    let step = env
        .step(ActionType::Torque, &[1.0])
        .await
        .expect("env step");
    assert!(step.observation.joint_positions[0] > 0.0);

    batch.close().await.expect("close the fleet batch");
    assert_eq!(batch_envs_per_server(&servers).await, [0, 0, 0]);
    reference.close().await.expect("close");
    for server in servers {
        server.stop().await.expect("clean shutdown");
    }
    reference_server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_lost_server_is_named_with_its_envs_and_the_survivors_step_on() {
    let mut servers = three_servers().await;
    let reference_server = server_with_threads(1).await;
    let fleet = fleet_of(&servers).await;
    let mut batch = fleet.create_batch(arms(N_ENVS)).await.expect("fleet batch");
    let mut small = fleet.create_batch(arms(6)).await.expect("second batch");
    assert_eq!(
        small
            .placement()
            .iter()
            .map(|p| p.envs.clone())
            .collect::<Vec<_>>(),
        [0..1, 1..3, 3..6]
    );
    let reference = reference_server
        .client()
        .await
        .create_batch(arms(N_ENVS))
        .await
        .expect("reference batch");

    let acts = actions(1, N_ENVS * ACTION_DIM, 0.5);
    let before = batch.step(ActionType::Torque, &acts).await.expect("step");
    let reference_before = reference
        .step(ActionType::Torque, &acts)
        .await
        .expect("step");
    for env in 0..N_ENVS {
        assert_same_env(&before, env, &reference_before, env);
    }

    // The middle server goes away mid-run.
    let lost = servers.remove(1);
    let lost_addr = lost.addr().to_string();
    lost.stop().await.expect("clean shutdown");

    let err = batch.step(ActionType::Torque, &acts).await.unwrap_err();
    match &err {
        ClientError::ServerLost { server, envs, .. } => {
            assert_eq!(server, &lost_addr);
            assert_eq!(envs.len(), 1, "{envs:?}");
            assert_eq!(envs[0], 16..48);
        }
        other => panic!("expected ServerLost, got {other:?}"),
    }
    let text = err.to_string();
    assert!(
        text.starts_with(&format!("server {lost_addr} failed (")),
        "{text}"
    );
    assert!(text.ends_with("lost envs 16..48 of fleet batch"), "{text}");
    // Until the caller drops them, every call says so again.
    let again = batch.observe().await.unwrap_err();
    assert!(matches!(again, ClientError::ServerLost { .. }), "{again:?}");
    let lost_shard = &batch.placement()[1];
    assert_eq!(lost_shard.server, lost_addr);
    assert!(lost_shard.lost.is_some());

    // Other fleet batches with envs there learn it too; new ones cannot be created.
    let small_err = small
        .step(ActionType::Torque, &[0.0; 12])
        .await
        .unwrap_err();
    assert!(
        matches!(&small_err, ClientError::ServerLost { server, envs, .. }
            if *server == lost_addr && envs.len() == 1 && envs[0] == (1..3)),
        "{small_err:?}"
    );
    let create_err = fleet.create_batch(arms(8)).await.unwrap_err();
    assert!(
        matches!(&create_err, ClientError::OnServer { server, .. } if *server == lost_addr),
        "{create_err:?}"
    );
    assert_eq!(create_err.server(), Some(lost_addr.as_str()));

    // The survivors go on, with their original indices, as on one server. They took
    // the step that found the loss: its result is kept for them.
    assert_eq!(batch.drop_lost(), (16..48).collect::<Vec<_>>());
    let survivors: Vec<usize> = (0..16).chain(48..96).collect();
    let interrupted = batch
        .take_interrupted_step()
        .expect("the survivors' result of the interrupted step");
    assert!(batch.take_interrupted_step().is_none());
    let reference_interrupted = reference
        .step(ActionType::Torque, &acts)
        .await
        .expect("reference step");
    assert_eq!(interrupted.n_envs(), 64);
    for (row, &env) in survivors.iter().enumerate() {
        assert_same_env(&interrupted, row, &reference_interrupted, env);
    }
    assert_eq!(batch.env_indices(), survivors);
    assert_eq!(batch.n_envs(), 64);
    assert_eq!(batch.info().n_envs, 64);
    assert_eq!(batch.placement().len(), 2);
    assert!(batch.drop_lost().is_empty());
    for k in 2..5u64 {
        let all = actions(k, N_ENVS * ACTION_DIM, 0.5);
        let from_fleet = batch
            .step(ActionType::Torque, &rows_of(&all, &survivors))
            .await
            .expect("survivors step");
        let from_one = reference
            .step(ActionType::Torque, &all)
            .await
            .expect("reference step");
        assert_eq!(from_fleet.n_envs(), 64);
        for (row, &env) in survivors.iter().enumerate() {
            assert_same_env(&from_fleet, row, &from_one, env);
        }
    }
    assert_eq!(small.drop_lost(), [1, 2]);
    let step = small
        .step(ActionType::Torque, &[0.0; 8])
        .await
        .expect("the small batch's survivors step");
    assert_eq!(step.n_envs(), 4);

    // Single envs avoid the lost server.
    let env = fleet
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await
        .expect("an env on a live server");
    assert_ne!(env.server(), lost_addr);

    batch.close().await.expect("close survivors");
    small.close().await.expect("close survivors");
    for server in servers {
        server.stop().await.expect("clean shutdown");
    }
    reference_server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_refused_shard_leaves_no_other_shard_behind() {
    let open = server_with_threads(1).await;
    let refusing = TestServer::start(ServerConfig {
        threads: 1,
        max_document_bytes: 64,
        ..ServerConfig::default()
    })
    .await;
    let servers = [open, refusing];
    let fleet = fleet_of(&servers).await;
    let err = fleet.create_batch(arms(8)).await.unwrap_err();
    let refusing_addr = servers[1].addr().to_string();
    assert!(
        matches!(&err, ClientError::OnServer { server, .. } if *server == refusing_addr),
        "{err:?}"
    );
    let info = servers[0].client().await.server_info().await.expect("info");
    assert_eq!(
        (info.batches, info.batch_envs),
        (0, 0),
        "the shard on the open server was closed"
    );

    // A fleet with an unreachable member does not connect, and says which.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let dead = listener.local_addr().expect("addr").to_string();
    drop(listener);
    let endpoints =
        FleetEndpoints::new([servers[0].addr().to_string(), dead.clone()]).expect("endpoints");
    let err = Fleet::connect(endpoints).await.unwrap_err();
    assert_eq!(err.server(), Some(dead.as_str()), "{err:?}");

    let [open, refusing] = servers;
    open.stop().await.expect("clean shutdown");
    refusing.stop().await.expect("clean shutdown");
}

/// A `FleetBatch` is usable where the caller holds it mutably across awaits.
#[allow(dead_code)]
fn fleet_batches_are_send(batch: FleetBatch) -> impl Send {
    batch
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_partitioned_server_is_reported_lost_within_seconds_not_awaited_forever() {
    use std::time::Duration;

    use gymfleet_client::Client;
    use gymfleet_e2e::PartitionableProxy;

    let near = server_with_threads(1).await;
    let far = server_with_threads(1).await;
    let proxy = PartitionableProxy::start(far.addr()).await;
    let endpoints =
        FleetEndpoints::new([near.addr().to_string(), proxy.addr().to_string()]).unwrap();
    // Without keepalive (`.keepalive(None)`) the step below waits forever.
    let settings =
        Client::builder("").keepalive(Some((Duration::from_millis(300), Duration::from_secs(1))));
    let fleet = Fleet::connect_with(endpoints, &settings)
        .await
        .expect("connect the fleet");
    let mut batch = fleet.create_batch(arms(8)).await.expect("fleet batch");
    let acts = actions(3, 8 * ACTION_DIM, 0.5);
    batch.step(ActionType::Torque, &acts).await.expect("step");

    // The far server's network goes silent: no reset, no close.
    proxy.partition();
    // The timeout only guards against a hang (without keepalive the step never ends). What
    // ends the step is keepalive's missed ping, about 1.3 s in, failing the connection: the
    // error is the connection's, not a timeout's.
    let err = tokio::time::timeout(
        Duration::from_secs(60),
        batch.step(ActionType::Torque, &acts),
    )
    .await
    .expect("the step ends instead of hanging")
    .unwrap_err();
    match &err {
        ClientError::ServerLost {
            server,
            envs,
            reason,
        } => {
            // The connection failed (HTTP/2's keepalive closed it), not a deadline.
            assert_eq!(reason, "unavailable: http2 error", "{err:?}");
            assert_eq!(server, &proxy.addr().to_string());
            assert_eq!(envs.len(), 1, "{envs:?}");
            assert_eq!(envs[0], 4..8);
        }
        other => panic!("expected ServerLost, got {other:?}"),
    }
    // The near server's half goes on.
    assert_eq!(batch.drop_lost(), (4..8).collect::<Vec<_>>());
    batch
        .step(ActionType::Torque, &acts[..4 * ACTION_DIM])
        .await
        .expect("the survivors step on");
    near.stop().await.expect("clean shutdown");
    drop(proxy);
    far.stop().await.expect("clean shutdown");
}

/// A fleet batch that checkpoints every 10 steps loses its middle server mid-run;
/// `recover` rebuilds those envs on the survivors from the checkpoint, replays the steps
/// and the partial reset since, returns the whole result of the step that found the loss,
/// and the batch goes on bitwise like a one-server batch that lost nothing.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_lost_server_is_recovered_from_a_checkpoint_bitwise() {
    const N: usize = 12;
    let mut servers = three_servers().await;
    let reference_server = server_with_threads(1).await;
    let fleet = fleet_of(&servers).await;
    let options = || arms(N).max_steps(7).reset_noise(3.0);
    let mut batch = fleet.create_batch(options()).await.expect("fleet batch");
    let reference = reference_server
        .client()
        .await
        .create_batch(options())
        .await
        .expect("reference batch");
    let lost_envs = batch.placement()[1].envs.clone();
    assert!(!lost_envs.is_empty(), "{:?}", batch.placement());

    let err = batch.recover(None).await.unwrap_err();
    assert!(matches!(err, ClientError::Fleet { .. }), "{err:?}");
    assert!(
        err.to_string().contains("call checkpoint_every first"),
        "{err}"
    );
    batch.checkpoint_every(10).await.expect("first checkpoint");

    for t in 0..24 {
        if t == 22 {
            // A partial reset between checkpoints: it is replayed too.
            let fleet_obs = batch
                .reset_envs(Some(5), 0, Some(&[2, 7]))
                .await
                .expect("reset");
            let reference_obs = reference
                .reset_envs(Some(5), 0, &[2, 7])
                .await
                .expect("reset");
            assert_eq!(
                bits(fleet_obs.observations()),
                bits(reference_obs.observations())
            );
        }
        let acts = actions(t as u64, N * ACTION_DIM, 0.5);
        let got = batch.step(ActionType::Torque, &acts).await.expect("step");
        let want = reference
            .step(ActionType::Torque, &acts)
            .await
            .expect("step");
        for env in 0..N {
            assert_same_env(&got, env, &want, env);
        }
    }
    let status = batch.checkpoint_status().expect("checkpointing");
    assert_eq!((status.every, status.steps_since), (10, 4));
    assert!(status.bytes > N * 1000, "{status:?}");

    // The middle server goes away; the step that finds it fails for its envs only.
    let lost = servers.remove(1);
    lost.stop().await.expect("clean shutdown");
    let acts = actions(24, N * ACTION_DIM, 0.5);
    let err = batch.step(ActionType::Torque, &acts).await.unwrap_err();
    assert!(matches!(err, ClientError::ServerLost { .. }), "{err:?}");
    let want = reference
        .step(ActionType::Torque, &acts)
        .await
        .expect("step");

    let got = batch
        .recover(None)
        .await
        .expect("recovered on the survivors")
        .expect("the interrupted step's result");
    for env in 0..N {
        assert_same_env(&got, env, &want, env);
    }
    let placement = batch.placement();
    assert!(placement.iter().all(|p| p.lost.is_none()), "{placement:?}");
    assert_eq!(placement[1].envs, lost_envs);
    assert!(
        servers
            .iter()
            .any(|s| s.addr().to_string() == placement[1].server),
        "rebuilt on a survivor: {placement:?}"
    );
    for t in 25..45 {
        let acts = actions(t, N * ACTION_DIM, 0.5);
        let got = batch.step(ActionType::Torque, &acts).await.expect("step");
        let want = reference
            .step(ActionType::Torque, &acts)
            .await
            .expect("step");
        for env in 0..N {
            assert_same_env(&got, env, &want, env);
        }
    }
    batch.close().await.expect("close");
    for server in servers {
        server.stop().await.expect("clean shutdown");
    }
    reference_server.stop().await.expect("clean shutdown");
}

/// Recovery onto a replacement server: both original servers' envs stay where they were
/// but the lost one's, which move to the new server, and the run matches one server's.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_lost_server_is_recovered_onto_a_replacement() {
    const N: usize = 6;
    let mut servers = vec![server_with_threads(1).await, server_with_threads(1).await];
    let reference_server = server_with_threads(1).await;
    let fleet = fleet_of(&servers).await;
    let options = || arms(N).max_steps(5).reset_noise(2.0);
    let mut batch = fleet.create_batch(options()).await.expect("fleet batch");
    let reference = reference_server
        .client()
        .await
        .create_batch(options())
        .await
        .expect("reference batch");
    batch.checkpoint_every(4).await.expect("checkpoint");
    for t in 0..7 {
        let acts = actions(t, N * ACTION_DIM, 0.5);
        batch.step(ActionType::Torque, &acts).await.expect("step");
        reference
            .step(ActionType::Torque, &acts)
            .await
            .expect("step");
    }
    servers
        .pop()
        .expect("two")
        .stop()
        .await
        .expect("clean shutdown");
    // Found by an observation this time, not by a step: nothing to hand back.
    let err = batch.observe().await.unwrap_err();
    assert!(matches!(err, ClientError::ServerLost { .. }), "{err:?}");
    let replacement = server_with_threads(1).await;
    let client = replacement.client().await;
    assert!(batch
        .recover(Some(&client))
        .await
        .expect("recovered")
        .is_none());
    let placement = batch.placement();
    assert_eq!(placement[1].server, replacement.addr().to_string());
    assert_eq!(placement[0].server, servers[0].addr().to_string());
    for t in 7..20 {
        let acts = actions(t, N * ACTION_DIM, 0.5);
        let got = batch.step(ActionType::Torque, &acts).await.expect("step");
        let want = reference
            .step(ActionType::Torque, &acts)
            .await
            .expect("step");
        for env in 0..N {
            assert_same_env(&got, env, &want, env);
        }
    }
    batch.close().await.expect("close");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn one_servers_batch_as_a_fleet_batch_steps_alike_and_keeps_the_servers_errors() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let options = BatchOptions::new(ARM2, 3)
        .end_effectors(["forearm"])
        .autoreset(Autoreset::SameStep)
        .max_steps(25)
        .seed(5);
    let reference = client.create_batch(options.clone()).await.expect("batch");
    let batch = client.create_batch(options).await.expect("batch");
    let id = batch.id().to_string();
    let mut one = FleetBatch::from(batch);
    assert_eq!(one.info().batch_id, id, "one shard: the server's own id");
    assert_eq!(one.placement().len(), 1);
    for t in 0..40 {
        let action = actions(t, 3 * ACTION_DIM, 0.05);
        let a = one.step(ActionType::Torque, &action).await.expect("step");
        let b = reference
            .step(ActionType::Torque, &action)
            .await
            .expect("step");
        assert_eq!(bits(a.observations()), bits(b.observations()), "step {t}");
        assert_eq!(bits(a.rewards()), bits(b.rewards()));
        assert_eq!(a.final_env_indices(), b.final_env_indices());
    }
    let (a, b) = (one.reset(Some(9)).await, reference.reset(Some(9)).await);
    assert_eq!(
        bits(a.expect("reset").observations()),
        bits(b.expect("reset").observations())
    );

    // Refusals are the server's own, unwrapped.
    let err = one.step(ActionType::Torque, &[0.0; 5]).await.unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_eq!(
        err.message(),
        "actions: expected 6 values (3 envs × 2 DOF), got 5"
    );
    let mut bad = vec![0.0; 3 * ACTION_DIM];
    bad[3] = f32::INFINITY;
    let err = one.step(ActionType::Torque, &bad).await.unwrap_err();
    assert_eq!(
        err.message(),
        "actions[3] (env 1, value 1): expected a finite number, got inf"
    );
    // A batch its server no longer holds is NOT_FOUND, as for the batch itself, not a
    // lost server.
    one.close().await.expect("close");
    let err = one.observe().await.unwrap_err();
    assert!(matches!(err, ClientError::NotFound { .. }), "{err:?}");
    let err = reference
        .step(ActionType::Torque, &[0.0; 5])
        .await
        .unwrap_err();
    assert!(
        err.message().starts_with("actions: expected 6 values"),
        "{err}"
    );
}
