//! The dashboard (`--dashboard-listen`): its page and JSON API over plain HTTP, as a
//! browser uses them. What an operator must be able to trust: it is off loopback only with
//! auth; a tenant sees only its own envs and batches, and nothing without a session; the
//! token is taken once and kept as an HttpOnly, SameSite=Strict session cookie; names
//! from documents come out escaped; counts and rates are right; watching an env does not
//! keep it from being reclaimed. (`tests/browser/dashboard.test.mjs` drives the page in
//! headless Chromium.)

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use gymfleet_client::{ActionType, Autoreset, BatchOptions, Client, EnvOptions};
use gymfleet_e2e::{ARM2, PENDULUM};
use gymfleet_server::{Clock, LocalServer, ServerConfig, TokenTable};
use serde_json::Value;

const TOKEN_A: &str = "team-a-dashboard-0123456789";
const TOKEN_B: &str = "team-b-dashboard-0123456789";
/// An instance name a document may well carry.
const HOSTILE: &str = "<script>alert(1)</script>";
const NOT_LOGGED_IN: &str = "not logged in: this server requires a token; POST it to \
     /api/login as {\"token\": \"…\"} (a session lasts 12 hours)";

/// The seed's pendulum with its arm named [`HOSTILE`].
fn hostile_pendulum() -> String {
    let name = serde_json::to_string(HOSTILE).unwrap();
    PENDULUM.replace("\"arm\"", &name)
}

fn tokens() -> Arc<TokenTable> {
    let text = format!("team-a {TOKEN_A}\nteam-b {TOKEN_B}\n");
    Arc::new(TokenTable::parse(&text).expect("token file"))
}

/// A server with the dashboard on a free loopback port, and that port.
async fn start(config: ServerConfig) -> (LocalServer, SocketAddr) {
    let server = LocalServer::start(ServerConfig {
        threads: 2,
        dashboard_listen: Some(([127, 0, 0, 1], 0).into()),
        ..config
    })
    .await
    .expect("start a server with a dashboard");
    let dashboard = server.dashboard_addr().expect("the dashboard is on");
    assert_ne!(dashboard.port(), 0, "the bound port is known");
    (server, dashboard)
}

async fn client(server: &LocalServer, token: Option<&str>) -> Client {
    let builder = Client::builder(server.client_addr());
    let builder = match token {
        Some(token) => builder.token(token),
        None => builder,
    };
    builder.connect().await.expect("connect")
}

/// An HTTP answer.
#[derive(Debug)]
struct Reply {
    status: u16,
    headers: Vec<(String, String)>,
    body: String,
}

impl Reply {
    fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }

    #[track_caller]
    fn json(&self) -> Value {
        serde_json::from_str(&self.body).unwrap_or_else(|e| panic!("{e}: {}", self.body))
    }

    /// The `{"error": …}` of a refusal with `status`.
    #[track_caller]
    fn error(&self, status: u16) -> String {
        assert_eq!(self.status, status, "{}", self.body);
        assert_eq!(self.header("content-type"), Some("application/json"));
        self.json()["error"].as_str().expect("an error").to_string()
    }
}

/// One HTTP/1.0 request (the connection closes after the answer). `headers` may set
/// `Host`; by default it is the dashboard's address.
async fn http(
    addr: SocketAddr,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
    body: &str,
) -> Reply {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let mut request = format!("{method} {path} HTTP/1.0\r\n");
    if !headers.iter().any(|(n, _)| n.eq_ignore_ascii_case("host")) {
        request.push_str(&format!("Host: {addr}\r\n"));
    }
    for (name, value) in headers {
        request.push_str(&format!("{name}: {value}\r\n"));
    }
    request.push_str(&format!("Content-Length: {}\r\n\r\n{body}", body.len()));
    let mut stream = tokio::net::TcpStream::connect(addr)
        .await
        .expect("dashboard");
    stream.write_all(request.as_bytes()).await.unwrap();
    let mut reply = Vec::new();
    stream.read_to_end(&mut reply).await.unwrap();
    let reply = String::from_utf8(reply).expect("utf-8");
    let (head, body) = reply.split_once("\r\n\r\n").expect("headers end");
    let mut lines = head.lines();
    let status = lines
        .next()
        .unwrap()
        .split(' ')
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    let headers = lines
        .filter_map(|l| l.split_once(": "))
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    Reply {
        status,
        headers,
        body: body.to_string(),
    }
}

