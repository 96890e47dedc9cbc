//! The command line: defaults, every flag, and the exact message of each bad flag or
//! bad combination. The default target is the embedded server, so these need the
//! `embedded` feature; `src/cli.rs` tests the pure network client's refusals.
#![cfg(feature = "embedded")]

use clap::error::ErrorKind;
use clap::Parser;
use gymfleet_load::{
    threads_or_cores, ActionKind, Api, Cli, LoadConfig, LoadError, Mode, StopRule, Target,
    TaskFile, UnitsArg, Warmup, DEFAULT_N_ENVS,
};

/// Clears the `GYMFLEET_*` variables, so that the caller's environment does not change
/// the defaults these tests check (no test of this binary sets one; `cli_env.rs` does, in
/// its own binary).
fn scrub_gymfleet_env() {
    std::env::vars_os()
        .map(|(key, _)| key)
        .filter(|key| key.to_string_lossy().starts_with("GYMFLEET_"))
        .for_each(|key| std::env::remove_var(key));
}

fn resolve(args: &[&str]) -> Result<LoadConfig, LoadError> {
    scrub_gymfleet_env();
    let mut argv = vec!["gymfleet-load"];
    argv.extend_from_slice(args);
    Cli::try_parse_from(argv)
        .expect("clap accepts the flags")
        .resolve()
}

fn error(args: &[&str]) -> String {
    let err = resolve(args).expect_err("the flags are refused");
    assert!(err.is_usage(), "{err:?} is a usage error");
    err.to_string()
}

#[test]
fn defaults_are_a_ten_second_arm2_run_on_an_embedded_server() {
    let config = resolve(&[]).unwrap();
    assert_eq!(
        config.target,
        Target::Embedded {
            threads: threads_or_cores(0)
        }
    );
    assert_eq!(config.model.name, "arm2");
    assert_eq!(config.end_effectors, ["forearm"]);
    assert_eq!(config.n_envs, DEFAULT_N_ENVS);
    assert_eq!(config.clients, 1);
    assert_eq!(config.stop, StopRule::Seconds(10.0));
    assert_eq!(config.warmup, Warmup::Seconds(1.0));
    assert_eq!(
        (config.api, config.mode, config.window),
        (Api::Batch, Mode::Unary, 4)
    );
    assert_eq!(config.action_type, ActionKind::Torque);
    // Torque: each DOF's own action bound, as the server reports it.
    assert_eq!(config.amplitude, None);
    assert_eq!(
        (config.substeps, config.dt, config.max_steps),
        (None, None, None)
    );
    assert_eq!(config.seed, 0);
    assert!(config.json.is_none() && !config.quiet && !config.report_rss);
}

#[test]
fn every_flag_parses() {
    let config = resolve(&[
        "--server",
        "127.0.0.1:1,127.0.0.1:2",
        "--server",
        "127.0.0.1:3",
        "--model",
        "arm6",
        "--end-effector",
        "forearm,tool",
        "--n-envs",
        "32",
        "--clients",
        "3",
        "--steps",
        "50",
        "--warmup-steps",
        "5",
        "--mode",
        "stream",
        "--window",
        "8",
        "--action-type",
        "velocity",
        "--amplitude",
        "10",
        "--substeps",
        "2",
        "--dt",
        "0.01",
        "--max-steps",
        "100",
        "--seed",
        "9",
        "--json",
        "out.json",
        "--quiet",
        "--report-rss",
    ])
    .unwrap();
    assert_eq!(
        config.target,
        Target::Remote {
            servers: vec![
                "127.0.0.1:1".into(),
                "127.0.0.1:2".into(),
                "127.0.0.1:3".into()
            ]
        }
    );
    assert_eq!(config.model.name, "arm6");
    assert_eq!(config.end_effectors, ["forearm", "tool"]);
    assert_eq!((config.n_envs, config.clients), (32, 3));
    assert_eq!(config.stop, StopRule::Steps(50));
    assert_eq!(config.warmup, Warmup::Steps(5));
    assert_eq!((config.mode, config.window), (Mode::Stream, 8));
    assert_eq!(
        (config.action_type, config.amplitude),
        (ActionKind::Velocity, Some(10.0))
    );
    assert_eq!(
        (config.substeps, config.dt, config.max_steps, config.seed),
        (Some(2), Some(0.01), Some(100), 9)
    );
    assert_eq!(
        config.json.as_deref(),
        Some(std::path::Path::new("out.json"))
    );
    assert!(config.quiet && config.report_rss);
}

