//! The server behind the dashboard's browser test (`tests/browser/dashboard.test.mjs`):
//! a gymfleet server on loopback with auth on and the dashboard on a free port, where
//! tenant `team-a` holds a batch of four pendulums whose arm is named
//! `<script>alert(1)</script>` (with a keyframe and a sensor) and tenant `team-b` a batch of
//! arms.
//!
//! ```sh
//! cargo run -p gymfleet-e2e --example dashboard_fixture
//! ```
//!
//! It prints one JSON line (`url`, `token`, `other_token`, `batch`, `other_batch`), then
//! reads commands from stdin: `step N` steps team-a's batch N times (a push, then a free
//! swing) and answers `stepped TOTAL`; the end of its input stops the server. `cargo test`
//! builds it (as it builds every example), so `.ci/run` finds it in `target/debug/examples`.

use std::io::BufRead;
use std::sync::Arc;

use gymfleet_client::{ActionType, BatchOptions, Client};
use gymfleet_e2e::{ARM2, PENDULUM};
use gymfleet_server::{LocalServer, ServerConfig, TokenTable};

const TOKEN: &str = "team-a-browser-0123456789";
const OTHER_TOKEN: &str = "team-b-browser-0123456789";
const HOSTILE: &str = "<script>alert(1)</script>";
const N_ENVS: usize = 4;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()?;
    let tokens = TokenTable::parse(&format!("team-a {TOKEN}\nteam-b {OTHER_TOKEN}\n"))?;
    // The other tenant's batch stays open as long as the server.
    let (server, batch, _other) = runtime.block_on(async {
        let server = LocalServer::start(ServerConfig {
            threads: 2,
            auth_tokens: Some(Arc::new(tokens)),
            dashboard_listen: Some(([127, 0, 0, 1], 0).into()),
            ..ServerConfig::default()
        })
        .await?;
        let connect = |token: &str| Client::builder(server.client_addr()).token(token).connect();
        let (mine, theirs) = (connect(TOKEN).await?, connect(OTHER_TOKEN).await?);
        let mut document: serde_json::Value = serde_json::from_str(PENDULUM)?;
        // A keyframe and a sensor for the page to list.
        document["assembly"]["joints"][0]["name"] = "hinge".into();
        document["assembly"]["keyframes"] =
            serde_json::json!([{"name": "raised", "positions": {"hinge": 30}}]);
        document["assembly"]["sensors"] =
            serde_json::json!([{"name": "angle", "type": "jointpos", "joint": "hinge"}]);
        let document = document
            .to_string()
            .replace("\"arm\"", &serde_json::to_string(HOSTILE)?);
        let batch = mine
            .create_batch(BatchOptions::new(document, N_ENVS).end_effectors([HOSTILE]))
            .await?;
        let other = theirs.create_batch(BatchOptions::new(ARM2, 2)).await?;
        let dashboard = server.dashboard_addr().ok_or("the dashboard is off")?;
        println!(
            "{}",
            serde_json::json!({
                "url": format!("http://{dashboard}/"),
                "token": TOKEN,
                "other_token": OTHER_TOKEN,
                "batch": batch.id(),
                "other_batch": other.id(),
            })
        );
        Ok::<_, Box<dyn std::error::Error>>((server, batch, other))
    })?;

    let mut stepped = 0usize;
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        let Some(n) = line
            .strip_prefix("step ")
            .and_then(|n| n.trim().parse().ok())
        else {
            eprintln!("dashboard_fixture: expected `step N`, got {line:?}");
            continue;
        };
        runtime.block_on(async {
            for i in 0..n {
                let torque = if stepped + i < 10 { 2e-4 } else { 0.0 };
                batch.step(ActionType::Torque, &[torque; N_ENVS]).await?;
            }
            Ok::<_, gymfleet_client::ClientError>(())
        })?;
        stepped += n;
        println!("stepped {stepped}");
    }
    runtime.block_on(server.stop())?;
    Ok(())
}
