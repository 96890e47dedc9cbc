//! The MCP adapter's door (issue R2): the bytes as the lines an MCP client writes after
//! the handshake, through the adapter's own session ([`gymfleet_mcp::serve_session`]:
//! rmcp's JSON-RPC handling and the gym tools) over an in-memory pipe, against a gymfleet
//! server on loopback. Shared by the libFuzzer binary and `tests/tests/fuzz_corpora.rs`.
//!
//! Each session starts fresh (the adapter's ids start at `sim_1` and `batch_1`, so a
//! corpus entry can create an env and then step it) and closes what it created. Asserts:
//! every line that rmcp reads as a request is answered within [`REPLY_WITHIN`] (no hang), every answer is JSON-RPC
//! 2.0, and error messages (JSON-RPC errors and tool errors) stay under their bound.

use std::sync::OnceLock;
use std::time::Duration;

use gymfleet_server::{LocalServer, ServerConfig};
use rmcp::model::ClientJsonRpcMessage;
use serde_json::{json, Value};
use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader};

use crate::targets::{Reached, MAX_ERROR_BYTES};

/// Longest wait for the answer to one request.
pub const REPLY_WITHIN: Duration = Duration::from_secs(10);

/// One gymfleet server for every input of a process, with small limits so that no input
/// can ask for much work.
struct Harness {
    runtime: tokio::runtime::Runtime,
    addr: String,
    _server: LocalServer,
}

fn harness() -> &'static Harness {
    static HARNESS: OnceLock<Harness> = OnceLock::new();
    HARNESS.get_or_init(|| {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .expect("a tokio runtime");
        let config = ServerConfig {
            threads: 1,
            max_envs: 256,
            max_batch_size: 64,
            ..ServerConfig::default()
        };
        let server = runtime
            .block_on(LocalServer::start(config))
            .expect("a loopback server");
        Harness {
            runtime,
            addr: server.client_addr(),
            _server: server,
        }
    })
}

fn message_bound(text: &str, what: &str) {
    assert!(
        text.len() <= MAX_ERROR_BYTES,
        "{what} of {} bytes: {}…",
        text.len(),
        text.chars().take(200).collect::<String>()
    );
}

/// Checks one answer and says how far its request got.
fn answer(reply: &Value) -> Reached {
    assert_eq!(reply["jsonrpc"], "2.0", "not JSON-RPC 2.0: {reply}");
    if let Some(error) = reply.get("error") {
        message_bound(&error["message"].to_string(), "a JSON-RPC error");
        return Reached::Validation;
    }
    let result = &reply["result"];
    if result["isError"] == true {
        message_bound(&result["content"].to_string(), "a tool error");
        Reached::Validation
    } else {
        Reached::Stepping
    }
}

/// The client's side of one session: writes lines, reads answers.
struct Session<R, W> {
    lines: tokio::io::Lines<BufReader<R>>,
    write: W,
}

impl<R: tokio::io::AsyncRead + Unpin, W: tokio::io::AsyncWrite + Unpin> Session<R, W> {
    /// Writes `line`; `false` when the session has ended.
    async fn send(&mut self, line: &[u8]) -> bool {
        self.write.write_all(line).await.is_ok() && self.write.write_all(b"\n").await.is_ok()
    }

    /// The answer with `id`, skipping the server's notifications; `None` when the session
    /// ended first. Panics after [`REPLY_WITHIN`].
    async fn answer_to(&mut self, id: &Value) -> Option<Value> {
        let wait = async {
            while let Ok(Some(line)) = self.lines.next_line().await {
                let reply: Value = serde_json::from_str(&line).unwrap_or_else(|e| {
                    panic!("the adapter wrote a line that is not JSON ({e}): {line}")
                });
                if reply.get("id") == Some(id) && reply.get("method").is_none() {
                    return Some(reply);
                }
            }
            None
        };
        tokio::time::timeout(REPLY_WITHIN, wait)
            .await
            .unwrap_or_else(|_| panic!("no answer to request {id} within {REPLY_WITHIN:?}"))
    }
}

/// One MCP session: the handshake, then each line of `data` as a message; each request
/// (a JSON object with `id` and `method`) waits for its answer.
pub fn mcp_message(data: &[u8]) -> Reached {
    let h = harness();
    h.runtime.block_on(async {
        let (ours, theirs) = tokio::io::duplex(1 << 20);
        let settings = gymfleet_client::Client::builder("");
        let served = tokio::spawn(gymfleet_mcp::serve_session(
            vec![h.addr.clone()],
            settings,
            theirs,
        ));
        let (read, write) = tokio::io::split(ours);
        let mut session = Session {
            lines: BufReader::new(read).lines(),
            write,
        };
        let initialize = json!({"jsonrpc": "2.0", "id": 0, "method": "initialize", "params": {
            "protocolVersion": "2025-06-18", "capabilities": {},
            "clientInfo": {"name": "gymfleet-fuzz", "version": "0"}}});
        assert!(session.send(initialize.to_string().as_bytes()).await);
        let ready = session.answer_to(&json!(0)).await;
        assert!(
            ready.is_some_and(|r| r.get("result").is_some()),
            "initialize failed"
        );
        let initialized = json!({"jsonrpc": "2.0", "method": "notifications/initialized"});
        assert!(session.send(initialized.to_string().as_bytes()).await);

        let mut reached = Reached::Parsing;
        for line in data.split(|&b| b == b'\n') {
            // A request as rmcp reads one must be answered; rmcp drops other lines
            // (malformed JSON-RPC gets no "invalid request" error from it).
            let request = matches!(
                serde_json::from_slice::<ClientJsonRpcMessage>(line),
                Ok(ClientJsonRpcMessage::Request(_))
            );
            if !session.send(line).await {
                break;
            }
            if !request {
                continue;
            }
            let Some(id) = serde_json::from_slice::<Value>(line)
                .ok()
                .and_then(|m| m.get("id").cloned())
            else {
                continue;
            };
            let id = &id;
            match session.answer_to(id).await {
                Some(reply) => reached = reached.max(answer(&reply)),
                None => break,
            }
        }
        drop(session);
        let ended = tokio::time::timeout(REPLY_WITHIN, served).await;
        assert!(
            ended.is_ok(),
            "the session did not end when its client left"
        );
        reached
    })
}
