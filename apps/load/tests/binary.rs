//! The `gymfleet-load` binary itself with `--task` and `--units`: the help text, the exit
//! status and stderr of a bad flag, and short runs (embedded server and in process) that
//! print the task in the summary line.

use std::process::{Command, Output};

/// Runs the binary with `args` and none of the caller's `GYMFLEET_*` variables.
fn gymfleet_load(args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_gymfleet-load"));
    for (key, _) in std::env::vars_os() {
        if key.to_string_lossy().starts_with("GYMFLEET_") {
            command.env_remove(key);
        }
    }
    command.args(args).output().expect("the binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).expect("UTF-8 output")
}

#[cfg(feature = "embedded")]
fn tmp(name: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

#[test]
fn help_describes_task_and_units() {
    let out = gymfleet_load(&["--help"]);
    assert!(out.status.success());
    let help = text(&out.stdout);
    for line in [
        "      --task <FILE>",
        "          A terms task's JSON file (docs/tasks.md: \"Terms tasks\"), the reward of every env: \
         its terms are computed in each step, so the run measures them too. Remote: sent as \
         the request's task; --in-process: parsed here",
        "          [env: GYMFLEET_TASK=]",
        "      --units <UNITS>",
        "          Units of observations and of the task's values, ranges and noise (actions \
         keep theirs)",
        "          [env: GYMFLEET_UNITS=]",
        "          [default: document]",
        "          - document: The document's: deg and mm (and per second)",
        "          - si:       SI, as MuJoCo and Gymnasium report them: rad and m (and per \
         second)",
    ] {
        assert!(
            help.lines().any(|l| l == line),
            "no line {line:?} in\n{help}"
        );
    }
}

#[test]
fn bad_task_files_and_units_are_usage_errors() {
    // With --server, so that a pure network client reaches the --task check too.
    let out = gymfleet_load(&[
        "--server",
        "127.0.0.1:1",
        "--task",
        "/no/such/task.json",
        "--steps",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        text(&out.stderr),
        "gymfleet-load: error: --task cannot read '/no/such/task.json': No such file or \
         directory (os error 2)\n"
    );
    assert!(out.stdout.is_empty());

    let out = gymfleet_load(&["--server", "127.0.0.1:1", "--units", "furlongs"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = text(&out.stderr);
    assert!(
        stderr.starts_with("error: invalid value 'furlongs' for '--units <UNITS>'\n"),
        "{stderr}"
    );
    assert!(
        stderr.contains("[possible values: document, si]"),
        "{stderr}"
    );
}

#[cfg(feature = "embedded")]
#[test]
fn runs_with_a_task_print_it_and_a_bad_one_fails_with_status_1() {
    let task = tmp("binary_effort_task.json");
    std::fs::write(
        &task,
        r#"{"terms": [{"name": "effort", "weight": -1, "ctrl_cost": {}}]}"#,
    )
    .unwrap();
    let task = task.to_str().unwrap();
    for target in [&[][..], &["--in-process"][..]] {
        let mut args = vec![
            "--quiet",
            "--threads",
            "1",
            "--model",
            "pendulum",
            "--n-envs",
            "2",
            "--steps",
            "3",
            "--task",
            task,
            "--units",
            "si",
        ];
        args.extend_from_slice(target);
        let out = gymfleet_load(&args);
        let stdout = text(&out.stdout);
        assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
        let summary = stdout.lines().next().unwrap();
        assert!(
            summary.ends_with(&format!(
                "· task {task} · units si · 3 steps after 0 steps warmup"
            )),
            "{stdout}"
        );
        let errors = stdout.lines().find(|l| l.starts_with("errors ")).unwrap();
        assert_eq!(
            errors.split_whitespace().collect::<Vec<_>>(),
            ["errors", "0"]
        );
    }

    let bad = tmp("binary_unknown_joint_task.json");
    std::fs::write(
        &bad,
        r#"{"terms": [{"name": "a", "value": {"joint": "elbow"}}]}"#,
    )
    .unwrap();
    let bad = bad.to_str().unwrap();
    let reason = "task.terms.terms[0].value.joint: unknown joint \"elbow\" (joints with a DOF: \"upper\", \"forearm\")";
    let out = gymfleet_load(&["--quiet", "--in-process", "--task", bad, "--steps", "1"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        text(&out.stderr),
        format!("gymfleet-load: error: setup failed (in-process: --task '{bad}'): {reason}\n")
    );
    let out = gymfleet_load(&["--quiet", "--threads", "1", "--task", bad, "--steps", "1"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = text(&out.stderr);
    assert!(
        stderr
            .starts_with("gymfleet-load: error: setup failed (client 0: CreateBatch on 127.0.0.1:"),
        "{stderr}"
    );
    assert!(
        stderr.ends_with(&format!("): invalid argument: {reason}\n")),
        "{stderr}"
    );
}

#[test]
fn an_unreachable_server_says_what_to_do_and_exits_1() {
    // Nothing listens on a port that was just free.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .to_string();
    let out = gymfleet_load(&["--server", &port, "--steps", "1"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = text(&out.stderr);
    assert!(
        stderr.starts_with(&format!(
            "gymfleet-load: error: setup failed (client 0: connect on {port}): cannot connect \
             to the gymfleet server at {port}: "
        )),
        "{stderr}"
    );
    assert!(
        stderr.trim_end().ends_with(
            "Is the server running? To use another one, pass --server ADDR (or set \
             GYMFLEET_SERVER)."
        ),
        "{stderr}"
    );
}
