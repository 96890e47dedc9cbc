//! Short real runs: against the embedded server (unary, stream, single env), in
//! process, compared, against servers the test starts itself (`--server`), and timed.
//! Checks that the counts add up (env-steps = n_envs × steps × clients), that nothing
//! failed, and that the JSON file holds the figures. Never checks timings.
#![cfg(feature = "embedded")]

use clap::Parser;
use gymfleet_load::{run, Cli};

mod common;

use common::*;

#[test]
fn unary_batches_on_the_embedded_server() {
    let report = run_flags(&[
        "--n-envs",
        "8",
        "--clients",
        "2",
        "--steps",
        "20",
        "--warmup-steps",
        "3",
    ]);
    assert_eq!(report.runs.len(), 1);
    assert_eq!(report.runs[0].label, "remote unary");
    assert!(report.runs[0]
        .target
        .starts_with("embedded server 127.0.0.1:"));
    assert_counts(&report.runs[0], 8, 20, 2);
    assert_eq!(report.ratio_remote_to_in_process, None);
}

#[test]
fn streamed_batches_on_the_embedded_server() {
    let report = run_flags(&[
        "--mode",
        "stream",
        "--window",
        "3",
        "--n-envs",
        "4",
        "--clients",
        "2",
        "--steps",
        "25",
        "--warmup-steps",
        "2",
        "--action-type",
        "position",
    ]);
    assert_eq!(report.runs[0].label, "remote stream w3");
    assert_counts(&report.runs[0], 4, 25, 2);
}

#[test]
fn single_env_steps_on_the_embedded_server() {
    // max-steps 10: episodes end and are reset between timed steps.
    let report = run_flags(&[
        "--api",
        "env",
        "--model",
        "pendulum",
        "--clients",
        "2",
        "--steps",
        "30",
        "--max-steps",
        "10",
        "--action-type",
        "velocity",
    ]);
    assert_eq!(report.runs[0].label, "remote env Step");
    assert_counts(&report.runs[0], 1, 30, 2);
}

#[test]
fn observe_and_ping_measure_the_pool_hop_and_the_transport() {
    let report = run_flags(&["--api", "observe", "--model", "pendulum", "--steps", "20"]);
    assert_eq!(report.runs[0].label, "remote env Observe");
    assert_counts(&report.runs[0], 1, 20, 1);
    let report = run_flags(&["--api", "ping", "--steps", "20", "--clients", "2"]);
    assert_eq!(report.runs[0].label, "remote GetServerInfo");
    assert_counts(&report.runs[0], 1, 20, 2);
    // A ping's report says nothing of envs, models or actions.
    assert_eq!(
        report.summary,
        "GetServerInfo · 2 clients · 20 steps after 0 steps warmup"
    );
    let table = gymfleet_load::render_table(&report);
    for absent in ["env-steps", "terminated envs", "torque", "model"] {
        assert!(
            !table.contains(absent),
            "{absent} in a ping's table:\n{table}"
        );
    }
    assert!(
        table.contains("calls/s") && table.contains("busy cores"),
        "{table}"
    );
    let report = run_flags(&[
        "--in-process",
        "--api",
        "observe",
        "--model",
        "pendulum",
        "--steps",
        "20",
    ]);
    assert_eq!(report.runs[0].label, "in-process env Observe");
    assert_counts(&report.runs[0], 1, 20, 1);
}

#[test]
fn in_process_batches_and_envs() {
    let report = run_flags(&[
        "--in-process",
        "--n-envs",
        "8",
        "--clients",
        "2",
        "--steps",
        "20",
    ]);
    assert_eq!(report.runs[0].label, "in-process");
    assert_eq!(report.runs[0].target, "StepPool (2 threads), no network");
    assert_counts(&report.runs[0], 8, 20, 2);

    let report = run_flags(&[
        "--in-process",
        "--api",
        "env",
        "--model",
        "pendulum",
        "--steps",
        "30",
        "--max-steps",
        "7",
    ]);
    assert_eq!(report.runs[0].label, "in-process env");
    assert_counts(&report.runs[0], 1, 30, 1);
}

