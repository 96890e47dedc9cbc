//! Auth and tenants, TLS and mutual TLS, call deadlines: what docs/design.md §6.6 promises an
//! operator who puts the server on a shared network.

use std::sync::Arc;
use std::time::Duration;

use gymfleet_client::{ActionType, BatchOptions, Client, ClientError, Code, EnvOptions};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};
use gymfleet_proto::v1 as pb;
use gymfleet_server::{ServerConfig, TlsConfig, TokenTable};
use rcgen::{
    BasicConstraints, CertificateParams, CertifiedIssuer, DnType, IsCa, KeyPair, KeyUsagePurpose,
};

const TOKEN_A: &str = "team-a-token-0123456789";
const TOKEN_A2: &str = "team-a-second-0123456789";
const TOKEN_B: &str = "team-b-token-0123456789";

fn tokens() -> Arc<TokenTable> {
    let text = format!(
        "# tenant token\nteam-a {TOKEN_A}\nteam-a {TOKEN_A2}\nteam-b {TOKEN_B}  # second team\n"
    );
    Arc::new(TokenTable::parse(&text).expect("token file"))
}

async fn as_tenant(server: &TestServer, token: &str) -> Client {
    Client::builder(server.addr().to_string())
        .token(token)
        .connect()
        .await
        .expect("connect")
}

/// The generated stub with a bearer token: reaches any id, not only the handles a
/// `Client` created.
type Raw = pb::simulator_client::SimulatorClient<
    tonic::service::interceptor::InterceptedService<tonic::transport::Channel, Bearer>,
>;

#[derive(Clone)]
struct Bearer(String);

impl tonic::service::Interceptor for Bearer {
    fn call(
        &mut self,
        mut request: tonic::Request<()>,
    ) -> Result<tonic::Request<()>, tonic::Status> {
        let value = format!("Bearer {}", self.0).parse().expect("ascii token");
        request.metadata_mut().insert("authorization", value);
        Ok(request)
    }
}

async fn raw(server: &TestServer, token: &str) -> Raw {
    let channel = tonic::transport::Channel::from_shared(server.url())
        .unwrap()
        .connect()
        .await
        .unwrap();
    pb::simulator_client::SimulatorClient::with_interceptor(channel, Bearer(token.to_string()))
}

