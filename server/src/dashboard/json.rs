//! The dashboard API's JSON: the overview and scenes, written with `serde_json` and then
//! made inert as markup ([`inert`]): every `<`, `>` and `&` (they can only occur inside
//! strings, such as names from documents) becomes a `\u` escape.

use std::time::Duration;

use gymfleet_env::{Scene, SceneShape};
use serde_json::{json, Value};

use crate::registry::{Rates, Watched};

/// `value` as JSON text with `<`, `>` and `&` escaped, so that no name from a document
/// can read as markup wherever the text ends up.
pub(super) fn inert(value: &Value) -> String {
    let text = value.to_string();
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            c => out.push(c),
        }
    }
    out
}

/// A number of seconds as milliseconds, or `null`.
fn millis(seconds: Option<f64>) -> Value {
    seconds.map_or(Value::Null, |s| json!(s * 1e3))
}

/// One listed env or batch, with its rates (`null` until a window has passed).
pub(super) fn watched(entry: &Watched, rates: Option<Rates>) -> Value {
    let facts = entry.activity.facts();
    let counts = entry.activity.counts();
    json!({
        "id": entry.id,
        "n_envs": facts.n_envs,
        "action_dim": facts.action_dim,
        "observation_dim": facts.observation_dim,
        "dt": facts.dt,
        "max_steps": facts.max_steps,
        "keyframes": facts.keyframes,
        "sensors": facts.sensors.iter().map(|(name, kind, dim)| {
            json!({"name": name, "type": kind, "dim": dim})
        }).collect::<Vec<_>>(),
        "steps": counts.steps,
        "env_steps": counts.env_steps,
        "episodes": counts.episodes,
        "env_steps_per_s": rates.map(|r| r.env_steps_per_s),
        "steps_per_s": rates.map(|r| r.steps_per_s),
        "mean_step_ms": millis(rates.and_then(|r| r.mean_step_s)),
        "idle_s": entry.idle.as_secs_f64(),
    })
}

/// How long the pool's jobs wait, and how many there are.
pub(super) fn pool(
    threads: usize,
    stats: gymfleet_batch::JobQueueStats,
    jobs_per_s: Option<f64>,
    mean_wait: Option<Option<f64>>,
) -> Value {
    let total_wait = Duration::from_nanos(stats.waited_ns).as_secs_f64();
    let mean_wait_all = (stats.started > 0).then(|| total_wait / stats.started as f64);
    json!({
        "threads": threads,
        "queue_depth": stats.waiting,
        "jobs_started": stats.started,
        "jobs_per_s": jobs_per_s,
        "mean_wait_ms": millis(mean_wait.flatten()),
        "mean_wait_ms_since_start": millis(mean_wait_all),
    })
}

/// A shape as the HTML replay's renderer takes it (`client/src/replay.rs`).
fn shape(shape: &SceneShape) -> Value {
    match shape {
        SceneShape::Cuboid { half_extents } => json!({ "box": half_extents }),
        SceneShape::Cylinder {
            radius,
            half_height,
        } => json!({ "cylinder": [radius, half_height] }),
        SceneShape::Ball { radius } => json!({ "sphere": radius }),
        SceneShape::Capsule {
            radius,
            half_segment,
        } => json!({ "capsule": [radius, half_segment] }),
        SceneShape::Mesh {
            vertices,
            triangles,
        } => json!({ "mesh": [vertices.as_flattened(), triangles.as_flattened()] }),
    }
}

/// An env's scene: its bodies (each part, named after its instance), their poses
/// `[x, y, z, qw, qx, qy, qz]` (mm), the end effectors and a reach target.
pub(super) fn scene(id: &str, index: Option<usize>, scene: &Scene) -> Value {
    let name = |i: usize| scene.instance_names.get(i).map_or("", String::as_str);
    let bodies: Vec<Value> = scene
        .parts
        .iter()
        .map(|part| {
            json!({
                "name": name(part.instance),
                "instance": part.instance,
                "shape": shape(&part.shape),
            })
        })
        .collect();
    let poses: Vec<[f32; 7]> = scene
        .parts
        .iter()
        .map(|part| {
            let [x, y, z] = part.position;
            let [qw, qx, qy, qz] = part.rotation;
            [x, y, z, qw, qx, qy, qz]
        })
        .collect();
    json!({
        "id": id,
        "index": index,
        "bodies": bodies,
        "poses": poses,
        "end_effectors": scene.end_effectors,
        "target": scene.target,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markup_in_names_is_escaped() {
        let value = json!({ "name": "<script>alert(1)</script> & \"co\"" });
        let text = inert(&value);
        assert_eq!(
            text,
            r#"{"name":"\u003cscript\u003ealert(1)\u003c/script\u003e \u0026 \"co\""}"#
        );
        assert_eq!(serde_json::from_str::<Value>(&text).unwrap(), value);
    }
}
