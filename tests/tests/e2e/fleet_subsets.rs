//! Subset steps on a fleet (`FleetBatch::step_envs`): three servers step their listed envs
//! (a server with none listed is not called) and the rows equal one server's subset steps
//! bitwise; a server lost in a subset step is rebuilt from the checkpoint, the recovery
//! returns that step's result, and nothing is lost or stepped twice.

use gymfleet_client::{
    ActionType, Autoreset, BatchOptions, BatchStep, ClientError, Fleet, FleetEndpoints,
};
use gymfleet_e2e::ARM2;

use crate::fleet::server_with_threads;
use crate::{actions, bits};

const N: usize = 12;

fn options() -> BatchOptions {
    BatchOptions::new(ARM2, N)
        .end_effectors(["forearm"])
        .seed(11)
        .max_steps(5)
        .reset_noise(3.0)
        .autoreset(Autoreset::SameStep)
}

/// The `t`th group: changing, uneven, sometimes within one server's envs only.
fn group(t: usize) -> Vec<u32> {
    match t % 4 {
        0 => (0..N as u32).filter(|e| e % 3 != 1).collect(),
        1 => vec![1, 2],
        2 => (6..N as u32).collect(),
        _ => (0..N as u32).step_by(2).collect(),
    }
}

/// Step `t`'s group on the fleet and on the reference, compared; then the reference
/// mirrors a checkpoint the fleet took.
async fn step_both(
    batch: &mut gymfleet_client::FleetBatch,
    reference: &gymfleet_client::Batch,
    t: usize,
) {
    let envs = group(t);
    let acts = actions(t as u64, envs.len() * 2, 0.5);
    let got = batch
        .step_envs(ActionType::Torque, &envs, &acts)
        .await
        .expect("fleet step");
    let want = reference
        .step_envs(ActionType::Torque, &envs, &acts)
        .await
        .expect("step");
    assert_same(&got, &want, t);
    mirror_checkpoint(batch, reference).await;
}

/// The reference saves its states whenever the fleet took a checkpoint: a save re-seats
/// every env from its state, and the fleet's bitwise promise holds given the same
/// checkpoints.
async fn mirror_checkpoint(
    batch: &gymfleet_client::FleetBatch,
    reference: &gymfleet_client::Batch,
) {
    if batch
        .checkpoint_status()
        .is_some_and(|s| s.steps_since == 0)
    {
        reference
            .save_states(&[])
            .await
            .expect("the reference's save");
    }
}

#[track_caller]
fn assert_same(got: &BatchStep, want: &BatchStep, t: usize) {
    assert_eq!(got.env_indices(), want.env_indices(), "step {t}");
    assert_eq!(
        bits(got.observations()),
        bits(want.observations()),
        "step {t}"
    );
    assert_eq!(bits(got.rewards()), bits(want.rewards()), "step {t}");
    assert_eq!(got.truncated(), want.truncated(), "step {t}");
    assert_eq!(
        got.final_env_indices(),
        want.final_env_indices(),
        "step {t}"
    );
    for &e in got.env_indices() {
        let e = e as usize;
        assert_eq!(
            got.final_observation(e).map(bits),
            want.final_observation(e).map(bits)
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn fleet_subset_steps_equal_one_servers_and_survive_a_lost_server() {
    let mut servers = vec![
        server_with_threads(1).await,
        server_with_threads(2).await,
        server_with_threads(3).await,
    ];
    let reference_server = server_with_threads(1).await;
    let endpoints = FleetEndpoints::new(servers.iter().map(|s| s.addr().to_string()))
        .expect("distinct endpoints");
    let fleet = Fleet::connect(endpoints).await.expect("connect");
    let mut batch = fleet.create_batch(options()).await.expect("fleet batch");
    let reference = reference_server
        .client()
        .await
        .create_batch(options())
        .await
        .expect("reference");
    batch.checkpoint_every(6).await.expect("checkpoint");
    reference
        .save_states(&[])
        .await
        .expect("the reference's save");
    for t in 0..14 {
        step_both(&mut batch, &reference, t).await;
    }
    let err = batch
        .step_envs(ActionType::Torque, &[3, 3], &[0.0; 4])
        .await
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "invalid argument: env_indices[1]: expected ascending, distinct indices, got 3 after 3"
    );

    // The middle server goes; a subset step of its envs and one more finds it, and is
    // the recovery's result.
    let held = batch.placement()[1].envs.clone();
    let lost = servers.remove(1);
    lost.stop().await.expect("stop");
    let envs: Vec<u32> = (0..N as u32)
        .filter(|&e| held.contains(&(e as usize)) || e == 0)
        .collect();
    let acts = actions(14, envs.len() * 2, 0.5);
    let err = batch
        .step_envs(ActionType::Torque, &envs, &acts)
        .await
        .unwrap_err();
    assert!(matches!(err, ClientError::ServerLost { .. }), "{err:?}");
    let want = reference
        .step_envs(ActionType::Torque, &envs, &acts)
        .await
        .expect("step");
    let got = batch
        .recover(None)
        .await
        .expect("recovered")
        .expect("the interrupted step");
    assert_same(&got, &want, 14);
    mirror_checkpoint(&batch, &reference).await;
    for t in 15..24 {
        step_both(&mut batch, &reference, t).await;
    }
    // Whole steps and subset steps mix.
    let acts = actions(99, N * 2, 0.5);
    let got = batch.step(ActionType::Torque, &acts).await.expect("whole");
    let want = reference
        .step(ActionType::Torque, &acts)
        .await
        .expect("whole");
    assert_same(&got, &want, 99);
    batch.close().await.expect("close");
    for s in servers {
        s.stop().await.expect("stop");
    }
    reference_server.stop().await.expect("stop");
}