#[test]
fn compare_runs_in_process_then_remote_and_writes_json() {
    let path = tmp("compare.json");
    let _ = std::fs::remove_file(&path);
    let report = run_flags(&[
        "--compare",
        "--model",
        "arm6",
        "--n-envs",
        "4",
        "--steps",
        "15",
        "--report-rss",
        "--json",
        path.to_str().unwrap(),
    ]);
    assert_eq!(report.runs.len(), 2);
    assert_eq!(report.runs[0].label, "in-process");
    assert_eq!(report.runs[1].label, "remote unary");
    for r in &report.runs {
        assert_counts(r, 4, 15, 1);
        assert!(r.memory_loaded.is_some());
    }
    let ratio = report.ratio_remote_to_in_process.expect("a ratio");
    assert!(ratio.is_finite() && ratio > 0.0);

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).expect("valid JSON");
    assert_eq!(json["config"]["model"]["name"], "arm6");
    assert_eq!(json["config"]["n_envs"], 4);
    assert_eq!(json["config"]["stop"]["steps"], 15);
    assert_eq!(json["config"]["target"]["kind"], "compare");
    assert!(json["summary"].as_str().unwrap().contains("model arm6"));
    assert!(json["ratio_remote_to_in_process"].as_f64().is_some());
    assert!(json["memory_end"]["hwm_kib"].as_u64().unwrap() > 0);
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    for run in runs {
        assert_eq!(run["env_steps"], 60);
        assert_eq!(run["calls"], 15);
        assert_eq!(run["errors"], 0);
        assert!(run["first_error"].is_null());
        for field in ["elapsed_s", "env_steps_per_s", "calls_per_s"] {
            assert!(run[field].as_f64().unwrap() > 0.0, "{field}");
        }
        for q in ["p50", "p90", "p99", "max"] {
            assert!(run["latency_us"][q].as_u64().unwrap() > 0, "{q}");
        }
    }
}

#[test]
fn table_shows_the_figures_and_the_ratio() {
    let report = compare_pendulum(&[]);
    let table = gymfleet_load::render_table(&report);
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines[0], report.summary);
    assert!(
        lines[1].starts_with("[1] in-process: StepPool (2 threads)"),
        "{table}"
    );
    assert!(
        lines[2].starts_with("[2] remote unary: embedded server 127.0.0.1:"),
        "{table}"
    );
    for row in [
        "env-steps/s",
        "calls/s",
        "latency p50 (µs)",
        "latency p90 (µs)",
        "latency p99 (µs)",
        "latency max (µs)",
        "errors",
    ] {
        assert!(
            lines.iter().any(|l| l.starts_with(row)),
            "no {row} row in\n{table}"
        );
    }
    let env_steps = lines.iter().find(|l| l.starts_with("env-steps ")).unwrap();
    assert_eq!(
        env_steps.split_whitespace().collect::<Vec<_>>(),
        ["env-steps", "10", "10"]
    );
    assert!(
        table.contains("remote / in-process env-steps/s: "),
        "{table}"
    );
}

/// Servers started by the test, on a runtime of their own, reached with `--server`.
#[test]
fn servers_given_with_server_get_clients_round_robin() {
    let runtime = tokio::runtime::Runtime::new().unwrap();
    let servers: Vec<_> = (0..2)
        .map(|_| {
            runtime
                .block_on(gymfleet_load::EmbeddedServer::start(1))
                .unwrap()
        })
        .collect();
    let addrs: Vec<String> = servers.iter().map(|s| s.addr().to_string()).collect();
    let joined = addrs.join(",");
    let report = run_flags(&[
        "--server",
        &joined,
        "--clients",
        "3",
        "--n-envs",
        "5",
        "--steps",
        "10",
    ]);
    assert_counts(&report.runs[0], 5, 10, 3);
    let target = &report.runs[0].target;
    assert!(target.starts_with("server "), "{target}");
    for addr in &addrs {
        assert!(target.contains(&format!("{addr} (gymfleet ")), "{target}");
    }
    // Every batch was closed at the end.
    let info = runtime.block_on(async {
        let client = gymfleet_client::Client::connect(addrs[0].clone())
            .await
            .unwrap();
        client.server_info().await.unwrap()
    });
    assert_eq!((info.batches, info.batch_envs), (0, 0));
    for s in servers {
        runtime.block_on(s.stop()).unwrap();
    }
}