#[track_caller]
fn assert_unauthenticated(err: &ClientError, message: &str) {
    assert!(
        matches!(err, ClientError::Unauthenticated { .. }),
        "expected UNAUTHENTICATED, got {err:?}"
    );
    assert_eq!(err.message(), message);
    assert_eq!(err.code(), Some(Code::Unauthenticated));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_call_but_health_needs_a_known_token() {
    let server = TestServer::start(ServerConfig {
        threads: 2,
        auth_tokens: Some(tokens()),
        ..ServerConfig::default()
    })
    .await;
    let anonymous = server.client().await;
    let err = anonymous.server_info().await.unwrap_err();
    assert_unauthenticated(
        &err,
        "this server requires a token: send `authorization: Bearer <token>` metadata (gymfleet's clients and tools read it from the GYMFLEET_TOKEN variable or --token)",
    );
    let err = anonymous
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .unwrap_err();
    assert_unauthenticated(
        &err,
        "this server requires a token: send `authorization: Bearer <token>` metadata (gymfleet's clients and tools read it from the GYMFLEET_TOKEN variable or --token)",
    );
    let wrong = as_tenant(&server, "not-a-token-of-this-server").await;
    let err = wrong.server_info().await.unwrap_err();
    assert_unauthenticated(&err, "authorization: unknown token");

    // Health stays open for probes.
    {
        use tonic_health::pb::health_check_response::ServingStatus;
        use tonic_health::pb::health_client::HealthClient;
        use tonic_health::pb::HealthCheckRequest;
        let channel = tonic::transport::Channel::from_shared(server.url())
            .unwrap()
            .connect()
            .await
            .unwrap();
        let reply = HealthClient::new(channel)
            .check(HealthCheckRequest {
                service: "gymfleet.v1.Simulator".into(),
            })
            .await
            .expect("health without a token")
            .into_inner();
        assert_eq!(reply.status(), ServingStatus::Serving);
    }

    let a = as_tenant(&server, TOKEN_A).await;
    let info = a.server_info().await.expect("info");
    assert_eq!(info.tenant, "team-a");
    assert!(info.auth_required);
    server.stop().await.expect("clean shutdown");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_tenant_sees_only_its_own_envs_and_has_its_own_quota() {
    let server = TestServer::start(ServerConfig {
        threads: 2,
        auth_tokens: Some(tokens()),
        tenant_max_envs: 3,
        ..ServerConfig::default()
    })
    .await;
    let a = as_tenant(&server, TOKEN_A).await;
    let b = as_tenant(&server, TOKEN_B).await;

    let env = a
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("a's env");
    let batch = a
        .create_batch(BatchOptions::new(ARM2, 2))
        .await
        .expect("a's batch");
    env.reset(Some(1)).await.expect("reset");
    let before = env.observe().await.expect("observe");

    // Tenant b addresses a's ids: exactly what an unknown id gets, and a's envs are
    // untouched.
    let mut b_raw = raw(&server, TOKEN_B).await;
    let step = |env_id: &str| pb::StepRequest {
        env_id: env_id.to_string(),
        action_type: pb::ActionType::Torque as i32,
        values: vec![1.0],
        ..Default::default()
    };
    let theirs = b_raw.step(step(env.id())).await.unwrap_err();
    let unknown = b_raw.step(step("sim_999999")).await.unwrap_err();
    assert_eq!(theirs.code(), tonic::Code::NotFound);
    assert_eq!(
        theirs.message().replace(env.id(), "ID"),
        unknown.message().replace("sim_999999", "ID")
    );
    let env_ref = pb::EnvRef {
        env_id: env.id().to_string(),
    };
    for status in [
        b_raw.observe(env_ref.clone()).await.unwrap_err(),
        b_raw.close(env_ref.clone()).await.unwrap_err(),
        b_raw
            .close_batch(pb::BatchRef {
                batch_id: batch.id().to_string(),
            })
            .await
            .unwrap_err(),
    ] {
        assert_eq!(status.code(), tonic::Code::NotFound, "{status:?}");
    }
    assert_eq!(env.observe().await.expect("observe"), before);
    batch.observe().await.expect("a's batch is still open");

    // A tenant's second token is the same tenant.
    raw(&server, TOKEN_A2)
        .await
        .observe(env_ref)
        .await
        .expect("same tenant, other token");

    // Counts are per tenant.
    let info = b.server_info().await.expect("info");
    assert_eq!(
        (info.tenant.as_str(), info.envs, info.batches),
        ("team-b", 0, 0)
    );
    assert_eq!(info.limits.tenant_max_envs, 3);
    let info = a.server_info().await.expect("info");
    assert_eq!((info.envs, info.batches, info.batch_envs), (1, 1, 2));

    // a holds 3 of its 3; b's quota is its own.
    let err = a.create_env(EnvOptions::new(PENDULUM)).await.unwrap_err();
    assert!(
        matches!(err, ClientError::ResourceExhausted { .. }),
        "{err:?}"
    );
    assert_eq!(
        err.message(),
        "too many environments for tenant team-a: this request needs 1 more, 3 of its quota \
         of 3 are held; close some, or ask the operator to raise --tenant-max-envs \
         (GYMFLEET_TENANT_MAX_ENVS)"
    );
    b.create_batch(BatchOptions::new(ARM2, 3))
        .await
        .expect("b's own quota");
    env.close().await.expect("close");
    a.create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("room again after a close");
    server.stop().await.expect("clean shutdown");
}

/// A CA, and a server and a client certificate it signed, as PEM.
pub(crate) struct Pki {
    pub(crate) ca: String,
    pub(crate) server_cert: String,
    pub(crate) server_key: String,
    pub(crate) client_cert: String,
    pub(crate) client_key: String,
}

pub(crate) fn pki() -> Pki {
    let mut ca_params = CertificateParams::new(Vec::<String>::new()).unwrap();
    ca_params.is_ca = IsCa::Ca(BasicConstraints::Unconstrained);
    ca_params
        .distinguished_name
        .push(DnType::CommonName, "gymfleet test CA");
    ca_params.key_usages = vec![KeyUsagePurpose::KeyCertSign, KeyUsagePurpose::CrlSign];
    let ca = CertifiedIssuer::self_signed(ca_params, KeyPair::generate().unwrap()).unwrap();
    let leaf = |names: Vec<String>| {
        let key = KeyPair::generate().unwrap();
        let params = CertificateParams::new(names).unwrap();
        let cert = params.signed_by(&key, &ca).unwrap();
        (cert.pem(), key.serialize_pem())
    };
    let (server_cert, server_key) = leaf(vec!["localhost".into(), "127.0.0.1".into()]);
    let (client_cert, client_key) = leaf(vec!["trainer-1".into()]);
    Pki {
        ca: ca.pem(),
        server_cert,
        server_key,
        client_cert,
        client_key,
    }
}

async fn tls_server(pki: &Pki, mutual: bool) -> TestServer {
    TestServer::start(ServerConfig {
        threads: 1,
        tls: Some(TlsConfig {
            cert_pem: pki.server_cert.clone().into_bytes(),
            key_pem: pki.server_key.clone().into_bytes(),
            client_ca_pem: mutual.then(|| pki.ca.clone().into_bytes()),
        }),
        ..ServerConfig::default()
    })
    .await
}

/// A pendulum step over `client`: the call works end to end.
async fn steps(client: &Client) {
    let env = client
        .create_env(EnvOptions::new(PENDULUM))
        .await
        .expect("env over TLS");
    env.reset(Some(0)).await.expect("reset");
    env.step(ActionType::Torque, &[1.0]).await.expect("step");
    env.close().await.expect("close");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tls_serves_clients_that_trust_its_ca_only() {
    let pki = pki();
    let server = tls_server(&pki, false).await;
    let addr = server.addr().to_string();
    let client = Client::builder(addr.clone())
        .tls_ca_pem(pki.ca.clone())
        .tls_domain("localhost")
        .connect()
        .await
        .expect("TLS connect");
    steps(&client).await;

    // A plaintext client gets nowhere; neither does one trusting another CA.
    let plain = Client::builder(addr.clone())
        .connect_timeout(Some(Duration::from_secs(5)))
        .timeout(Duration::from_secs(5))
        .connect()
        .await;
    if let Ok(plain) = plain {
        let err = plain.server_info().await.unwrap_err();
        assert!(
            matches!(
                err,
                ClientError::Unavailable { .. } | ClientError::Internal { .. }
            ),
            "{err:?}"
        );
    }
    let other = pki_other_ca();
    let err = Client::builder(addr)
        .tls_ca_pem(other)
        .tls_domain("localhost")
        .connect()
        .await
        .unwrap_err();
    assert!(matches!(err, ClientError::Connect { .. }), "{err:?}");
    assert!(
        err.to_string().to_lowercase().contains("certificate"),
        "{err}"
    );
    server.stop().await.expect("clean shutdown");
}

fn pki_other_ca() -> String {
    let mut params = CertificateParams::new(Vec::<String>::new()).unwrap();
    params.is_ca = IsCa::Ca(BasicConstraints::Unconstrained);
    params
        .self_signed(&KeyPair::generate().unwrap())
        .unwrap()
        .pem()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn mutual_tls_admits_only_clients_with_a_certificate_from_its_ca() {
    let pki = pki();
    let server = tls_server(&pki, true).await;
    let addr = server.addr().to_string();
    let with_cert = Client::builder(addr.clone())
        .tls_ca_pem(pki.ca.clone())
        .tls_domain("localhost")
        .tls_identity_pem(pki.client_cert.clone(), pki.client_key.clone())
        .connect()
        .await
        .expect("mTLS connect");
    steps(&with_cert).await;

    // Without a client certificate the handshake (or the first call) fails.
    let without = Client::builder(addr)
        .tls_ca_pem(pki.ca.clone())
        .tls_domain("localhost")
        .connect()
        .await;
    let err = match without {
        Err(err) => err,
        Ok(client) => client.server_info().await.unwrap_err(),
    };
    assert!(
        matches!(
            err,
            ClientError::Connect { .. } | ClientError::Unavailable { .. }
        ),
        "{err:?}"
    );
    server.stop().await.expect("clean shutdown");
}

/// Deadlines, with the server's test gate on its pool jobs (debug builds only, as the
/// gate is): the held jobs make each deadline pass whatever the machine's speed.
#[cfg(debug_assertions)]
mod deadlines {
    use super::*;
    use gymfleet_server::JobGate;

    /// A server whose pool jobs wait at `gate` while it is closed (debug builds).
    async fn gated_server(gate: &JobGate) -> TestServer {
        TestServer::start(ServerConfig {
            job_gate: Some(gate.clone()),
            ..ServerConfig::default()
        })
        .await
    }

    /// Waits until a held job has seen that its caller has gone. Not a race: the gate holds
    /// it until then, however long the server takes to drop the call.
    async fn until_abandoned(gate: &JobGate, jobs: usize) {
        tokio::time::timeout(Duration::from_secs(60), async {
            while gate.abandoned() < jobs {
                tokio::time::sleep(Duration::from_millis(1)).await;
            }
        })
        .await
        .expect("the server drops a call past its deadline");
    }

    /// In process (the Python package's embedded server) there is no network layer to
    /// enforce a deadline: the client does, and the server drops the abandoned work.
    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn an_in_process_call_past_its_deadline_fails_as_deadline_exceeded() {
        let gate = JobGate::default();
        let server = gymfleet_server::LocalServer::start(ServerConfig {
            job_gate: Some(gate.clone()),
            ..ServerConfig::default()
        })
        .await
        .expect("start");
        let hurried = Client::builder(server.client_addr())
            .timeout(Duration::from_millis(1))
            .in_process(server.in_process())
            .expect("in-process client");
        gate.close();
        // The minute only turns a deadline nobody enforces (a bug) into a failure, not a
        // hang: the gate holds the job until its caller has gone.
        let err = tokio::time::timeout(
            Duration::from_secs(60),
            hurried.create_batch(BatchOptions::new(ARM2, 2000)),
        )
        .await
        .expect("the client enforces the deadline")
        .unwrap_err();
        assert!(
            matches!(err, ClientError::DeadlineExceeded { .. }),
            "{err:?}"
        );
        assert!(err.message().contains("deadline of 1ms"), "{err}");
        until_abandoned(&gate, 1).await;
        gate.open();
        let patient = Client::builder(server.client_addr())
            .in_process(server.in_process())
            .expect("in-process client");
        let info = patient.server_info().await.expect("info");
        assert_eq!((info.batches, info.batch_envs), (0, 0), "{info:?}");
        server.stop().await.expect("clean shutdown");
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn a_call_past_its_deadline_fails_as_deadline_exceeded() {
        let gate = JobGate::default();
        let server = gated_server(&gate).await;
        let hurried = Client::builder(server.addr().to_string())
            .timeout(Duration::from_millis(1))
            .connect()
            .await
            .expect("connect");
        // The creation's job is held on the pool until its caller has gone, so the
        // millisecond passes whatever the machine's speed.
        gate.close();
        let err = hurried
            .create_batch(BatchOptions::new(ARM2, 2000))
            .await
            .unwrap_err();
        assert!(
            matches!(err, ClientError::DeadlineExceeded { .. }),
            "{err:?}"
        );
        assert_eq!(err.code(), Some(Code::DeadlineExceeded));
        until_abandoned(&gate, 1).await;
        gate.open();
        // The server is fine, and nothing was built or reserved for nobody.
        let client = server.client().await;
        let info = client.server_info().await.expect("info");
        assert_eq!((info.batches, info.batch_envs), (0, 0), "{info:?}");
        steps(&client).await;
        server.stop().await.expect("clean shutdown");
    }

    #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
    async fn work_for_a_caller_that_has_gone_is_not_started() {
        let gate = JobGate::default();
        let server = gated_server(&gate).await;
        let client = server.client().await;
        let short = client
            .create_batch(BatchOptions::new(ARM2, 1))
            .await
            .expect("short batch");
        // The step waits for a thread (held at the gate) and its caller gives up; its
        // deadline went out as `grpc-timeout` (`with_deadline`), so the server drops the call.
        gate.close();
        let err = gymfleet_client::with_deadline(
            Duration::from_millis(20),
            short.step(ActionType::Torque, &[0.0, 0.0]),
        )
        .await
        .unwrap_err();
        assert_eq!(err.code(), Some(Code::DeadlineExceeded), "{err:?}");
        // The held job saw its caller gone before starting; then the pool is free again.
        until_abandoned(&gate, 1).await;
        gate.open();
        // Had the abandoned step run, this would be the short batch's second step.
        let step = short
            .step(ActionType::Torque, &[0.0, 0.0])
            .await
            .expect("step");
        assert_eq!(step.step_index(), 1, "the abandoned step never ran");
        server.stop().await.expect("clean shutdown");
    }
}

/// `GET /metrics` over a plain HTTP/1.0 connection: the body.
async fn scrape(addr: std::net::SocketAddr) -> String {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let mut stream = tokio::net::TcpStream::connect(addr).await.expect("metrics");
    stream
        .write_all(b"GET /metrics HTTP/1.0\r\nHost: localhost\r\n\r\n")
        .await
        .unwrap();
    let mut reply = String::new();
    stream.read_to_string(&mut reply).await.unwrap();
    assert!(reply.starts_with("HTTP/1.0 200"), "{reply}");
    let body = reply.split_once("\r\n\r\n").expect("headers end").1;
    body.to_string()
}

/// The value of the sample `series` (name and labels, exactly as written).
#[track_caller]
fn sample(text: &str, series: &str) -> f64 {
    text.lines()
        .find_map(|line| line.strip_prefix(series)?.strip_prefix(' '))
        .unwrap_or_else(|| panic!("no sample {series} in:\n{text}"))
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn metrics_count_steps_open_envs_calls_and_refusals_per_tenant() {
    let free = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let metrics_addr = free.local_addr().unwrap();
    drop(free);
    let server = TestServer::start(ServerConfig {
        threads: 2,
        auth_tokens: Some(tokens()),
        max_batch_size: 8,
        metrics_listen: Some(metrics_addr),
        ..ServerConfig::default()
    })
    .await;
    let a = as_tenant(&server, TOKEN_A).await;
    let b = as_tenant(&server, TOKEN_B).await;
    let env = a.create_env(EnvOptions::new(PENDULUM)).await.expect("env");
    env.reset(Some(0)).await.expect("reset");
    for _ in 0..3 {
        env.step(ActionType::Torque, &[0.5]).await.expect("step");
    }
    let batch = b
        .create_batch(BatchOptions::new(ARM2, 5))
        .await
        .expect("batch");
    batch.reset(Some(0)).await.expect("reset");
    batch
        .step(ActionType::Torque, &[0.0; 10])
        .await
        .expect("batch step");
    let err = b
        .create_batch(BatchOptions::new(ARM2, 9))
        .await
        .unwrap_err();
    assert_eq!(err.code(), Some(Code::ResourceExhausted));
    server.client().await.server_info().await.unwrap_err();
    a.server_info().await.expect("info");

    let text = scrape(metrics_addr).await;
    assert_eq!(
        sample(&text, "gymfleet_env_steps_total{tenant=\"team-a\"}"),
        3.0
    );
    assert_eq!(
        sample(&text, "gymfleet_env_steps_total{tenant=\"team-b\"}"),
        5.0
    );
    assert_eq!(sample(&text, "gymfleet_envs_open{tenant=\"team-a\"}"), 1.0);
    assert_eq!(
        sample(&text, "gymfleet_batches_open{tenant=\"team-b\"}"),
        1.0
    );
    assert_eq!(
        sample(&text, "gymfleet_batch_envs_open{tenant=\"team-b\"}"),
        5.0
    );
    assert_eq!(
        sample(
            &text,
            "gymfleet_rpc_duration_seconds_count{method=\"Step\",code=\"OK\"}"
        ),
        3.0
    );
    assert_eq!(
        sample(
            &text,
            "gymfleet_rpc_duration_seconds_count{method=\"CreateBatch\",code=\"RESOURCE_EXHAUSTED\"}"
        ),
        1.0
    );
    // Every unary call is timed, GetServerInfo too (the refused one never reached it).
    assert_eq!(
        sample(
            &text,
            "gymfleet_rpc_duration_seconds_count{method=\"GetServerInfo\",code=\"OK\"}"
        ),
        1.0
    );
    assert_eq!(
        sample(
            &text,
            "gymfleet_rejected_requests_total{reason=\"max_batch_size\"}"
        ),
        1.0
    );
    assert_eq!(
        sample(
            &text,
            "gymfleet_rejected_requests_total{reason=\"unauthenticated\"}"
        ),
        1.0
    );
    assert_eq!(sample(&text, "gymfleet_pool_queue_depth"), 0.0);
    assert!(sample(&text, "gymfleet_pool_jobs_total") >= 8.0, "{text}");
    assert!(
        text.trim_end().ends_with("# EOF"),
        "OpenMetrics text ends with # EOF"
    );

    // Closing shows in the gauges: team-a's series reads 0 (it does not vanish, so a
    // dashboard or an alert on it keeps a value).
    env.close().await.expect("close");
    let text = scrape(metrics_addr).await;
    assert_eq!(sample(&text, "gymfleet_envs_open{tenant=\"team-a\"}"), 0.0);
    server.stop().await.expect("clean shutdown");
}
