//! Descriptions in MuJoCo's and ROS's formats over the network (MJCF, URDF with its meshes
//! in an assets archive or the model library): detected and converted by the server, shown
//! by ConvertDocument, refused with the element and line when unsupported.

// These requests are built in the flat form (`CreateEnvRequest.document_json`, …): the
// proto deprecates it for `options`, and the server still reads it (`server/src/convert/create.rs`).
#![allow(deprecated)]

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

/// Assets larger than a message can carry are refused by the client before anything is
/// sent, naming the sizes (the transport alone would only report a broken stream).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn assets_over_the_message_limit_are_refused_before_sending() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let huge = vec![7u8; 65 * 1024 * 1024];
    let expected = format!(
        "bytes ({} of document, {} of assets) is over the message limit of {} bytes; send only \
         the files the description references",
        REACHER.len(),
        huge.len(),
        64 * 1024 * 1024
    );
    let err = client
        .create_env(EnvOptions::new(REACHER).assets(huge.clone()))
        .await
        .unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert!(
        err.message().starts_with("request: ") && err.message().contains(&expected),
        "{}",
        err.message()
    );
    let err = client
        .create_batch(BatchOptions::new(REACHER, 2).assets(huge.clone()))
        .await
        .unwrap_err();
    assert!(
        err.message()
            .contains("of assets) is over the message limit"),
        "{}",
        err.message()
    );
    let err = client
        .convert_document_with_assets(REACHER, DocumentFormat::Detect, huge)
        .await
        .unwrap_err();
    assert!(
        err.message()
            .contains("of assets) is over the message limit"),
        "{}",
        err.message()
    );
    // The server is fine and still serves.
    client
        .create_env(EnvOptions::new(REACHER))
        .await
        .expect("a request within the limit");
}

const ANT: &str = include_str!("../../../crates/import/tests/data/ant.xml");

/// Gymnasium's Ant over the network: its free joint is a floating base whose pose and
/// velocity every observation carries (single envs in their own fields, batch rows after
/// the joint velocities), the same bits either way; its saved state brings the base back.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_free_joint_makes_a_floating_base_over_the_network() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(ANT))
        .await
        .expect("the Ant converts");
    let info = env.info().clone();
    let layout = info.observation_layout.clone();
    assert!(info.floating_base());
    assert_eq!(info.action_dim, 8);
    assert_eq!(info.observation_dim, 16 + 13);
    let names: Vec<&str> = layout.iter().map(|(name, _)| name.as_str()).collect();
    assert_eq!(
        names,
        [
            "joint_positions",
            "joint_velocities",
            "base_pose",
            "base_velocity",
            "end_effector_poses"
        ]
    );
    let batch = client
        .create_batch(BatchOptions::new(ANT, 2))
        .await
        .expect("a batch of Ants");
    assert!(batch.info().floating_base());
    let torque = [20.0, -10.0, 5.0, 0.0, -20.0, 10.0, 0.0, 5.0];
    let mut single = env.observe().await.expect("observes");
    assert_eq!(single.base_pose[..3], [0.0, 0.0, 750.0]);
    let mut rows = Vec::new();
    for _ in 0..60 {
        single = env
            .step(ActionType::Torque, &torque)
            .await
            .expect("steps")
            .observation;
        let both: Vec<f32> = torque.iter().chain(&torque).copied().collect();
        rows = batch
            .step(ActionType::Torque, &both)
            .await
            .expect("batch steps")
            .obs(1)
            .to_vec();
    }
    assert_eq!(single.base_pose.len(), 7);
    assert_eq!(single.base_velocity.len(), 6);
    assert!(
        single.base_pose[2] < 700.0,
        "it fell: {:?}",
        single.base_pose
    );
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(&rows),
        bits(&single.to_flat(&layout)),
        "batch row = single env"
    );

    let state = env.save_state().await.expect("saves");
    let later = env
        .step(ActionType::Torque, &torque)
        .await
        .expect("steps")
        .observation;
    env.load_state(&state).await.expect("loads");
    let again = env
        .step(ActionType::Torque, &torque)
        .await
        .expect("steps")
        .observation;
    assert_eq!(
        bits(&again.to_flat(&layout)),
        bits(&later.to_flat(&layout)),
        "the state brings the base back"
    );
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
    // MuJoCo's timestep is the document's env step (`simulation.dt`).
    assert_eq!(json["simulation"]["dt"], 0.01);
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
    let err = create("<mujoco>\n<worldbody>\n<body><geom size=\".1\"/><body><freejoint/><geom size=\".1\"/></body></body>\n</worldbody>\n</mujoco>")
        .await
        .unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_eq!(
        err.message(),
        "document_json: line 3: <freejoint>: a free joint belongs to a top-level body (a child of <worldbody>)"
    );
    let err = create("<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<joint name=\"j\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>")
        .await
        .unwrap_err();
    assert_eq!(
        err.message(),
        "document_json: line 4: <joint type=…>: \"planar\" joints are not supported"
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
                "<mujoco><worldbody><body><joint type=\"ball\" springdamper=\"0.1 1\"/><geom size=\".1\"/></body></worldbody></mujoco>",
            ),
        ],
    );
    let err = gymfleet_server::ModelLibrary::load(&dir.0)
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("--models: "), "{err}");
    assert!(err.contains("bad.xml: line 1: <joint>"), "{err}");
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

const UR5: &str = include_str!(
    "../../../crates/import/tests/data/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf"
);
const UR5_MESHES: &str = "example-robot-data/robots/ur_description/meshes/ur5/collision";