#[test]
fn a_server_started_with_the_server_library() {
    let runtime = tokio::runtime::Runtime::new().unwrap();
    let server = runtime
        .block_on(gymfleet_server::LocalServer::start(
            gymfleet_server::ServerConfig {
                threads: 1,
                ..Default::default()
            },
        ))
        .unwrap();
    let report = run_flags(&[
        "--server",
        &server.client_addr(),
        "--mode",
        "stream",
        "--n-envs",
        "3",
        "--steps",
        "12",
    ]);
    assert_counts(&report.runs[0], 3, 12, 1);
    runtime.block_on(server.stop()).unwrap();
}

#[test]
fn a_server_that_requires_a_token_gets_it_from_token() {
    let runtime = tokio::runtime::Runtime::new().unwrap();
    let tokens = gymfleet_server::TokenTable::parse("load load-test-token-0123456789").unwrap();
    let server = runtime
        .block_on(gymfleet_server::LocalServer::start(
            gymfleet_server::ServerConfig {
                threads: 1,
                auth_tokens: Some(std::sync::Arc::new(tokens)),
                ..Default::default()
            },
        ))
        .unwrap();
    let addr = server.client_addr();
    let path = tmp("token.json");
    let report = run_flags(&[
        "--server",
        &addr,
        "--token",
        "load-test-token-0123456789",
        "--n-envs",
        "2",
        "--steps",
        "5",
        "--json",
        path.to_str().unwrap(),
    ]);
    assert_counts(&report.runs[0], 2, 5, 1);
    let written = std::fs::read_to_string(&path).unwrap();
    assert!(
        !written.contains("load-test-token"),
        "the token stays out of the report"
    );
    let err = run(&config(&["--server", &addr, "--steps", "1"])).unwrap_err();
    assert!(
        err.to_string().contains(
            "unauthenticated: this server requires a token: send `authorization: Bearer \
             <token>` metadata (gymfleet's clients and tools read it from the GYMFLEET_TOKEN \
             variable or --token)"
        ),
        "{err}"
    );
    runtime.block_on(server.stop()).unwrap();
}

#[test]
fn timed_runs_count_whole_calls() {
    let report = run_flags(&[
        "--duration",
        "0.3",
        "--warmup",
        "0.1",
        "--n-envs",
        "4",
        "--clients",
        "2",
    ]);
    let r = &report.runs[0];
    assert_eq!(r.errors, 0, "{:?}", r.first_error);
    assert!(r.calls > 0);
    assert_eq!(r.env_steps, 4 * r.calls);
    assert_eq!(r.calls_per_client.iter().sum::<u64>(), r.calls);
}

#[test]
fn setup_failures_are_errors_with_the_servers_message() {
    let path = tmp("broken_model.json");
    std::fs::write(
        &path,
        r#"{"parts": [], "assembly": {"instances": [{"part": "Nope", "name": "a"}]}}"#,
    )
    .unwrap();
    let err = run(&config(&[
        "--model",
        path.to_str().unwrap(),
        "--steps",
        "1",
    ]))
    .unwrap_err();
    assert!(!err.is_usage());
    let message = err.to_string();
    assert!(
        message.starts_with("setup failed (client 0: CreateBatch on 127.0.0.1:"),
        "{message}"
    );
    assert!(message.contains("Nope"), "{message}");

    // Nothing listens on a port that was just free.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap();
    let err = run(&config(&["--server", &port.to_string(), "--steps", "1"])).unwrap_err();
    let message = err.to_string();
    assert!(
        message.starts_with(&format!(
            "setup failed (client 0: connect on {port}): cannot connect to the gymfleet server \
             at {port}: "
        )),
        "{message}"
    );
    assert!(
        message.ends_with(
            ". Is the server running? To use another one, pass --server ADDR (or set \
             GYMFLEET_SERVER)."
        ),
        "{message}"
    );
}

