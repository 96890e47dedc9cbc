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
