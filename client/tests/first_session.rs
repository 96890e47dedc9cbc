//! The first-session example prints its errors for people: an unreachable server is named,
//! with the question and how to point the example elsewhere, never a Debug struct.

use std::path::PathBuf;
use std::process::Command;

/// The example's binary, which `cargo test` builds beside the test binaries.
fn example() -> PathBuf {
    let deps = std::env::current_exe().expect("test binary");
    let debug = deps
        .parent()
        .and_then(|d| d.parent())
        .expect("target/debug");
    debug
        .join("examples")
        .join(format!("first_session{}", std::env::consts::EXE_SUFFIX))
}

#[test]
fn an_unreachable_server_is_reported_with_what_to_do() {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .to_string();
    let out = Command::new(example())
        .arg(&port)
        .output()
        .expect("the example runs (cargo test builds it)");
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8(out.stderr).expect("UTF-8");
    assert!(
        stderr.starts_with(&format!(
            "error: cannot connect to the gymfleet server at {port}: "
        )),
        "{stderr}"
    );
    assert!(
        stderr.trim_end().ends_with(
            ". Is the server running? To use another one, give its address as the argument: \
             first_session ADDR."
        ),
        "{stderr}"
    );
    assert!(!stderr.contains("Connect {"), "{stderr}");
}
