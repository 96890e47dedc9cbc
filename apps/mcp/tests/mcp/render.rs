//! `gym_render`: an agent sees the robot (a PNG as image content, a JSON account as text),
//! and a bad size or camera is a tool error with the server's reason.

use base64::Engine as _;
use serde_json::{json, Value};

use crate::{doc, Adapter, ARM2};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn gym_render_returns_a_png_and_its_description() {
    let adapter = Adapter::embedded().await;
    let created = adapter
        .ok(
            "create_robot_env",
            json!({"document": doc(ARM2), "end_effector_ids": ["forearm"]}),
        )
        .await;
    let env_id = created["env_id"].as_str().expect("env_id").to_string();

    let result = adapter
        .call(
            "gym_render",
            json!({"env_id": env_id, "camera": "front", "width": 200, "height": 150}),
        )
        .await;
    assert_ne!(result.is_error, Some(true), "{result:?}");
    assert_eq!(result.content.len(), 2, "{result:?}");
    let image = result.content[0].as_image().expect("image content first");
    assert_eq!(image.mime_type, "image/png");
    let png = base64::engine::general_purpose::STANDARD
        .decode(&image.data)
        .expect("base64");
    let reader = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .expect("a PNG");
    assert_eq!((reader.info().width, reader.info().height), (200, 150));
    let text: Value =
        serde_json::from_str(&result.content[1].as_text().expect("text second").text).unwrap();
    assert_eq!(Some(&text), result.structured_content.as_ref());
    assert_eq!(text["env_id"], env_id.as_str());
    assert_eq!(
        (text["width"].as_u64(), text["height"].as_u64()),
        (Some(200), Some(150))
    );
    let description = text["description"].as_str().unwrap();
    assert!(
        description.contains("front view (perspective)"),
        "{description}"
    );
    assert!(description.contains("End effector 0 at ("), "{description}");
    assert!(text["grid_mm"].as_f64().unwrap() > 0.0);

    let err = adapter
        .err("gym_render", json!({"env_id": env_id, "width": 5000}))
        .await;
    assert!(
        err.contains("image size 5000x240 is out of range: each side must be 16 to 2048 pixels"),
        "{err}"
    );
    let err = adapter
        .err(
            "gym_render",
            json!({"env_id": env_id, "eye": [0, 0, 50], "target": [0, 0, 50]}),
        )
        .await;
    assert!(
        err.contains("bad camera: eye and target are the same point"),
        "{err}"
    );
    adapter.stop().await;
}