#[test]
fn targets_follow_the_flags() {
    let steps = ["--steps", "1"];
    let with = |extra: &[&str]| resolve(&[&steps[..], extra].concat()).unwrap().target;
    assert_eq!(
        with(&["--in-process", "--threads", "1"]),
        Target::InProcess { threads: 1 }
    );
    assert_eq!(
        with(&["--compare", "--threads", "2"]),
        Target::Compare {
            threads: 2,
            servers: vec![],
            rounds: 1
        }
    );
    assert_eq!(
        with(&["--compare", "--threads", "2", "--rounds", "3"]),
        Target::Compare {
            threads: 2,
            servers: vec![],
            rounds: 3
        }
    );
    assert_eq!(
        with(&["--compare", "--threads", "1", "--server", "h:1"]),
        Target::Compare {
            threads: 1,
            servers: vec!["h:1".into()],
            rounds: 1
        }
    );
}

#[test]
fn per_mode_defaults() {
    let env = resolve(&["--api", "env", "--model", "pendulum", "--steps", "10"]).unwrap();
    assert_eq!((env.n_envs, env.warmup), (1, Warmup::Steps(0)));
    assert_eq!(env.end_effectors, ["arm"]);
    let position = resolve(&["--action-type", "position"]).unwrap();
    assert_eq!(position.amplitude, Some(30.0));
    let velocity = resolve(&["--action-type", "velocity"]).unwrap();
    assert_eq!(velocity.amplitude, Some(45.0));
    let arm6 = resolve(&["--model", "arm6"]).unwrap();
    assert_eq!(
        (arm6.amplitude, arm6.end_effectors.as_slice()),
        (None, &["tool".to_string()][..])
    );
    let timed = resolve(&["--duration", "2.5", "--warmup", "0"]).unwrap();
    assert_eq!(
        (timed.stop, timed.warmup),
        (StopRule::Seconds(2.5), Warmup::Seconds(0.0))
    );
}

#[test]
fn model_files_are_read_and_default_to_their_last_instance() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join("cli_model_arm2.json");
    std::fs::write(&path, gymfleet_load::ARM2).unwrap();
    let config = resolve(&["--model", path.to_str().unwrap()]).unwrap();
    assert!(!config.model.builtin);
    assert_eq!(config.model.document, gymfleet_load::ARM2);
    assert_eq!(config.end_effectors, ["forearm"]);
}

#[test]
fn bad_flags_have_exact_messages() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["--duration", "5", "--steps", "10"],
            "--duration cannot be used with --steps",
        ),
        (
            &["--warmup", "1", "--warmup-steps", "3"],
            "--warmup cannot be used with --warmup-steps",
        ),
        (
            &["--steps", "10", "--warmup", "1"],
            "--warmup cannot be used with --steps (use --warmup-steps)",
        ),
        (
            &["--warmup-steps", "3"],
            "--warmup-steps cannot be used with --duration (use --warmup)",
        ),
        (
            &["--in-process", "--compare"],
            "--in-process cannot be used with --compare",
        ),
        (
            &["--in-process", "--server", "h:1"],
            "--in-process cannot be used with --server",
        ),
        (
            &["--api", "env", "--mode", "stream"],
            "--mode stream cannot be used with --api env",
        ),
        (
            &["--in-process", "--mode", "stream"],
            "--mode stream cannot be used with --in-process",
        ),
        (
            &["--api", "observe", "--mode", "stream"],
            "--mode stream cannot be used with --api observe",
        ),
        (
            &["--api", "ping", "--in-process"],
            "--in-process cannot be used with --api ping (a server round trip has no \
             in-process twin)",
        ),
        (
            &["--api", "ping", "--compare"],
            "--compare cannot be used with --api ping (a server round trip has no \
             in-process twin)",
        ),
        (
            &["--api", "ping", "--n-envs", "2"],
            "--n-envs must be 1 with --api ping (one env per client), got 2",
        ),
        (&["--n-envs", "0"], "--n-envs must be at least 1, got 0"),
        (
            &["--api", "env", "--n-envs", "4"],
            "--n-envs must be 1 with --api env (one env per client), got 4",
        ),
        (&["--clients", "0"], "--clients must be at least 1, got 0"),
        (&["--window", "0"], "--window must be at least 1, got 0"),
        (&["--steps", "0"], "--steps must be at least 1, got 0"),
        (
            &["--duration", "0"],
            "--duration must be a positive number of seconds, got 0",
        ),
        (
            &["--duration", "-1"],
            "--duration must be a positive number of seconds, got -1",
        ),
        (
            &["--warmup", "-1"],
            "--warmup must be a number of seconds ≥ 0, got -1",
        ),
        (&["--substeps", "0"], "--substeps must be at least 1, got 0"),
        (
            &["--max-steps", "0"],
            "--max-steps must be at least 1, got 0",
        ),
        (
            &["--dt", "0"],
            "--dt must be a positive number of seconds, got 0",
        ),
        (
            &["--amplitude", "NaN"],
            "--amplitude must be a finite number ≥ 0, got NaN",
        ),
        (&["--server", "h:1,,h:2"], "--server address 2 is empty"),
        (
            &["--rounds", "3"],
            "--rounds needs --compare (it alternates the in-process and remote runs)",
        ),
        (
            &["--compare", "--rounds", "0"],
            "--rounds must be at least 1, got 0",
        ),
        (
            &["--compare", "--rounds", "101"],
            "--rounds must be at most 100, got 101",
        ),
        (
            &["--model", "foo"],
            "unknown model 'foo': not pendulum|arm2|arm6|chain20|fourbar and no such file",
        ),
    ];
    for (args, message) in cases {
        assert_eq!(error(args), *message, "flags {args:?}");
    }
}

