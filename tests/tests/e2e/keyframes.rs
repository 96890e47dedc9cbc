//! Keyframes over the network: an MJCF file's `<key>`s become the env's keyframes
//! (`EnvInfo.keyframes`), `ResetRequest.keyframe` and `ResetBatchRequest.keyframe` start
//! from one, and an unknown name is refused with what the document has.

use gymfleet_client::{BatchOptions, ClientError, EnvOptions};
use gymfleet_e2e::TestServer;

use crate::assert_mentions;

/// Two hinges (the first with `ref`), and two keys (radians, as MuJoCo's qpos).
const DOUBLE: &str = r#"<mujoco>
  <worldbody>
    <body name="upper">
      <joint name="shoulder" type="hinge" axis="0 1 0" ref="10"/>
      <geom type="capsule" fromto="0 0 0 0 0 -.3" size=".02"/>
      <body name="lower" pos="0 0 -.3">
        <joint name="elbow" type="hinge" axis="0 1 0" range="-90 90"/>
        <geom type="capsule" fromto="0 0 0 0 0 -.3" size=".02"/>
      </body>
    </body>
  </worldbody>
  <keyframe>
    <key name="bent" qpos="0.5 -1.0" qvel="0.25 0"/>
    <key qpos="0 0.3"/>
  </keyframe>
</mujoco>"#;

fn degrees(v: f32) -> f64 {
    f64::from(v)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_reset_names_a_keyframe_of_the_converted_file() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(DOUBLE))
        .await
        .expect("create");
    assert_eq!(env.info().keyframes, ["bent", "key1"]);
    let bent = env.reset_to(None, "bent").await.expect("reset to bent");
    // Document units: degrees, the observed positions MuJoCo's qpos.
    let want = [0.5f64.to_degrees(), -1.0f64.to_degrees()];
    for (got, want) in bent.joint_positions.iter().zip(want) {
        assert!(
            (degrees(*got) - want).abs() < 1e-3,
            "{got} deg, {want} wanted"
        );
    }
    assert!((degrees(bent.joint_velocities[0]) - 0.25f64.to_degrees()).abs() < 1e-3);
    let plain = env.reset(None).await.expect("plain reset");
    assert!(
        (degrees(plain.joint_positions[0]) - 10.0).abs() < 1e-3,
        "the file's ref"
    );

    let err = env
        .reset_to(None, "home")
        .await
        .expect_err("no such keyframe");
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_mentions(
        &err,
        &["keyframe: no keyframe is named \"home\"; the document's are \"bent\", \"key1\""],
    );
    assert_eq!(
        env.observe().await.expect("observe"),
        plain,
        "nothing was reset"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_batch_resets_some_envs_to_a_keyframe() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let batch = client
        .create_batch(BatchOptions::new(DOUBLE, 3))
        .await
        .expect("create");
    assert_eq!(batch.info().keyframes, ["bent", "key1"]);
    let obs = batch
        .reset_envs_to(None, 0, &[1], "key1")
        .await
        .expect("reset env 1 to key1");
    assert!((degrees(obs.obs(1)[1]) - 0.3f64.to_degrees()).abs() < 1e-3);
    assert!(degrees(obs.obs(0)[1]).abs() < 1e-3, "env 0 keeps its state");
    let err = batch
        .reset_envs_to(None, 0, &[], "nope")
        .await
        .expect_err("no such keyframe");
    assert_mentions(&err, &["keyframe: no keyframe is named \"nope\""]);
}
