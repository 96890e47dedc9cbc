//! [`Replay`]: an episode's poses, recorded from [`Env::scene`], written as one
//! self-contained HTML file (a three.js view with play, pause, a scrubber and orbit
//! controls; three.js r170 is embedded, so the file opens offline).

use base64::Engine as _;
use serde_json::{json, Value};

use crate::{Env, Result, Scene, SceneShape};

const PAGE: &str = include_str!("../assets/replay.html");
const THREE: &str = include_str!("../assets/three/three.module.min.js");
const ORBIT_CONTROLS: &str = include_str!("../assets/three/OrbitControls.js");

/// A frame whose bodies do not match the first frame's.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("replay frame {frame}: {reason}")]
pub struct ReplayMismatch {
    /// The frame's index.
    pub frame: usize,
    /// What differs from the first frame.
    pub reason: String,
}

/// An episode's poses, frame by frame, for an HTML replay.
///
/// ```no_run
/// # async fn demo(env: gymfleet_client::Env) -> Result<(), Box<dyn std::error::Error>> {
/// use gymfleet_client::{ActionType, Replay};
/// let mut replay = Replay::new("pendulum", env.info().dt);
/// replay.capture(&env).await?;
/// for _ in 0..240 {
///     env.step(ActionType::Torque, &[1e-4]).await?;
///     replay.capture(&env).await?;
/// }
/// replay.write_html("pendulum.html")?;
/// # Ok(()) }
/// ```
#[derive(Debug, Clone)]
pub struct Replay {
    title: String,
    dt: f64,
    /// Each body's name and shape, from the first frame.
    bodies: Vec<(String, SceneShape)>,
    frames: Vec<Value>,
}

impl Replay {
    /// An empty replay whose frames are `dt` seconds apart.
    pub fn new(title: impl Into<String>, dt: f64) -> Replay {
        Replay {
            title: title.into(),
            dt,
            bodies: Vec::new(),
            frames: Vec::new(),
        }
    }

    /// Frames recorded so far.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether no frame was recorded.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Adds a frame. The first frame's bodies (names and shapes) fix the replay's; a
    /// later scene with other bodies is refused.
    pub fn push(&mut self, scene: &Scene) -> std::result::Result<(), ReplayMismatch> {
        let frame = self.frames.len();
        if self.frames.is_empty() {
            self.bodies = scene
                .bodies
                .iter()
                .map(|b| (b.name.clone(), b.shape.clone()))
                .collect();
        } else if scene.bodies.len() != self.bodies.len()
            || scene
                .bodies
                .iter()
                .zip(&self.bodies)
                .any(|(b, (name, shape))| b.name != *name || b.shape != *shape)
        {
            return Err(ReplayMismatch {
                frame,
                reason: format!(
                    "its {} bodies are not the first frame's {} (names and shapes must match)",
                    scene.bodies.len(),
                    self.bodies.len()
                ),
            });
        }
        let poses: Vec<[f64; 7]> = scene
            .bodies
            .iter()
            .map(|b| {
                let [x, y, z] = b.position;
                let [qw, qx, qy, qz] = b.rotation;
                [x, y, z, qw, qx, qy, qz]
            })
            .collect();
        self.frames.push(json!({
            "poses": poses,
            "end_effectors": scene.end_effectors,
            "target": scene.target,
        }));
        Ok(())
    }

    /// Reads `env`'s scene ([`Env::scene`]) and adds it as a frame.
    pub async fn capture(&mut self, env: &Env) -> Result<()> {
        let scene = env.scene().await?;
        self.push(&scene).map_err(|e| crate::ClientError::Protocol {
            message: e.to_string(),
            code: tonic::Code::Ok,
        })
    }

    /// The replay as one HTML file.
    pub fn to_html(&self) -> String {
        let mut instances: Vec<&str> = Vec::new();
        let bodies: Vec<Value> = self
            .bodies
            .iter()
            .map(|(name, shape)| {
                let instance = instances.iter().position(|n| n == name).unwrap_or_else(|| {
                    instances.push(name);
                    instances.len() - 1
                });
                let shape = match shape {
                    SceneShape::Box { half_extents } => json!({ "box": half_extents }),
                    SceneShape::Cylinder {
                        radius,
                        half_height,
                    } => json!({ "cylinder": [radius, half_height] }),
                    SceneShape::Sphere { radius } => json!({ "sphere": radius }),
                    SceneShape::Capsule {
                        radius,
                        half_segment,
                    } => json!({ "capsule": [radius, half_segment] }),
                    SceneShape::Mesh {
                        ref vertices,
                        ref triangles,
                    } => json!({ "mesh": [vertices.as_flattened(), triangles.as_flattened()] }),
                };
                json!({ "name": name, "instance": instance, "shape": shape })
            })
            .collect();
        let data = json!({
            "title": self.title,
            "dt": self.dt,
            "bodies": bodies,
            "frames": self.frames,
        });
        // Inside <script>, "</" could end the element: JSON allows "<\/" for it.
        let data = data.to_string().replace("</", "<\\/");
        let b64 = |js: &str| {
            format!(
                "data:text/javascript;base64,{}",
                base64::engine::general_purpose::STANDARD.encode(js)
            )
        };
        PAGE.replace("__TITLE__", &html_escape(&self.title))
            .replace("__THREE_URL__", &b64(THREE))
            .replace("__ORBIT_URL__", &b64(ORBIT_CONTROLS))
            .replace("__DATA__", &data)
    }

    /// Writes [`Replay::to_html`] to `path`.
    pub fn write_html(&self, path: impl AsRef<std::path::Path>) -> std::io::Result<()> {
        std::fs::write(path, self.to_html())
    }
}

fn html_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SceneBody;

    fn scene(name: &str, z: f64) -> Scene {
        Scene {
            bodies: vec![SceneBody {
                name: name.to_string(),
                shape: SceneShape::Sphere { radius: 5.0 },
                position: [0.0, 0.0, z],
                rotation: [1.0, 0.0, 0.0, 0.0],
            }],
            joints: Vec::new(),
            end_effectors: vec![[0.0, 0.0, z]],
            target: None,
        }
    }

    #[test]
    fn the_page_embeds_three_and_the_frames_and_escapes_names() {
        let mut replay = Replay::new("a </script> <b>", 0.01);
        replay
            .push(&scene("</script><script>alert(1)</script>", 1.0))
            .unwrap();
        replay
            .push(&scene("</script><script>alert(1)</script>", 2.0))
            .unwrap();
        let html = replay.to_html();
        assert!(html.contains("<title>a &lt;/script&gt; &lt;b&gt;</title>"));
        // The name reaches the data escaped; only the page's own script tags close.
        assert!(!html.contains("</script><script>alert"));
        assert!(html.contains(r#"<\/script><script>alert(1)<\/script>"#));
        assert_eq!(html.matches("</script>").count(), 3);
        assert!(html.contains("data:text/javascript;base64,"));
        assert!(!html.contains("__DATA__") && !html.contains("__THREE_URL__"));
        assert!(html.len() > THREE.len(), "three.js is embedded");
    }

    #[test]
    fn a_frame_with_other_bodies_is_refused() {
        let mut replay = Replay::new("x", 0.01);
        replay.push(&scene("a", 0.0)).unwrap();
        let err = replay.push(&scene("b", 0.0)).unwrap_err();
        assert_eq!(
            err.to_string(),
            "replay frame 1: its 1 bodies are not the first frame's 1 (names and shapes must match)"
        );
        assert_eq!(replay.len(), 1);
    }
}