#[test]
fn unreadable_model_files_say_why() {
    // A directory exists but cannot be read as a file.
    let dir = env!("CARGO_TARGET_TMPDIR");
    let message = error(&["--model", dir]);
    assert!(
        message.starts_with(&format!("cannot read model file '{dir}': ")),
        "{message}"
    );
}

#[test]
fn clap_refuses_malformed_values() {
    for args in [
        &["--n-envs", "many"][..],
        &["--mode", "bidi"],
        &["--api", "rest"],
        &["--action-type", "force"],
        &["--clients", "-1"],
    ] {
        let argv = [&["gymfleet-load"][..], args].concat();
        let err = Cli::try_parse_from(argv).expect_err("refused");
        assert!(
            matches!(
                err.kind(),
                ErrorKind::InvalidValue | ErrorKind::ValueValidation
            ),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn task_and_units_flags() {
    let defaults = resolve(&[]).unwrap();
    assert_eq!(defaults.task, None);
    assert_eq!(defaults.units, UnitsArg::Document);

    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_effort_task.json");
    let json = r#"{"terms": [{"name": "effort", "weight": -1, "ctrl_cost": {}}]}"#;
    std::fs::write(&path, json).unwrap();
    let config = resolve(&["--task", path.to_str().unwrap(), "--units", "si"]).unwrap();
    assert_eq!(
        config.task,
        Some(TaskFile {
            file: path.clone(),
            json: json.to_string()
        })
    );
    assert_eq!(config.units, UnitsArg::Si);
    // The task and the units are in the summary line.
    assert!(
        config.summary().ends_with(&format!(
            "· seed 0 · task {} · units si · 10 s after 1 s warmup",
            path.display()
        )),
        "{}",
        config.summary()
    );
    assert_eq!(
        resolve(&["--units", "document"]).unwrap().units,
        UnitsArg::Document
    );
    // Remote servers check the task themselves: nothing is parsed here.
    let remote = resolve(&["--server", "h:1", "--task", path.to_str().unwrap()]).unwrap();
    assert_eq!(remote.task.map(|t| t.json), Some(json.to_string()));

    assert_eq!(
        error(&["--task", "/no/such/task.json"]),
        "--task cannot read '/no/such/task.json': No such file or directory (os error 2)"
    );
    let dir = env!("CARGO_TARGET_TMPDIR");
    let message = error(&["--task", dir]);
    assert!(
        message.starts_with(&format!("--task cannot read '{dir}': ")),
        "{message}"
    );

    scrub_gymfleet_env();
    let refused =
        Cli::try_parse_from(["gymfleet-load", "--units", "furlongs"]).expect_err("clap refuses it");
    assert_eq!(refused.kind(), ErrorKind::InvalidValue);
    assert!(
        refused
            .to_string()
            .starts_with("error: invalid value 'furlongs' for '--units <UNITS>'"),
        "{refused}"
    );
}

/// Every file of `models/` is a built-in model by its name, with the file's text, and the
/// unknown-model message lists them all.
#[test]
fn every_file_of_models_is_a_builtin_by_its_name() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models");
    let mut stems = Vec::new();
    for entry in std::fs::read_dir(dir).expect("models/") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            continue;
        }
        let stem = path.file_stem().unwrap().to_str().unwrap().to_string();
        let model = gymfleet_load::Model::resolve(&stem).expect("a built-in");
        assert!(model.builtin, "{stem}");
        assert_eq!(
            model.document,
            std::fs::read_to_string(&path).unwrap(),
            "{stem}"
        );
        stems.push(stem);
    }
    stems.sort();
    let mut builtins: Vec<&str> = gymfleet_load::BUILTINS.iter().map(|b| b.0).collect();
    builtins.sort_unstable();
    assert_eq!(stems, builtins);
    let message = gymfleet_load::Model::resolve("foo")
        .unwrap_err()
        .to_string();
    for stem in &stems {
        assert!(message.contains(stem.as_str()), "{message} lacks {stem}");
    }
}
