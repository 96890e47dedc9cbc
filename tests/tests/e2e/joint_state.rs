//! MuJoCo-shaped state access over the network: `SetJointState` puts an env in a state
//! given as values (warnings for what it clamps, precise refusals), and `GetBodies` reads
//! every instance's and site's state.

use gymfleet_client::{ActionType, ClientError, EnvOptions};
use gymfleet_e2e::{TestServer, ARM2};

use crate::{actions, assert_mentions, assert_not_found};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_joint_state_set_over_the_wire_reads_back_and_bodies_follow() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let options = || EnvOptions::new(ARM2).end_effectors(["forearm"]);
    let source = client.create_env(options()).await.expect("create");
    for t in 0..20 {
        source
            .step(ActionType::Torque, &actions(t, 2, 0.05))
            .await
            .expect("step");
    }
    let now = source.observe().await.expect("observe");
    let q: Vec<f64> = now.joint_positions.iter().map(|&v| f64::from(v)).collect();
    let v: Vec<f64> = now.joint_velocities.iter().map(|&v| f64::from(v)).collect();
    assert!(v.iter().any(|v| v.abs() > 1.0), "the source moves: {v:?}");

    let env = client.create_env(options()).await.expect("create");
    let (set, warnings) = env.set_joint_state(&q, &v, &[]).await.expect("set");
    assert!(warnings.is_empty(), "{warnings:?}");
    for (got, want) in set.joint_positions.iter().zip(&now.joint_positions) {
        assert!((got - want).abs() < 1e-3, "{got} deg read back, {want} set");
    }
    let (a, b) = (
        env.bodies().await.expect("bodies"),
        source.bodies().await.expect("bodies"),
    );
    assert_eq!(a.instances, ["base", "upper", "forearm"]);
    assert_eq!(a.centers_of_mass.len(), 9);
    assert_eq!((a.inertias.len(), a.velocities.len()), (30, 18));
    for (x, y) in a.centers_of_mass.iter().zip(&b.centers_of_mass) {
        assert!(
            (x - y).abs() < 1e-3,
            "{:?} against {:?}",
            a.centers_of_mass,
            b.centers_of_mass
        );
    }
    assert!(a.masses.iter().all(|&m| m > 0.0), "{:?}", a.masses);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_clamped_position_warns_and_an_unusable_state_is_refused() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(ARM2).end_effectors(["forearm"]))
        .await
        .expect("create");
    // The elbow's range is [-120°, 0°].
    let (set, warnings) = env
        .set_joint_state(&[10.0, 5.0], &[0.0, 0.0], &[])
        .await
        .expect("set");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].starts_with("joint_positions[1] (")
            && warnings[0].ends_with("): 5 is past the joint's limit; set to 0"),
        "{}",
        warnings[0]
    );
    assert!(
        set.joint_positions[1].abs() < 1e-3,
        "{:?}",
        set.joint_positions
    );

    let before = env.observe().await.expect("observe");
    for (q, v, b, message) in [
        (
            &[0.0][..],
            &[0.0, 0.0][..],
            &[][..],
            "joint_positions: expected 2 values (one per DOF), got 1",
        ),
        (
            &[0.0, 0.0],
            &[0.0, f64::NAN],
            &[],
            "joint_velocities[1]: expected a finite number, got NaN",
        ),
        (
            &[0.0, 0.0],
            &[0.0, 0.0],
            &[0.0; 13],
            "base_state: the env has no floating base: give no values, got 13",
        ),
    ] {
        let err = env.set_joint_state(q, v, b).await.expect_err(message);
        assert!(
            matches!(err, ClientError::InvalidArgument { .. }),
            "{err:?}"
        );
        assert_mentions(&err, &[message]);
        assert_eq!(env.observe().await.expect("observe"), before, "unchanged");
    }
    env.close().await.expect("close");
    assert_not_found(&env.bodies().await.unwrap_err(), &["sim_"]);
    let err = env.set_joint_state(&[0.0, 0.0], &[0.0, 0.0], &[]).await;
    assert_not_found(&err.unwrap_err(), &["sim_"]);
}
