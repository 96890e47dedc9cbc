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

/// The adapter on HTTP without a token: with its embedded server (`embedded` feature),
/// or against a test server started here (returned, to stop at the end).
async fn spawn_plain_http() -> (tokio::process::Child, String, Option<crate::TestServer>) {
    let server = if cfg!(feature = "embedded") {
        None
    } else {
        Some(crate::TestServer::start().await)
    };
    let mut args: Vec<String> = vec!["--http".into(), "127.0.0.1:0".into()];
    match &server {
        None => args.extend(["--threads".into(), "1".into()]),
        Some(s) => args.extend(["--server".into(), s.addr()]),
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (child, url) = spawn_http(&args).await;
    (child, url, server)
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
    let (mut child, url, server) = spawn_plain_http().await;

    let session =
        ().serve(StreamableHttpClientTransport::from_uri(url))
            .await
            .expect("MCP initialize over HTTP");
    let tools = session.list_all_tools().await.expect("tools/list");
    assert_eq!(tools.len(), 14);
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

/// Sends one HTTP/1.1 request to the adapter at `url` and returns the status code and the
/// headers (lower-cased names); the body is not read.
async fn http_request(
    url: &str,
    method: &str,
    headers: &[(&str, &str)],
    body: &str,
) -> (u16, Vec<(String, String)>) {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let authority = url
        .strip_prefix("http://")
        .and_then(|rest| rest.split('/').next())
        .expect("an http URL");
    let mut stream = tokio::net::TcpStream::connect(authority)
        .await
        .expect("connect to the adapter");
    let mut request = format!(
        "{method} /mcp HTTP/1.1\r\nhost: {authority}\r\ncontent-length: {}\r\nconnection: close\r\n",
        body.len()
    );
    for (name, value) in headers {
        request.push_str(&format!("{name}: {value}\r\n"));
    }
    request.push_str("\r\n");
    request.push_str(body);
    stream.write_all(request.as_bytes()).await.expect("send");
    // The headers end at the first blank line; an SSE body may stay open, so stop there.
    let mut head = Vec::new();
    let mut byte = [0u8; 1];
    while !head.ends_with(b"\r\n\r\n") {
        let n = stream.read(&mut byte).await.expect("read the answer");
        assert!(n == 1, "the connection closed in the headers");
        head.push(byte[0]);
    }
    let text = String::from_utf8(head).expect("ASCII headers");
    let mut lines = text.split("\r\n");
    let status = lines
        .next()
        .and_then(|l| l.split(' ').nth(1))
        .and_then(|c| c.parse().ok())
        .expect("a status line");
    let headers = lines
        .filter_map(|l| l.split_once(':'))
        .map(|(n, v)| (n.trim().to_ascii_lowercase(), v.trim().to_string()))
        .collect();
    (status, headers)
}

/// Ending a session with `DELETE` is answered 204 No Content (MCP clients take 200 or 204
/// as ended; rmcp's own answer, 202, makes the official Python SDK warn), and the session
/// is gone afterwards.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn ending_a_session_with_delete_answers_no_content() {
    let (mut child, url, server) = spawn_plain_http().await;
    let initialize = json!({
        "jsonrpc": "2.0", "id": 1, "method": "initialize",
        "params": {"protocolVersion": "2025-03-26", "capabilities": {},
                   "clientInfo": {"name": "raw-http", "version": "0"}}
    })
    .to_string();
    let json_and_sse = [
        ("content-type", "application/json"),
        ("accept", "application/json, text/event-stream"),
    ];
    let (status, headers) = http_request(&url, "POST", &json_and_sse, &initialize).await;
    assert_eq!(status, 200, "{headers:?}");
    let session = headers
        .iter()
        .find(|(n, _)| n == "mcp-session-id")
        .map(|(_, v)| v.clone())
        .expect("a session id");
    let (status, _) = http_request(&url, "DELETE", &[("mcp-session-id", &session)], "").await;
    assert_eq!(status, 204, "the session's end");
    // The session is gone: a request in it is refused.
    let ping = json!({"jsonrpc": "2.0", "id": 2, "method": "ping"}).to_string();
    let mut in_session = json_and_sse.to_vec();
    in_session.push(("mcp-session-id", &session));
    let (status, _) = http_request(&url, "POST", &in_session, &ping).await;
    assert!(status >= 400, "a request in an ended session: {status}");
    child.start_kill().expect("stop the adapter");
    child.wait().await.expect("adapter exited");
    if let Some(server) = server {
        server.stop().await;
    }
}