async fn get(addr: SocketAddr, path: &str, cookie: Option<&str>) -> Reply {
    match cookie {
        Some(cookie) => http(addr, "GET", path, &[("Cookie", cookie)], "").await,
        None => http(addr, "GET", path, &[], "").await,
    }
}

async fn login(addr: SocketAddr, token: &str) -> Reply {
    let body = serde_json::json!({ "token": token }).to_string();
    let json = [("Content-Type", "application/json")];
    http(addr, "POST", "/api/login", &json, &body).await
}

/// Logs in with `token`: the cookie to send (`gymfleet_dashboard=<id>`).
async fn session(addr: SocketAddr, token: &str) -> String {
    let reply = login(addr, token).await;
    assert_eq!(reply.status, 200, "{}", reply.body);
    let cookie = reply.header("set-cookie").expect("a session cookie");
    cookie.split(';').next().unwrap().to_string()
}

/// The ids listed under `kind` (`envs` or `batches`) of an overview.
fn ids(overview: &Value, kind: &str) -> Vec<String> {
    overview[kind]["items"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["id"].as_str().unwrap().to_string())
        .collect()
}

fn item<'a>(overview: &'a Value, kind: &str, id: &str) -> &'a Value {
    overview[kind]["items"]
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["id"] == id)
        .unwrap_or_else(|| panic!("{id} not listed in {overview}"))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_dashboard_off_loopback_is_refused_without_auth() {
    for addr in ["0.0.0.0:0", "[::]:0"] {
        let err = LocalServer::start(ServerConfig {
            dashboard_listen: Some(addr.parse().unwrap()),
            ..ServerConfig::default()
        })
        .await
        .expect_err("refused");
        assert_eq!(
            err.to_string(),
            format!(
                "cannot listen on {addr}: a dashboard on an address other than loopback needs \
                 --auth-tokens (GYMFLEET_AUTH_TOKENS): without tokens, anyone who reaches the \
                 port sees every env; serve it on 127.0.0.1 (through an SSH tunnel, say) or \
                 turn auth on"
            )
        );
    }
    let off = LocalServer::start(ServerConfig::default()).await.unwrap();
    assert_eq!(off.dashboard_addr(), None, "off by default");
    off.stop().await.unwrap();
    // A port already taken is named with the system's reason.
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = taken.local_addr().unwrap();
    let err = LocalServer::start(ServerConfig {
        dashboard_listen: Some(addr),
        ..ServerConfig::default()
    })
    .await
    .expect_err("the port is taken");
    let message = err.to_string();
    assert!(
        message.starts_with(&format!("cannot listen on {addr}: ")) && message.contains("in use"),
        "{message}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_and_its_files_come_from_the_server_itself() {
    let (server, addr) = start(ServerConfig::default()).await;
    let page = get(addr, "/", None).await;
    assert_eq!(page.status, 200);
    assert_eq!(
        page.header("content-type"),
        Some("text/html; charset=utf-8")
    );
    let policy = page.header("content-security-policy").expect("a policy");
    assert!(
        policy.contains("default-src 'none'; script-src 'self'"),
        "{policy}"
    );
    assert_eq!(page.header("x-content-type-options"), Some("nosniff"));
    assert_eq!(page.header("x-frame-options"), Some("DENY"));
    assert!(page
        .body
        .contains(r#"<script type="module" src="/assets/dashboard.js">"#));
    for (path, needle) in [
        (
            "/assets/dashboard.js",
            "import { SceneView } from './viewer.js';",
        ),
        ("/assets/viewer.js", "import * as THREE from './three.js';"),
        ("/assets/OrbitControls.js", "} from './three.js';"),
        ("/assets/three.js", "const t=\"170\""),
        ("/assets/dashboard.css", "#view"),
        ("/assets/icon.svg", "<svg"),
        ("/assets/three-LICENSE.txt", "MIT"),
    ] {
        let file = get(addr, path, None).await;
        assert_eq!(file.status, 200, "{path}");
        assert!(file.body.contains(needle), "{path} lacks {needle:?}");
    }
    let missing = get(addr, "/assets/missing.js", None).await;
    assert_eq!(
        missing.error(404),
        "no such page: GET \"/assets/missing.js\""
    );
    server.stop().await.expect("clean shutdown");
    assert!(
        tokio::net::TcpStream::connect(addr).await.is_err(),
        "the dashboard stopped with the server"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn without_auth_it_answers_only_requests_addressed_to_loopback() {
    let (server, addr) = start(ServerConfig::default()).await;
    let info = get(addr, "/api/session", None).await.json();
    assert_eq!(
        info,
        serde_json::json!({ "auth": false, "logged_in": true, "tenant": "" })
    );
    for host in ["localhost:8080", "127.0.0.1", "[::1]:1"] {
        let reply = http(addr, "GET", "/api/overview", &[("Host", host)], "").await;
        assert_eq!(reply.status, 200, "{host}: {}", reply.body);
    }
    // A site that rebinds its own name to 127.0.0.1 gets nothing.
    let rebound = http(
        addr,
        "GET",
        "/api/overview",
        &[("Host", "evil.example:80")],
        "",
    )
    .await;
    assert_eq!(
        rebound.error(403),
        "this dashboard runs without --auth-tokens, so it answers only requests addressed to \
         this machine's loopback (localhost, 127.0.0.1, [::1]); got Host: \"evil.example:80\""
    );
    assert_eq!(
        login(addr, TOKEN_A).await.error(400),
        "this server runs without --auth-tokens: there is nothing to log in to"
    );
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn with_auth_a_session_cookie_shows_its_tenant_only() {
    let (server, addr) = start(ServerConfig {
        auth_tokens: Some(tokens()),
        ..ServerConfig::default()
    })
    .await;
    let a = client(&server, Some(TOKEN_A)).await;
    let b = client(&server, Some(TOKEN_B)).await;
    let a_batch = a
        .create_batch(BatchOptions::new(ARM2, 3))
        .await
        .expect("batch");
    let a_env = a.create_env(EnvOptions::new(PENDULUM)).await.expect("env");
    let b_batch = b
        .create_batch(BatchOptions::new(ARM2, 2))
        .await
        .expect("batch");
    let a_scene = format!("/api/batches/{}/envs/0/scene", a_batch.id());
    let b_scene = format!("/api/batches/{}/envs/0/scene", b_batch.id());

    // No session: nothing but the page and the question.
    assert_eq!(
        get(addr, "/api/session", None).await.json(),
        serde_json::json!({ "auth": true, "logged_in": false, "tenant": null })
    );
    for path in ["/api/overview", a_scene.as_str()] {
        assert_eq!(get(addr, path, None).await.error(401), NOT_LOGGED_IN);
        let forged = get(addr, path, Some("gymfleet_dashboard=0123abcd")).await;
        assert_eq!(forged.error(401), NOT_LOGGED_IN);
        let token_as_cookie = format!("gymfleet_dashboard={TOKEN_A}");
        let reply = get(addr, path, Some(&token_as_cookie)).await;
        assert_eq!(reply.error(401), NOT_LOGGED_IN, "a token is not a session");
    }
    let wrong = login(addr, "team-a-dashboard-XXXXXXXXXX").await;
    assert_eq!(wrong.error(401), "unknown token");
    assert_eq!(wrong.header("set-cookie"), None);
    let body = serde_json::json!({ "token": TOKEN_A }).to_string();
    let plain = http(
        addr,
        "POST",
        "/api/login",
        &[("Content-Type", "text/plain")],
        &body,
    )
    .await;
    assert_eq!(
        plain.error(415),
        "POST /api/login takes Content-Type: application/json"
    );
    let json = [("Content-Type", "application/json")];
    for bad in ["token", "{\"secret\": 1}", "{\"token\": 7}"] {
        let reply = http(addr, "POST", "/api/login", &json, bad).await;
        assert_eq!(
            reply.error(400),
            "the body must be JSON: {\"token\": \"…\"}"
        );
    }

    // Logged in: a random session id in an HttpOnly, SameSite=Strict cookie.
    let reply = login(addr, TOKEN_A).await;
    assert_eq!(reply.status, 200);
    assert_eq!(
        reply.json(),
        serde_json::json!({ "auth": true, "logged_in": true, "tenant": "team-a" })
    );
    let set_cookie = reply.header("set-cookie").expect("a cookie");
    let (pair, flags) = set_cookie.split_once("; ").unwrap();
    assert_eq!(flags, "HttpOnly; SameSite=Strict; Path=/; Max-Age=43200");
    let id = pair.strip_prefix("gymfleet_dashboard=").expect("its name");
    assert_eq!(id.len(), 64);
    assert!(id.bytes().all(|c| c.is_ascii_hexdigit()) && !set_cookie.contains(TOKEN_A));
    let cookie_a = pair.to_string();

    let overview = get(addr, "/api/overview", Some(&cookie_a)).await.json();
    assert_eq!(overview["tenant"], "team-a");
    assert_eq!(ids(&overview, "batches"), [a_batch.id()]);
    assert_eq!(ids(&overview, "envs"), [a_env.id()]);
    assert_eq!(overview["batches"]["total"], 1);
    assert_eq!(item(&overview, "batches", a_batch.id())["n_envs"], 3);
    assert_eq!(get(addr, &a_scene, Some(&cookie_a)).await.status, 200);
    // Another tenant's batch is as unknown as one that never existed.
    let theirs = get(addr, &b_scene, Some(&cookie_a)).await.error(404);
    let none = get(addr, "/api/batches/batch_99/envs/0/scene", Some(&cookie_a))
        .await
        .error(404);
    assert_eq!(
        theirs.replace(b_batch.id(), "X"),
        none.replace("batch_99", "X")
    );
    assert_eq!(
        none,
        "batch \"batch_99\" not found: it was closed, reclaimed after idling, or never existed"
    );

    let cookie_b = session(addr, TOKEN_B).await;
    let overview = get(addr, "/api/overview", Some(&cookie_b)).await.json();
    assert_eq!(ids(&overview, "batches"), [b_batch.id()]);
    assert!(ids(&overview, "envs").is_empty());

    // Logging out ends the session on the server, not only in the browser.
    let out = http(addr, "POST", "/api/logout", &[("Cookie", &cookie_a)], "").await;
    assert_eq!(
        out.header("set-cookie"),
        Some("gymfleet_dashboard=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0")
    );
    let after = get(addr, "/api/overview", Some(&cookie_a)).await;
    assert_eq!(after.error(401), NOT_LOGGED_IN);
    assert_eq!(
        get(addr, "/api/overview", Some(&cookie_b)).await.status,
        200
    );
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn names_are_escaped_and_a_batch_members_scene_follows_its_steps() {
    let (server, addr) = start(ServerConfig::default()).await;
    let client = client(&server, None).await;
    let batch = client
        .create_batch(BatchOptions::new(hostile_pendulum(), 3).end_effectors([HOSTILE]))
        .await
        .expect("a batch whose arm is named <script>");
    let path = format!("/api/batches/{}/envs/1/scene", batch.id());
    let before = get(addr, &path, None).await;
    assert_eq!(before.status, 200, "{}", before.body);
    assert!(!before.body.contains('<') && !before.body.contains('>'));
    assert!(before
        .body
        .contains(r#""name":"\u003cscript\u003ealert(1)\u003c/script\u003e""#));
    let scene = before.json();
    assert_eq!(scene["id"], batch.id());
    assert_eq!(scene["index"], 1);
    let names: Vec<&str> = scene["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["base", HOSTILE]);
    assert_eq!(
        scene["bodies"][1]["shape"]["box"],
        serde_json::json!([2.0, 2.0, 20.0])
    );

    for _ in 0..30 {
        batch
            .step(ActionType::Torque, &[2e-4; 3])
            .await
            .expect("step");
    }
    let after = get(addr, &path, None).await.json();
    assert_eq!(after["poses"][0], scene["poses"][0], "the base stays");
    assert_ne!(after["poses"][1], scene["poses"][1], "the arm swung");
    assert_ne!(after["end_effectors"], scene["end_effectors"]);

    let past = format!("/api/batches/{}/envs/3/scene", batch.id());
    assert_eq!(
        get(addr, &past, None).await.error(400),
        "env_index: 3 is out of range: the batch has 3 envs"
    );
    let word = format!("/api/batches/{}/envs/first/scene", batch.id());
    assert_eq!(
        get(addr, &word, None).await.error(400),
        "env index: expected a whole number from 0, got \"first\""
    );
    let env = client
        .create_env(EnvOptions::new(hostile_pendulum()))
        .await
        .expect("env");
    let single = get(addr, &format!("/api/envs/{}/scene", env.id()), None).await;
    assert_eq!(single.json()["bodies"][1]["name"], HOSTILE);
    assert_eq!(single.json()["index"], Value::Null);
    assert_eq!(
        get(addr, "/api/envs/sim_404/scene", None).await.error(404),
        "environment \"sim_404\" not found: it was closed, reclaimed after idling, or never \
         existed"
    );
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn steps_episodes_and_rates_are_counted_on_the_servers_clock() {
    let clock = Clock::manual();
    let (server, addr) = start(ServerConfig {
        clock: clock.clone(),
        ..ServerConfig::default()
    })
    .await;
    let client = client(&server, None).await;
    let batch = client
        .create_batch(
            BatchOptions::new(ARM2, 2)
                .max_steps(3)
                .autoreset(Autoreset::SameStep),
        )
        .await
        .expect("batch");
    let env = client
        .create_env(EnvOptions::new(PENDULUM).max_steps(2))
        .await
        .expect("env");
    // The first reading: no rates yet.
    let first = get(addr, "/api/overview", None).await.json();
    assert_eq!(
        item(&first, "batches", batch.id())["env_steps_per_s"],
        Value::Null
    );
    assert_eq!(first["pool"]["jobs_per_s"], Value::Null);

    for _ in 0..7 {
        batch.step(ActionType::Torque, &[0.0; 4]).await.unwrap();
    }
    // Truncated at its second step and still at its third: one episode, not two.
    for _ in 0..3 {
        env.step(ActionType::Torque, &[0.0]).await.unwrap();
    }
    env.reset(None).await.unwrap();
    for _ in 0..2 {
        env.step(ActionType::Torque, &[0.0]).await.unwrap();
    }
    clock.advance(Duration::from_secs(2));
    let overview = get(addr, "/api/overview", None).await.json();
    let b = item(&overview, "batches", batch.id());
    assert_eq!(
        (b["steps"].as_u64(), b["env_steps"].as_u64()),
        (Some(7), Some(14))
    );
    assert_eq!(b["episodes"], 4, "each env ended episodes at steps 3 and 6");
    assert_eq!(b["env_steps_per_s"], 7.0);
    assert_eq!(b["steps_per_s"], 3.5);
    assert!(b["mean_step_ms"].as_f64().unwrap() > 0.0);
    assert_eq!(
        (b["max_steps"].as_u64(), b["action_dim"].as_u64()),
        (Some(3), Some(2))
    );
    assert_eq!(b["idle_s"], 2.0);
    let e = item(&overview, "envs", env.id());
    assert_eq!(
        (e["steps"].as_u64(), e["episodes"].as_u64()),
        (Some(5), Some(2))
    );
    assert_eq!(e["env_steps_per_s"], 2.5);
    let pool = &overview["pool"];
    assert_eq!(pool["threads"], 2);
    assert!(pool["jobs_started"].as_u64().unwrap() >= 15, "{pool}");
    assert!(pool["jobs_per_s"].as_f64().unwrap() > 0.0, "{pool}");
    assert!(pool["queue_depth"].is_u64());
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn watching_an_abandoned_batch_does_not_keep_it_alive() {
    let clock = Clock::manual();
    let (server, addr) = start(ServerConfig {
        clock: clock.clone(),
        idle_ttl: Duration::from_secs(60),
        ..ServerConfig::default()
    })
    .await;
    let client = client(&server, None).await;
    let batch = client
        .create_batch(BatchOptions::new(ARM2, 2))
        .await
        .expect("batch");
    let scene = format!("/api/batches/{}/envs/1/scene", batch.id());
    clock.advance(Duration::from_secs(59));
    for _ in 0..3 {
        assert_eq!(get(addr, &scene, None).await.status, 200);
        let overview = get(addr, "/api/overview", None).await.json();
        assert_eq!(ids(&overview, "batches"), [batch.id()]);
    }
    clock.advance(Duration::from_secs(1));
    crate::swept(&clock).await;
    // Reclaimed by the sweeper although the dashboard kept looking.
    let overview = get(addr, "/api/overview", None).await.json();
    assert!(
        ids(&overview, "batches").is_empty(),
        "the watched batch was reclaimed"
    );
    server.stop().await.expect("clean shutdown");
}
