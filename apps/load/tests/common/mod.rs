//! What the run tests share: flags to a configuration, a run, its counts checked, a
//! scratch path.
#![allow(dead_code, unreachable_pub)]

use std::path::PathBuf;

use clap::Parser;
use gymfleet_load::{run, Cli, LoadConfig, Report, RunResult};

pub fn config(args: &[&str]) -> LoadConfig {
    let mut argv = vec!["gymfleet-load", "--quiet", "--threads", "2"];
    argv.extend_from_slice(args);
    Cli::try_parse_from(argv)
        .expect("flags parse")
        .resolve()
        .expect("flags are valid")
}

pub fn run_flags(args: &[&str]) -> Report {
    run(&config(args)).expect("the run completes")
}

#[track_caller]
pub fn assert_counts(run: &RunResult, n_envs: u64, steps: u64, clients: u64) {
    assert_eq!(run.errors, 0, "first error: {:?}", run.first_error);
    assert_eq!(run.first_error, None);
    assert_eq!(run.calls, steps * clients, "{run:?}");
    assert_eq!(run.env_steps, n_envs * steps * clients, "{run:?}");
    assert_eq!(run.calls_per_client, vec![steps; clients as usize]);
    assert_eq!(run.terminations, 0, "no env diverged");
    assert!(run.env_steps_per_s > 0.0 && run.calls_per_s > 0.0);
    let l = run.latency_us;
    assert!(
        0 < l.p50 && l.p50 <= l.p90 && l.p90 <= l.p99 && l.p99 <= l.max,
        "{l:?}"
    );
}

pub fn tmp(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}
