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

/// A directory holding `files` (name, text), removed on drop.
struct Dir(std::path::PathBuf);

impl Dir {
    fn with(tag: &str, files: &[(&str, &str)]) -> Dir {
        let dir =
            std::env::temp_dir().join(format!("gymfleet-models-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        for (name, text) in files {
            std::fs::write(dir.join(name), text).expect("write");
        }
        Dir(dir)
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_model_library_is_listed_and_named_by_requests() {
    use gymfleet_server::{ModelLibrary, ServerConfig};
    let dir = Dir::with(
        "ok",
        &[
            ("reacher.xml", REACHER),
            ("arm2.json", gymfleet_e2e::ARM2),
            ("notes.txt", "not a model"),
        ],
    );
    let library = ModelLibrary::load(&dir.0).expect("loads");
    let server = TestServer::start(ServerConfig {
        models: Some(std::sync::Arc::new(library)),
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let models = client.list_models().await.expect("lists");
    let listed: Vec<(&str, DocumentFormat, usize, usize)> = models
        .iter()
        .map(|m| (m.name.as_str(), m.format, m.dofs, m.action_dim))
        .collect();
    assert_eq!(
        listed,
        [
            ("arm2", DocumentFormat::Json, 2, 2),
            ("reacher", DocumentFormat::Mjcf, 4, 2)
        ]
    );
    let env = client
        .create_env(EnvOptions::from_model("reacher").end_effectors(["fingertip"]))
        .await
        .expect("a library model");
    assert_eq!(env.info().action_dim, 2);
    let batch = client
        .create_batch(BatchOptions::from_env(EnvOptions::from_model("arm2"), 3))
        .await
        .expect("a batch of a library model");
    assert_eq!(batch.info().n_envs, 3);

    let err = client
        .create_env(EnvOptions::from_model("ur5e"))
        .await
        .unwrap_err();
    assert!(matches!(err, ClientError::NotFound { .. }), "{err:?}");
    assert_eq!(
        err.message(),
        "model: \"ur5e\" is not in this server's model library (known: \"arm2\", \"reacher\")"
    );
    // A document and a model: one or the other (the raw stub sends both).
    let mut raw = gymfleet_proto::v1::simulator_client::SimulatorClient::new(
        tonic::transport::Channel::from_shared(server.url())
            .expect("url")
            .connect()
            .await
            .expect("connect"),
    );
    let status = raw
        .create_env(gymfleet_proto::v1::CreateEnvRequest {
            document_json: gymfleet_e2e::ARM2.to_string(),
            model: "arm2".to_string(),
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), tonic::Code::InvalidArgument);
    assert_eq!(
        status.message(),
        "model: give document_json or model, not both"
    );

    // Without a library: nothing listed, and a model is unknown.
    let bare = TestServer::start_default().await;
    let bare_client = bare.client().await;
    assert!(bare_client.list_models().await.expect("lists").is_empty());
    let err = bare_client
        .create_env(EnvOptions::from_model("arm2"))
        .await
        .unwrap_err();
    assert_eq!(
        err.message(),
        "model: \"arm2\" is not in this server's model library (known: none: start the server with --models DIR)"
    );
}

#[test]
fn a_broken_library_file_stops_the_server_naming_it() {
    let dir = Dir::with(
        "broken",
        &[
            ("good.json", gymfleet_e2e::ARM2),
            (
                "bad.xml",
                "<mujoco><worldbody><body><freejoint/></body></worldbody></mujoco>",
            ),
        ],
    );
    let err = gymfleet_server::ModelLibrary::load(&dir.0)
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("--models: "), "{err}");
    assert!(err.contains("bad.xml: line 1: <freejoint>"), "{err}");
    let twice = Dir::with(
        "twice",
        &[("arm.json", gymfleet_e2e::ARM2), ("arm.xml", REACHER)],
    );
    let err = gymfleet_server::ModelLibrary::load(&twice.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("arm.xml: model \"arm\" is also "), "{err}");
    assert!(err.ends_with("arm.json"), "{err}");
    let missing = gymfleet_server::ModelLibrary::load(std::path::Path::new("/no/such/dir"))
        .unwrap_err()
        .to_string();
    assert!(missing.starts_with("--models: /no/such/dir: "), "{missing}");
}