/// The UR5's collision meshes: (path from the assets root, bytes).
fn ur5_meshes() -> Vec<(String, Vec<u8>)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../crates/import/tests/data")
        .join(UR5_MESHES);
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
        .expect("the import crate's test data")
        .map(|e| {
            let e = e.expect("entry");
            let name = format!("{UR5_MESHES}/{}", e.file_name().to_string_lossy());
            (name, std::fs::read(e.path()).expect("read"))
        })
        .collect();
    files.sort();
    files
}

/// `files` as a tar archive.
fn tar_of(files: &[(String, Vec<u8>)]) -> Vec<u8> {
    let mut out = tar::Builder::new(Vec::new());
    for (name, bytes) in files {
        let mut header = tar::Header::new_gnu();
        header.set_size(bytes.len() as u64);
        header.set_mode(0o644);
        header.set_cksum();
        out.append_data(&mut header, name, bytes.as_slice())
            .expect("tar");
    }
    out.into_inner().expect("tar")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_urdf_with_its_meshes_in_an_archive_creates_envs_that_hold_still() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let assets = tar_of(&ur5_meshes());
    let env = client
        .create_env(
            EnvOptions::new(UR5)
                .assets(assets.clone())
                .end_effectors(["ee_link"]),
        )
        .await
        .expect("URDF with meshes");
    assert_eq!(env.info().action_dim, 6);
    let mut last = None;
    for _ in 0..120 {
        last = Some(
            env.step(ActionType::Position, &[0.0; 6])
                .await
                .expect("steps"),
        );
    }
    let q = last.expect("stepped").observation.joint_positions;
    assert!(
        q.iter().all(|v| v.abs() < 1.0),
        "PD at the initial pose: {q:?}"
    );
    // The scene draws the hulls.
    let scene = env.scene().await.expect("scene");
    assert!(scene
        .bodies
        .iter()
        .any(|b| b.name == "forearm_link"
            && matches!(b.shape, gymfleet_client::SceneShape::Mesh { .. })));
    // The saved state carries the meshes (read into the document): it forks without assets.
    let state = env.save_state().await.expect("saves");
    let fork = client
        .fork(&state, 2, gymfleet_client::Autoreset::Disabled)
        .await
        .expect("forks");
    assert_eq!(fork.info().action_dim, 6);
    // ConvertDocument shows the document with the hulls' vertices in place of the files.
    let converted = client
        .convert_document_with_assets(UR5, DocumentFormat::Detect, assets.clone())
        .await
        .expect("converts");
    assert_eq!(converted.format, DocumentFormat::Urdf);
    assert!(!converted.document_json.contains("package://"));
    assert!(converted
        .warnings
        .iter()
        .any(|w| w.contains("<visual> ignored")));
    // A batch takes the same archive.
    let batch = client
        .create_batch(BatchOptions::new(UR5, 3).assets(assets))
        .await
        .expect("a batch");
    assert_eq!(batch.info().n_envs, 3);

    // Without the archive, or with one that misses a mesh: the file is named.
    let err = client.create_env(EnvOptions::new(UR5)).await.unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_mentions(
        &err,
        &[
            ".primitive.file: \"package://example-robot-data/robots/ur_description/meshes/ur5/collision/base.stl\": a mesh file is read from the request's assets",
        ],
    );
    let mut partial = ur5_meshes();
    partial.retain(|(n, _)| !n.ends_with("wrist2.stl"));
    let err = client
        .create_env(EnvOptions::new(UR5).assets(tar_of(&partial)))
        .await
        .unwrap_err();
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_mentions(&err, &["assets: no file \"package://example-robot-data/robots/ur_description/meshes/ur5/collision/wrist2.stl\" in the archive"]);
    let err = client
        .create_env(EnvOptions::new(UR5).assets(b"not an archive".to_vec()))
        .await
        .unwrap_err();
    assert_eq!(
        err.message(),
        "document_json: assets: expected a zip, tar or tar.gz archive; the 14 bytes given are none of these"
    );
    let info = client.server_info().await.expect("info");
    assert_eq!((info.envs, info.batches), (1, 2), "nothing half-created");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_library_urdf_reads_its_meshes_from_the_library_folder() {
    use gymfleet_server::{ModelLibrary, ServerConfig};
    let dir = Dir::with("urdf", &[("ur5.urdf", UR5)]);
    for (name, bytes) in ur5_meshes() {
        let path = dir.0.join(&name);
        std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
        std::fs::write(path, bytes).expect("write");
    }
    let library = ModelLibrary::load(&dir.0).expect("loads");
    let server = TestServer::start(ServerConfig {
        models: Some(std::sync::Arc::new(library)),
        ..ServerConfig::default()
    })
    .await;
    let client = server.client().await;
    let models = client.list_models().await.expect("lists");
    assert_eq!(models.len(), 1);
    assert_eq!(
        (models[0].name.as_str(), models[0].format, models[0].dofs),
        ("ur5", DocumentFormat::Urdf, 6)
    );
    let env = client
        .create_env(EnvOptions::from_model("ur5"))
        .await
        .expect("a library URDF");
    assert_eq!(env.info().action_dim, 6);
    // A model brings its own meshes.
    let err = client
        .create_env(EnvOptions::from_model("ur5").assets(b"x".to_vec()))
        .await
        .unwrap_err();
    assert_eq!(
        err.message(),
        "assets: a library model brings its own mesh files: give assets with document_json only"
    );
}
