//! The adapter over streamable HTTP (`--http 127.0.0.1:0`): it prints its bound URL on
//! stderr, and rmcp's streamable-HTTP client drives the same tools through it.

use std::process::Stdio;

use rmcp::transport::StreamableHttpClientTransport;
use rmcp::ServiceExt;
use serde_json::json;
use tokio::io::{AsyncBufReadExt, BufReader};

use crate::{adapter_command, call, doc, expect_err, expect_ok, PENDULUM};

/// Starts the adapter with `args` (which include `--http`) and returns it with the URL
/// it printed.
async fn spawn_http(args: &[&str]) -> (tokio::process::Child, String) {
    let mut child = adapter_command(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn gymfleet-mcp --http");
    let mut lines = BufReader::new(child.stderr.take().expect("stderr")).lines();
    let url = loop {
        let line = lines
            .next_line()
            .await
            .expect("read stderr")
            .expect("the adapter printed its URL before exiting");
        if let Some(url) = line.strip_prefix("gymfleet-mcp: listening on ") {
            break url.to_string();
        }
    };
    assert!(
        url.starts_with("http://127.0.0.1:") && url.ends_with("/mcp"),
        "{url}"
    );
    // Keep draining stderr so the child never blocks on it.
    tokio::spawn(async move { while let Ok(Some(_)) = lines.next_line().await {} });
    (child, url)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_http_token_guards_the_adapter_and_a_server_token_reaches_the_server() {
    use rmcp::transport::streamable_http_client::StreamableHttpClientTransportConfig;

    const HTTP_TOKEN: &str = "mcp-http-secret-0123456789";
    const SERVER_TOKEN: &str = "agents-token-0123456789";
    let tokens = gymfleet_server::TokenTable::parse(&format!("agents {SERVER_TOKEN}")).unwrap();
    let server = crate::TestServer::start_with(gymfleet_server::ServerConfig {
        threads: 1,
        auth_tokens: Some(std::sync::Arc::new(tokens)),
        ..gymfleet_server::ServerConfig::default()
    })
    .await;
    let addr = server.addr();
    let (mut child, url) = spawn_http(&[
        "--http",
        "127.0.0.1:0",
        "--http-token",
        HTTP_TOKEN,
        "--server",
        &addr,
        "--token",
        SERVER_TOKEN,
    ])
    .await;

    // Without the token, or with another, the adapter answers 401 and no session starts.
    for token in [None, Some("wrong-token")] {
        let mut config = StreamableHttpClientTransportConfig::with_uri(url.clone());
        if let Some(token) = token {
            config = config.auth_header(token);
        }
        let refused = ().serve(StreamableHttpClientTransport::from_config(config)).await;
        assert!(refused.is_err(), "a session without the token ({token:?})");
    }

    let config = StreamableHttpClientTransportConfig::with_uri(url).auth_header(HTTP_TOKEN);
    let session =
        ().serve(StreamableHttpClientTransport::from_config(config))
            .await
            .expect("MCP initialize with the token");
    let created = expect_ok(
        "create_robot_env",
        call(
            &session,
            "create_robot_env",
            json!({"document": doc(PENDULUM), "end_effector_ids": ["arm"]}),
        )
        .await,
    );
    assert_eq!(created["observation_dim"], json!(9));
    // The env is the tenant's, on the server that requires the token.
    let tenant = gymfleet_client::Client::builder(addr.clone())
        .token(SERVER_TOKEN)
        .connect()
        .await
        .expect("connect as the tenant");
    let info = tenant.server_info().await.expect("info");
    assert_eq!((info.tenant.as_str(), info.envs), ("agents", 1));
    session.cancel().await.expect("close the HTTP session");
    child.start_kill().expect("stop the adapter");
    child.wait().await.expect("adapter exited");
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tools_over_streamable_http() {
    let mut args = vec!["--http", "127.0.0.1:0"];
    if cfg!(feature = "embedded") {
        args.extend(["--threads", "1"]);
    }
    let server = if cfg!(feature = "embedded") {
        None
    } else {
        Some(crate::TestServer::start().await)
    };
    let server_addr = server.as_ref().map(|s| s.addr());
    if let Some(addr) = &server_addr {
        args.extend(["--server", addr.as_str()]);
    }
    let (mut child, url) = spawn_http(&args).await;

    let session =
        ().serve(StreamableHttpClientTransport::from_uri(url))
            .await
            .expect("MCP initialize over HTTP");
    let tools = session.list_all_tools().await.expect("tools/list");
    assert_eq!(tools.len(), 13);
    let created = expect_ok(
        "create_robot_env",
        call(
            &session,
            "create_robot_env",
            json!({"document": doc(PENDULUM), "end_effector_ids": ["arm"]}),
        )
        .await,
    );
    assert_eq!(created["observation_dim"], json!(9));
    let env_id = created["env_id"].as_str().expect("env_id").to_string();
    let step = expect_ok(
        "gym_step",
        call(
            &session,
            "gym_step",
            json!({"env_id": env_id, "action_type": "torque", "values": [2.0]}),
        )
        .await,
    );
    assert_eq!(step["done"], json!(false));
    let err = expect_err(
        "gym_step",
        call(
            &session,
            "gym_step",
            json!({"env_id": env_id, "action_type": "torque", "values": [1, 2]}),
        )
        .await,
    );
    assert_eq!(
        err,
        format!("{env_id} expects 1 action value (action_dim), got 2")
    );
    expect_ok(
        "gym_close",
        call(&session, "gym_close", json!({"env_id": env_id})).await,
    );
    session.cancel().await.expect("close the HTTP session");

    child.start_kill().expect("stop the adapter");
    child.wait().await.expect("adapter exited");
    if let Some(server) = server {
        server.stop().await;
    }
}
