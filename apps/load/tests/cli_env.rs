//! Every flag can be given as a `GYMFLEET_*` variable. Its own test binary (one test)
//! because the variables are process-wide.

use clap::Parser;
use gymfleet_load::{ActionKind, Api, Cli, Mode, StopRule, Target, UnitsArg, Warmup};

#[test]
fn flags_read_gymfleet_variables() {
    let task = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_env_task.json");
    let task_json = r#"{"terms": [{"name": "effort", "weight": -1, "ctrl_cost": {}}]}"#;
    std::fs::write(&task, task_json).unwrap();
    std::env::set_var("GYMFLEET_TASK", &task);
    let vars = [
        ("GYMFLEET_SERVER", "127.0.0.1:7001,127.0.0.1:7002"),
        ("GYMFLEET_MODEL", "pendulum"),
        ("GYMFLEET_END_EFFECTOR", "arm"),
        ("GYMFLEET_N_ENVS", "7"),
        ("GYMFLEET_CLIENTS", "3"),
        ("GYMFLEET_STEPS", "12"),
        ("GYMFLEET_WARMUP_STEPS", "2"),
        ("GYMFLEET_MODE", "stream"),
        ("GYMFLEET_WINDOW", "5"),
        ("GYMFLEET_API", "batch"),
        ("GYMFLEET_ACTION_TYPE", "position"),
        ("GYMFLEET_AMPLITUDE", "12.5"),
        ("GYMFLEET_SUBSTEPS", "3"),
        ("GYMFLEET_DT", "0.005"),
        ("GYMFLEET_MAX_STEPS", "64"),
        ("GYMFLEET_SEED", "11"),
        ("GYMFLEET_UNITS", "si"),
        ("GYMFLEET_JSON", "results.json"),
        ("GYMFLEET_QUIET", "true"),
        ("GYMFLEET_REPORT_RSS", "true"),
    ];
    for (k, v) in vars {
        std::env::set_var(k, v);
    }
    let config = Cli::try_parse_from(["gymfleet-load"])
        .unwrap()
        .resolve()
        .unwrap();
    assert_eq!(
        config.target,
        Target::Remote {
            servers: vec!["127.0.0.1:7001".into(), "127.0.0.1:7002".into()]
        }
    );
    assert_eq!(config.model.name, "pendulum");
    assert_eq!(config.end_effectors, ["arm"]);
    assert_eq!((config.n_envs, config.clients), (7, 3));
    assert_eq!(
        (config.stop, config.warmup),
        (StopRule::Steps(12), Warmup::Steps(2))
    );
    assert_eq!(
        (config.api, config.mode, config.window),
        (Api::Batch, Mode::Stream, 5)
    );
    assert_eq!(
        (config.action_type, config.amplitude),
        (ActionKind::Position, Some(12.5))
    );
    assert_eq!(
        (config.substeps, config.dt, config.max_steps, config.seed),
        (Some(3), Some(0.005), Some(64), 11)
    );
    assert_eq!(
        config.json.as_deref(),
        Some(std::path::Path::new("results.json"))
    );
    assert!(config.quiet && config.report_rss);
    let read = config.task.expect("GYMFLEET_TASK");
    assert_eq!((read.file, read.json.as_str()), (task, task_json));
    assert_eq!(config.units, UnitsArg::Si);

    // A flag on the command line wins over its variable.
    let config = Cli::try_parse_from(["gymfleet-load", "--n-envs", "9"])
        .unwrap()
        .resolve()
        .unwrap();
    assert_eq!(config.n_envs, 9);

    // Variables take part in the checks like flags.
    std::env::set_var("GYMFLEET_DURATION", "3");
    let err = Cli::try_parse_from(["gymfleet-load"])
        .unwrap()
        .resolve()
        .unwrap_err();
    assert_eq!(err.to_string(), "--duration cannot be used with --steps");
    std::env::remove_var("GYMFLEET_DURATION");

    if cfg!(not(feature = "embedded")) {
        return;
    }
    std::env::remove_var("GYMFLEET_SERVER");
    std::env::set_var("GYMFLEET_IN_PROCESS", "true");
    std::env::set_var("GYMFLEET_MODE", "unary");
    std::env::set_var("GYMFLEET_THREADS", "1");
    let config = Cli::try_parse_from(["gymfleet-load"])
        .unwrap()
        .resolve()
        .unwrap();
    assert_eq!(config.target, Target::InProcess { threads: 1 });
}
