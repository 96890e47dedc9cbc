//! End-to-end tests of the `gymfleet-mcp` binary: each test spawns it and drives it with
//! rmcp's real MCP client, over stdio (`TokioChildProcess`) or streamable HTTP. The child
//! uses its own embedded server unless a test starts a gymfleet server itself and points
//! the child at it with `--server`. One test binary, one module per area.

mod batches;
mod errors;
mod http;
mod imports;
mod remote;
mod render;
mod states;
mod tools;
mod walkthrough;

use std::process::Stdio;

use rmcp::model::{CallToolRequestParams, CallToolResult};
use rmcp::service::RunningService;
use rmcp::transport::TokioChildProcess;
use rmcp::{RoleClient, ServiceExt};
use serde_json::Value;
use tokio::process::Command;

/// The seed's 1-DOF pendulum (end effector `"arm"`).
const PENDULUM: &str = include_str!("../../../../models/pendulum.json");
/// The seed's 2-DOF arm (end effector `"forearm"`).
const ARM2: &str = include_str!("../../../../models/arm2.json");

/// A document as the JSON object an agent would pass.
fn doc(text: &str) -> Value {
    serde_json::from_str(text).expect("model JSON")
}

/// The adapter binary with quiet logs and no `GYMFLEET_*` settings from the environment.
fn adapter_command(args: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_gymfleet-mcp"));
    for (key, _) in std::env::vars() {
        if key.starts_with("GYMFLEET_") {
            cmd.env_remove(key);
        }
    }
    cmd.args(["--log", "warn"]).args(args).kill_on_drop(true);
    cmd
}

/// A running adapter child and the MCP client session talking to it.
struct Adapter {
    session: RunningService<RoleClient, ()>,
    /// The server a test started for it, when the build has no embedded server.
    _server: Option<TestServer>,
}

impl Adapter {
    /// The adapter on its own: its embedded server (or, in a build without the
    /// `embedded` feature, a test server given with `--server`).
    async fn embedded() -> Adapter {
        if cfg!(feature = "embedded") {
            Self::spawn(&["--threads", "1"]).await
        } else {
            let server = TestServer::start().await;
            let addr = server.addr();
            let mut adapter = Self::spawn(&["--server", &addr]).await;
            adapter._server = Some(server);
            adapter
        }
    }

    /// The adapter with `args`, over stdio.
    async fn spawn(args: &[&str]) -> Adapter {
        let (transport, _) = TokioChildProcess::builder(adapter_command(args))
            .stderr(Stdio::inherit())
            .spawn()
            .expect("spawn gymfleet-mcp");
        let session = ().serve(transport).await.expect("MCP initialize");
        Adapter {
            session,
            _server: None,
        }
    }

    /// Calls `tool` with `args` (a JSON object); protocol errors fail the test.
    async fn call(&self, tool: &str, args: Value) -> CallToolResult {
        call(&self.session, tool, args).await
    }

    /// Calls `tool`, expects success, and returns its structured content (checked to be
    /// the same JSON as its text content).
    async fn ok(&self, tool: &str, args: Value) -> Value {
        expect_ok(tool, self.call(tool, args).await)
    }

    /// Calls `tool`, expects a tool error, and returns its message.
    async fn err(&self, tool: &str, args: Value) -> String {
        expect_err(tool, self.call(tool, args).await)
    }

    /// Closes stdin and waits for the child to exit.
    async fn stop(self) {
        self.session.cancel().await.expect("MCP session shutdown");
    }
}

async fn call(session: &RunningService<RoleClient, ()>, tool: &str, args: Value) -> CallToolResult {
    let Value::Object(args) = args else {
        panic!("tool arguments must be an object: {args}");
    };
    session
        .call_tool(CallToolRequestParams::new(tool.to_string()).with_arguments(args))
        .await
        .unwrap_or_else(|e| panic!("{tool}: protocol error {e}"))
}

/// The result's text content, which must be exactly one text block.
fn text_of(tool: &str, result: &CallToolResult) -> String {
    assert_eq!(result.content.len(), 1, "{tool}: {result:?}");
    result.content[0]
        .as_text()
        .unwrap_or_else(|| panic!("{tool}: not text: {result:?}"))
        .text
        .clone()
}

#[track_caller]
fn expect_ok(tool: &str, result: CallToolResult) -> Value {
    let text = text_of(tool, &result);
    assert_ne!(result.is_error, Some(true), "{tool} failed: {text}");
    let structured = result
        .structured_content
        .unwrap_or_else(|| panic!("{tool}: no structured content"));
    let parsed: Value = serde_json::from_str(&text).expect("text content is JSON");
    assert_eq!(
        parsed, structured,
        "{tool}: text and structured content differ"
    );
    structured
}

#[track_caller]
fn expect_err(tool: &str, result: CallToolResult) -> String {
    let text = text_of(tool, &result);
    assert_eq!(
        result.is_error,
        Some(true),
        "{tool} should have failed: {text}"
    );
    text
}

/// Every number in `value`, depth first.
fn numbers(value: &Value, out: &mut Vec<f64>) {
    match value {
        Value::Number(n) => out.push(n.as_f64().expect("finite")),
        Value::Array(items) => items.iter().for_each(|v| numbers(v, out)),
        Value::Object(map) => map.values().for_each(|v| numbers(v, out)),
        _ => {}
    }
}

/// Asserts that every number of `value` is printed in the shortest form of the `f32`
/// the server sent (no `10.041999816894531` for `10.042`).
#[track_caller]
fn assert_clean_numbers(value: &Value) {
    let mut all = Vec::new();
    numbers(value, &mut all);
    assert!(!all.is_empty());
    for x in all {
        let shortest: f64 = format!("{}", x as f32).parse().expect("float");
        assert_eq!(
            x, shortest,
            "{x} is not the shortest form of an f32 in {value}"
        );
    }
}

/// The `f64`s of a JSON array.
#[track_caller]
fn floats(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .unwrap_or_else(|| panic!("not an array: {value}"))
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect()
}

/// Asserts that `a` and `b` agree within `tol`, element by element.
#[track_caller]
fn assert_close(a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= tol, "{a:?} vs {b:?} (tol {tol})");
    }
}

/// A gymfleet server started by the test itself, on 127.0.0.1:0.
struct TestServer {
    server: gymfleet_server::LocalServer,
}

impl TestServer {
    async fn start() -> TestServer {
        Self::start_with(gymfleet_server::ServerConfig {
            threads: 1,
            ..gymfleet_server::ServerConfig::default()
        })
        .await
    }

    async fn start_with(config: gymfleet_server::ServerConfig) -> TestServer {
        let server = gymfleet_server::LocalServer::start(config)
            .await
            .expect("start a server on 127.0.0.1:0");
        TestServer { server }
    }

    /// The address clients connect to.
    fn addr(&self) -> String {
        self.server.client_addr()
    }

    /// How many single envs and batch envs the server holds.
    async fn held(&self) -> (u64, u64) {
        let client = gymfleet_client::Client::connect(self.addr())
            .await
            .expect("connect to the test server");
        let info = client.server_info().await.expect("server info");
        (info.envs, info.batch_envs)
    }

    async fn stop(self) {
        self.server.stop().await.expect("clean shutdown");
    }
}
