//! `Render` over the network: a PNG of an env and of a batch's env, the pictures move with
//! the robot, and bad requests get exact errors.

use gymfleet_client::{
    ActionType, BatchOptions, Camera, CameraPreset, ClientError, EnvOptions, Image, ReachTask, Task,
};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};

/// The PNG's pixels, checking its size.
fn pixels(image: &Image) -> Vec<u8> {
    let decoder = png::Decoder::new(std::io::Cursor::new(image.png.clone()));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut out = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut out).expect("decode");
    assert_eq!((info.width, info.height), (image.width, image.height));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    out.truncate(info.buffer_size());
    out
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn render_draws_an_env_and_a_batch_env_as_they_are_now() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]))
        .await
        .expect("env");
    env.reset(None).await.expect("reset");
    // A fixed camera, so that only the pendulum moves between the pictures.
    let camera = Camera {
        eye: Some([10.0, -150.0, 25.0]),
        target: Some([10.0, 10.0, 25.0]),
        ..Camera::default()
    };
    let before = env.render(&camera, 0, 0).await.expect("render");
    assert_eq!((before.width, before.height), (320, 240));
    assert!(
        before.description.contains("custom view"),
        "{}",
        before.description
    );
    let first = pixels(&before);
    assert_eq!(
        first,
        pixels(&env.render(&camera, 0, 0).await.expect("again"))
    );
    for _ in 0..120 {
        env.step(ActionType::Torque, &[2e-3]).await.expect("step");
    }
    let after = pixels(&env.render(&camera, 0, 0).await.expect("render"));
    let changed = first
        .chunks(3)
        .zip(after.chunks(3))
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed > 100,
        "only {changed} pixels changed after the swing"
    );

    // A batch env, with a reach target drawn in.
    let batch = client
        .create_batch(BatchOptions::new(ARM2, 3).task(Task::from(ReachTask {
            end_effector: "forearm".into(),
            target: Some([20.0, 0.0, 40.0]),
            ..ReachTask::default()
        })))
        .await
        .expect("batch");
    batch.reset(Some(1)).await.expect("reset");
    let image = batch
        .render(2, &Camera::preset(CameraPreset::Top), 64, 48)
        .await
        .expect("render");
    assert_eq!((image.width, image.height), (64, 48));
    assert!(
        image.description.contains("Target at (20, 0, 40) mm"),
        "{}",
        image.description
    );
    pixels(&image);

    // Errors, exactly.
    let err = batch
        .render(3, &Camera::default(), 0, 0)
        .await
        .expect_err("past the end");
    assert_eq!(
        err.to_string(),
        "invalid argument: env_index: 3 is out of range: the batch has 3 envs"
    );
    let err = env.render(&camera, 4096, 10).await.expect_err("too large");
    assert!(
        matches!(err, ClientError::InvalidArgument { .. }),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        "invalid argument: image size 4096x10 is out of range: each side must be 16 to 2048 pixels (0 means 320x240)"
    );
    let bad = Camera {
        fov_deg: -5.0,
        ..Camera::default()
    };
    let err = env.render(&bad, 0, 0).await.expect_err("bad fov");
    assert_eq!(
        err.to_string(),
        "invalid argument: bad camera: fov_deg must be in (0, 170] degrees (0 means 45), got -5"
    );
    let far = Camera {
        eye: Some([1e300, 0.0, 0.0]),
        ..Camera::default()
    };
    let err = env.render(&far, 0, 0).await.expect_err("eye at infinity");
    assert_eq!(
        err.to_string(),
        "invalid argument: bad camera: eye must be finite and within 1e7 mm of the origin, got [inf, 0.0, 0.0]"
    );
    env.close().await.expect("close");
    let err = env.render(&camera, 0, 0).await.expect_err("closed");
    assert!(matches!(err, ClientError::NotFound { .. }), "{err:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn get_scene_gives_every_part_where_it_is() {
    use gymfleet_client::SceneShape;
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let env = client
        .create_env(EnvOptions::new(ARM2).end_effectors(["forearm"]))
        .await
        .expect("env");
    env.reset(None).await.expect("reset");
    let scene = env.scene().await.expect("scene");
    let names: Vec<&str> = scene.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["base", "upper", "forearm"]);
    // arm2's base: a cylinder of radius 15 mm and height 5 mm, its centre 2.5 mm up.
    assert_eq!(
        scene.bodies[0].shape,
        SceneShape::Cylinder {
            radius: 15.0,
            half_height: 2.5
        }
    );
    assert!(
        (scene.bodies[0].position[2] - 2.5).abs() < 1e-4,
        "{:?}",
        scene.bodies[0]
    );
    // The forearm: a 3 x 3 x 25 mm box from z = 35 mm.
    assert_eq!(
        scene.bodies[2].shape,
        SceneShape::Box {
            half_extents: [1.5, 1.5, 12.5]
        }
    );
    assert!(
        (scene.bodies[2].position[2] - 47.5).abs() < 1e-3,
        "{:?}",
        scene.bodies[2]
    );
    assert_eq!(scene.joints.len(), 2);
    assert_eq!(scene.end_effectors.len(), 1);
    assert_eq!(scene.target, None);
    // It moves with the robot, and matches the observation's end-effector position.
    for _ in 0..60 {
        env.step(ActionType::Torque, &[0.0, 1e-3])
            .await
            .expect("step");
    }
    let observed = env.observe().await.expect("observe");
    let moved = env.scene().await.expect("scene");
    assert_ne!(moved.bodies[2].position, scene.bodies[2].position);
    let ee = observed.end_effector_poses[0];
    for (scene_mm, observed_mm) in moved.end_effectors[0].iter().zip(&ee[..3]) {
        assert!((scene_mm - f64::from(*observed_mm)).abs() < 1e-3);
    }
    env.close().await.expect("close");
    let err = env.scene().await.expect_err("closed");
    assert!(matches!(err, ClientError::NotFound { .. }), "{err:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_unknown_camera_preset_or_no_target_is_invalid() {
    use gymfleet_proto::v1 as pb;
    let server = TestServer::start_default().await;
    let env = server
        .client()
        .await
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("env");
    let mut raw = pb::simulator_client::SimulatorClient::connect(server.url())
        .await
        .expect("connect");
    let status = raw
        .render(pb::RenderRequest {
            env_id: env.id().to_string(),
            camera: Some(pb::Camera {
                preset: 99,
                ..Default::default()
            }),
            ..Default::default()
        })
        .await
        .expect_err("preset 99");
    assert_eq!(status.code(), tonic::Code::InvalidArgument);
    assert_eq!(status.message(), "camera.preset: unknown camera preset 99");
    let status = raw
        .render(pb::RenderRequest::default())
        .await
        .expect_err("neither id");
    assert_eq!(status.code(), tonic::Code::InvalidArgument);
    assert_eq!(
        status.message(),
        "env_id: expected exactly one of env_id and batch_id"
    );
}
