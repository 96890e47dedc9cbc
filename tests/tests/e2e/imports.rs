//! Descriptions in MuJoCo's format over the network: detected and converted by the
//! server, shown by ConvertDocument, refused with the element and line when unsupported.

use gymfleet_client::{ActionType, BatchOptions, ClientError, DocumentFormat, EnvOptions};
use gymfleet_e2e::TestServer;

use crate::assert_mentions;

const REACHER: &str = include_str!("../../../crates/import/tests/data/reacher.xml");

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_mjcf_description_creates_envs_and_batches() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(REACHER).end_effectors(["fingertip"]))
        .await
        .expect("MJCF is detected and converted");
    let info = env.info();
    assert_eq!(info.action_dim, 2);
    let names: Vec<&str> = info.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["joint0", "joint1", "target_x", "target_y"]);
    let step = env
        .step(ActionType::Torque, &[0.5, -0.5])
        .await
        .expect("steps");
    assert!(step.observation.joint_velocities[0] > 0.0);

    // Its saved state carries the converted JSON: it forks anywhere.
    let state = env.save_state().await.expect("saves");
    let fork = client
        .fork(&state, 2, gymfleet_client::Autoreset::Disabled)
        .await
        .expect("forks");
    assert_eq!(fork.info().action_dim, 2);

    let batch = client
        .create_batch(
            BatchOptions::new(REACHER, 4)
                .end_effectors(["fingertip"])
                .format(DocumentFormat::Mjcf),
        )
        .await
        .expect("batch");
    batch
        .step(ActionType::Torque, &[0.1; 8])
        .await
        .expect("batch steps");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn convert_document_shows_the_json_and_what_was_ignored() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let converted = client
        .convert_document(REACHER, DocumentFormat::Detect)
        .await
        .expect("converts");
    assert_eq!(converted.format, DocumentFormat::Mjcf);
    let json: serde_json::Value =
        serde_json::from_str(&converted.document_json).expect("JSON text");
    assert!(
        json["assembly"]["instances"]
            .as_array()
            .expect("instances")
            .len()
            > 5
    );
    assert!(
        converted
            .warnings
            .iter()
            .any(|w| w.contains("timestep 0.01 s not applied")),
        "{:?}",
        converted.warnings
    );
    // The converted JSON builds the same env as the description.
    let from_json = client
        .create_env(EnvOptions::new(converted.document_json.clone()).format(DocumentFormat::Json))
        .await
        .expect("the JSON builds");
    assert_eq!(from_json.info().action_dim, 2);
    // JSON passes through, checked.
    let bad = client
        .convert_document(r#"{"parts": []}"#, DocumentFormat::Detect)
        .await
        .unwrap_err();
    assert!(
        matches!(bad, ClientError::InvalidArgument { .. }),
        "{bad:?}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn unsupported_descriptions_name_the_element_and_line() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let create = |doc: &str| client.create_env(EnvOptions::new(doc));
    let err = create("<mujoco>\n<worldbody>\n<body><freejoint/><geom size=\".1\"/></body>\n</worldbody>\n</mujoco>")
        .await
        .unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_eq!(
        err.message(),
        "document_json: line 3: <freejoint>: a free joint (floating base) is not supported yet"
    );
    let err = create("<robot name=\"ur5\"><link name=\"base\"/></robot>")
        .await
        .unwrap_err();
    assert_eq!(
        err.message(),
        "document_json: line 1: <robot>: URDF is not converted yet (MJCF is)"
    );
    let err = create("<html><body/></html>").await.unwrap_err();
    assert_mentions(
        &err,
        &["document_json: line 1: <html>: not a description gymfleet reads"],
    );
    let err = create("<mujoco><worldbody>").await.unwrap_err();
    assert_mentions(&err, &["document_json: not well-formed XML"]);
    // Told it is JSON, XML is a JSON error.
    let err = client
        .create_env(EnvOptions::new(REACHER).format(DocumentFormat::Json))
        .await
        .unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert!(!err.message().contains("<mujoco>"), "{}", err.message());
}
