//! The `gymfleet-server` binary as an operator runs it: logs to a pipe are plain text.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

/// With stderr redirected (a log file, a container's log collector), the log lines carry
/// no ANSI colour codes.
#[test]
fn logs_to_a_pipe_have_no_colour_codes() {
    let mut server = Command::new(env!("CARGO_BIN_EXE_gymfleet-server"))
        .args(["--listen", "127.0.0.1:0", "--threads", "1"])
        .env_remove("RUST_LOG")
        .env_remove("GYMFLEET_LOG_FORMAT")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start gymfleet-server");
    let stderr = server.stderr.take().expect("stderr");
    let mut lines = BufReader::new(stderr).lines();
    let serving = lines
        .next()
        .expect("a first log line")
        .expect("utf-8 log line");
    server.kill().expect("stop the server");
    let _ = server.wait();
    assert!(
        serving.contains("serving gymfleet.v1.Simulator"),
        "first line: {serving:?}"
    );
    assert!(
        !serving.contains('\u{1b}'),
        "ANSI escape in a piped log line: {serving:?}"
    );
}

/// The first log line of a server started with `args` under `taskset -c 0` (one CPU).
fn serving_line_on_one_cpu(args: &[&str]) -> String {
    let mut server = Command::new("taskset")
        .args(["-c", "0", env!("CARGO_BIN_EXE_gymfleet-server")])
        .args(["--listen", "127.0.0.1:0"])
        .args(args)
        .env_remove("RUST_LOG")
        .env_remove("GYMFLEET_LOG_FORMAT")
        .env_remove("GYMFLEET_THREADS")
        .env_remove("GYMFLEET_POOL_NICENESS")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start gymfleet-server under taskset (util-linux)");
    let stderr = server.stderr.take().expect("stderr");
    let line = BufReader::new(stderr)
        .lines()
        .next()
        .expect("a first log line")
        .expect("utf-8 log line");
    server.kill().expect("stop the server");
    let _ = server.wait();
    line
}

/// `--threads 0` sizes the pool to the CPUs the process may use (its affinity, here one
/// CPU of the machine's), not the machine's count; the pool runs at the process's own
/// priority unless `--pool-niceness` says otherwise (issue P2).
#[cfg(target_os = "linux")]
#[test]
fn the_pool_follows_the_cpus_the_process_may_use() {
    let line = serving_line_on_one_cpu(&["--threads", "0"]);
    assert!(line.contains("threads=1 "), "{line:?}");
    assert!(line.contains("pool_niceness=0 "), "{line:?}");
    let line = serving_line_on_one_cpu(&["--pool-niceness", "10"]);
    assert!(line.contains("pool_niceness=10 "), "{line:?}");
}