/// In-process and remote runs send identical actions only if both sides see the same
/// DOF limits (position targets are centred in them).
#[test]
fn server_and_env_report_the_same_dof_limits() {
    let runtime = tokio::runtime::Runtime::new().unwrap();
    let server = runtime
        .block_on(gymfleet_load::EmbeddedServer::start(1))
        .unwrap();
    for (document, tip) in [
        (gymfleet_load::ARM2, "forearm"),
        (gymfleet_load::ARM6, "tool"),
    ] {
        let remote: Vec<(Option<f64>, Option<f64>)> = runtime.block_on(async {
            let client = gymfleet_client::Client::connect(server.addr().to_string())
                .await
                .unwrap();
            let options = gymfleet_client::BatchOptions::new(document, 1).end_effectors([tip]);
            let batch = client.create_batch(options).await.unwrap();
            let limits = batch.info().joints.iter().flat_map(|j| j.limits.iter());
            let limits = limits.map(|l| (l.min, l.max)).collect();
            batch.close().await.unwrap();
            limits
        });
        let env = gymfleet_env::RobotEnv::from_json(
            document,
            gymfleet_env::EnvConfig::with_end_effectors([tip]),
        )
        .unwrap();
        let local: Vec<_> = env
            .spec()
            .dofs
            .iter()
            .map(|d| (d.limits.map(|l| l[0]), d.limits.map(|l| l[1])))
            .collect();
        assert_eq!(remote, local, "{tip}");
    }
    runtime.block_on(server.stop()).unwrap();
}

#[test]
fn replay_writes_an_html_page_of_one_env() {
    let path = tmp("replay.html");
    let _ = std::fs::remove_file(&path);
    let report = run_flags(&[
        "--model",
        "arm2",
        "--n-envs",
        "2",
        "--steps",
        "5",
        "--replay",
        path.to_str().unwrap(),
        "--replay-steps",
        "30",
    ]);
    assert_counts(&report.runs[0], 2, 5, 1);
    let html = std::fs::read_to_string(&path).expect("the replay page");
    assert!(html.starts_with("<!doctype html>"));
    assert!(html.contains(r#""title":"arm2""#));
    // The first frame and 30 steps.
    assert_eq!(html.matches(r#"{"end_effectors""#).count(), 31);

    let err = Cli::try_parse_from(["gymfleet-load", "--in-process", "--replay", "x.html"])
        .expect("flags parse")
        .resolve()
        .expect_err("no server to record on");
    assert_eq!(
        err.to_string(),
        "--replay records over the network: it needs a server (not --in-process)"
    );
    let err = Cli::try_parse_from(["gymfleet-load", "--replay", "x.html", "--replay-steps", "0"])
        .expect("flags parse")
        .resolve()
        .expect_err("nothing to record");
    assert_eq!(err.to_string(), "--replay-steps must be at least 1, got 0");
}

#[test]
fn compare_rounds_report_each_ratio_and_their_median() {
    let report = compare_pendulum(&["--rounds", "2"]);
    let labels: Vec<&str> = report.runs.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "in-process #1",
            "remote unary #1",
            "in-process #2",
            "remote unary #2"
        ]
    );
    for r in &report.runs {
        assert_counts(r, 2, 5, 1);
    }
    assert_eq!(report.round_ratios.len(), 2);
    for (round, ratio) in report.round_ratios.iter().enumerate() {
        let (local, remote) = (&report.runs[2 * round], &report.runs[2 * round + 1]);
        assert_eq!(*ratio, remote.env_steps_per_s / local.env_steps_per_s);
    }
    let median = (report.round_ratios[0] + report.round_ratios[1]) / 2.0;
    assert_eq!(report.ratio_remote_to_in_process, Some(median));
    let table = gymfleet_load::render_table(&report);
    let each = format!(
        "remote / in-process env-steps/s, each round: {:.3} {:.3}",
        report.round_ratios[0], report.round_ratios[1]
    );
    assert!(table.contains(&each), "{table}");
    assert!(
        table.contains(&format!(
            "remote / in-process env-steps/s, median of 2 rounds: {median:.3}"
        )),
        "{table}"
    );
}

/// `--compare` of 2 pendulum envs for 5 steps, with `extra` flags.
fn compare_pendulum(extra: &[&str]) -> gymfleet_load::Report {
    let flags = [
        "--compare",
        "--model",
        "pendulum",
        "--n-envs",
        "2",
        "--steps",
        "5",
    ];
    run_flags(&[&flags[..], extra].concat())
}
