//! An HTML replay of a swinging pendulum, recorded over the network with `Replay`. The page
//! is written to `target/tmp/replay/pendulum.html`, where `.ci/run`'s browser test
//! (`tests/browser/replay.test.mjs`, headless Chromium) opens it.

use gymfleet_client::{ActionType, EnvOptions, Replay};
use gymfleet_e2e::{TestServer, PENDULUM};

/// Where the browser test finds the page.
const REPLAY_PAGE: &str = concat!(env!("CARGO_TARGET_TMPDIR"), "/replay/pendulum.html");

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_swinging_pendulum_is_recorded_as_an_html_replay() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await
        .expect("env");
    env.reset(None).await.expect("reset");
    let mut replay = Replay::new("pendulum", env.info().dt);
    replay.capture(&env).await.expect("frame 0");
    // A push, then a free swing: about a quarter of a period in 120 frames.
    for i in 0..120 {
        let torque = if i < 10 { 2e-4 } else { 0.0 };
        env.step(ActionType::Torque, &[torque]).await.expect("step");
        replay.capture(&env).await.expect("frame");
    }
    assert_eq!(replay.len(), 121);
    let html = replay.to_html();
    assert!(html.starts_with("<!doctype html>"));
    assert!(html.contains(r#""title":"pendulum""#));
    let path = std::path::Path::new(REPLAY_PAGE);
    std::fs::create_dir_all(path.parent().unwrap()).expect("mkdir");
    replay.write_html(path).expect("write the page");
    assert_eq!(std::fs::read_to_string(path).unwrap(), html);
}
