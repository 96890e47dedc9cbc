//! Bounded cost per request: documents past the structural limits (instances, joints,
//! DOFs, end effectors) and batches whose replies could outgrow the message limit are
//! refused with RESOURCE_EXHAUSTED naming the flag, before anything is built.

use crate::exhausted;
use gymfleet_client::{BatchOptions, EnvOptions};
use gymfleet_e2e::{TestServer, ARM2};
use gymfleet_server::ServerConfig;

/// A chain of `n` 4 mm links on revolute joints about +Y, standing on a base.
fn chain(n: usize) -> String {
    let mut instances = vec![r#"{"part": "Base", "name": "base"}"#.to_string()];
    let mut joints = Vec::new();
    for i in 1..=n {
        instances.push(format!(
            r#"{{"part": "Link", "name": "l{i}", "position": {{"x": 0, "y": 0, "z": {}}}}}"#,
            5 * i
        ));
        let parent = if i == 1 {
            "base".to_string()
        } else {
            format!("l{}", i - 1)
        };
        joints.push(format!(
            r#"{{"type": "revolute", "parent": "{parent}", "child": "l{i}", "anchor": {{"x": 2, "y": 2, "z": {}}}, "axis": {{"x": 0, "y": 1, "z": 0}}}}"#,
            5 * i
        ));
    }
    format!(
        r#"{{"parts": [{{"name": "Base", "primitive": {{"type": "cube", "size": {{"x": 4, "y": 4, "z": 5}}}}}},
                      {{"name": "Link", "primitive": {{"type": "cube", "size": {{"x": 4, "y": 4, "z": 5}}}}}}],
            "assembly": {{"instances": [{}], "joints": [{}]}}}}"#,
        instances.join(","),
        joints.join(",")
    )
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn documents_past_the_structural_limits_are_refused_naming_the_flag() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let limits = client.server_info().await.expect("info").limits;
    assert_eq!(
        (
            limits.max_instances,
            limits.max_joints,
            limits.max_dofs,
            limits.max_end_effectors
        ),
        (512, 512, 128, 64)
    );
    let cases = [
        (
            chain(5000),
            Vec::new(),
            "assembly.instances: 5001 exceeds the server's limit of 512; raise it with \
             --max-instances (GYMFLEET_MAX_INSTANCES)",
        ),
        (
            chain(200),
            Vec::new(),
            "degrees of freedom: 200 exceeds the server's limit of 128; raise it with \
             --max-dofs (GYMFLEET_MAX_DOFS)",
        ),
        (
            ARM2.to_string(),
            vec!["forearm".to_string(); 65],
            "end_effector_ids: 65 exceeds the server's limit of 64; raise it with \
             --max-end-effectors (GYMFLEET_MAX_END_EFFECTORS)",
        ),
    ];
    for (document, ids, message) in cases {
        let err = client
            .create_env(EnvOptions::new(document.clone()).end_effectors(ids.clone()))
            .await
            .expect_err("refused");
        assert_eq!(exhausted(err), message);
        let err = client
            .create_batch(BatchOptions::new(document, 4).end_effectors(ids))
            .await
            .expect_err("refused");
        assert_eq!(exhausted(err), message);
    }
    let info = client.server_info().await.expect("info");
    assert_eq!((info.envs, info.batches), (0, 0), "nothing half-created");
    // Within the limits, a 100-link chain is an env like any other.
    client
        .create_env(EnvOptions::new(chain(100)))
        .await
        .expect("100 DOF are within the default limit");

    let strict = TestServer::start(ServerConfig {
        max_joints: 10,
        ..ServerConfig::default()
    })
    .await;
    let err = strict
        .client()
        .await
        .create_env(EnvOptions::new(chain(11)))
        .await
        .expect_err("11 joints");
    assert_eq!(
        exhausted(err),
        "assembly.joints: 11 exceeds the server's limit of 10; raise it with --max-joints \
         (GYMFLEET_MAX_JOINTS)"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_batch_whose_replies_could_outgrow_the_message_limit_is_refused() {
    let server = TestServer::start(ServerConfig {
        max_message_bytes: 64 * 1024,
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let err = client
        .create_batch(BatchOptions::new(ARM2, 1000).end_effectors(["forearm"]))
        .await
        .expect_err("too large a reply");
    assert_eq!(
        exhausted(err),
        "n_envs: a step of 1000 envs × 11 observation values can need 98000 bytes, over the \
         server's message limit of 65536; use smaller batches, or raise --max-message-bytes \
         (GYMFLEET_MAX_MESSAGE_BYTES) on the server and the client"
    );
    let info = client.server_info().await.expect("info");
    assert_eq!((info.batches, info.batch_envs), (0, 0));
    client
        .create_batch(BatchOptions::new(ARM2, 500).end_effectors(["forearm"]))
        .await
        .expect("500 envs fit");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn envs_whose_steps_ask_for_too_much_work_are_refused_before_building() {
    let server = TestServer::start(ServerConfig {
        threads: 1,
        max_step_work: 1_000,
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    assert_eq!(
        client
            .server_info()
            .await
            .expect("info")
            .limits
            .max_step_work,
        1_000
    );
    // 20 envs × 10 substeps × 6 DOFs = 1 200 DOF-substeps.
    let err = client
        .create_batch(BatchOptions::new(chain(6), 20).substeps(10))
        .await
        .unwrap_err();
    assert_eq!(
        exhausted(err),
        "a step of 20 env(s) × 10 substeps × 6 DOFs is 1200 DOF-substeps of work, over the \
         server's limit of 1000 per call; use fewer envs or substeps, or raise \
         --max-step-work (GYMFLEET_MAX_STEP_WORK)"
    );
    // One env of a huge substep count, too.
    let err = client
        .create_env(EnvOptions::new(chain(2)).substeps(1000))
        .await
        .unwrap_err();
    assert!(exhausted(err).contains("is 2000 DOF-substeps"));
    // Within the budget, it builds; nothing was left held by the refusals.
    client
        .create_batch(BatchOptions::new(chain(6), 16).substeps(10))
        .await
        .expect("960 DOF-substeps");
    let info = client.server_info().await.expect("info");
    assert_eq!((info.envs, info.batches, info.batch_envs), (0, 1, 16));
    server.stop().await.expect("clean shutdown");
}
