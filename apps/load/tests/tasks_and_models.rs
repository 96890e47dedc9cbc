//! Real runs of what a model and a task change: terms tasks read from files, remote and in
//! process, and their errors; models with passive joints, whose actions cover only the
//! actuated DOFs.
#![cfg(feature = "embedded")]

mod common;

use common::*;
use gymfleet_load::run;

/// `--task FILE` gives every env a terms task (its terms computed in each step) and
/// `--units si` its units, the same on both sides: `--compare` runs it in process, then on
/// the embedded server; single envs take it too. The report names the file and holds its
/// JSON.
#[test]
fn a_terms_task_from_a_file_runs_remote_and_in_process() {
    let task = tmp("effort_task.json");
    let json = r#"{"terms": [{"name": "effort", "weight": -1, "ctrl_cost": {}},
                      {"name": "speed", "velocity": {"joint": "upper"}}]}"#;
    std::fs::write(&task, json).expect("write the task");
    let task = task.to_str().expect("utf-8 path");
    let report_path = tmp("task_report.json");
    let _ = std::fs::remove_file(&report_path);
    let report = run_flags(&[
        "--compare",
        "--task",
        task,
        "--units",
        "si",
        "--n-envs",
        "4",
        "--steps",
        "10",
        "--json",
        report_path.to_str().unwrap(),
    ]);
    assert_eq!(report.runs.len(), 2);
    assert_eq!(report.runs[0].label, "in-process");
    assert_eq!(report.runs[1].label, "remote unary");
    for r in &report.runs {
        assert_counts(r, 4, 10, 1);
    }
    assert!(
        report.summary.ends_with(&format!(
            "· task {task} · units si · 10 steps after 0 steps warmup"
        )),
        "{}",
        report.summary
    );
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    assert_eq!(written["config"]["task"]["file"], task);
    assert_eq!(written["config"]["task"]["json"], json);
    assert_eq!(written["config"]["units"], "si");

    for target in [&[][..], &["--in-process"][..]] {
        let mut args = vec![
            "--api", "env", "--model", "pendulum", "--task", task, "--steps", "5",
        ];
        args.extend_from_slice(target);
        // The pendulum has no joint "upper".
        let err = run(&config(&args)).expect_err("the pendulum has no joint upper");
        assert!(err.to_string().contains("unknown joint \"upper\""), "{err}");
    }
    let pendulum = tmp("pendulum_effort_task.json");
    std::fs::write(
        &pendulum,
        r#"{"terms": [{"name": "effort", "weight": -1, "ctrl_cost": {}}]}"#,
    )
    .unwrap();
    for target in [&[][..], &["--in-process"][..]] {
        let mut args = vec![
            "--api",
            "env",
            "--model",
            "pendulum",
            "--task",
            pendulum.to_str().unwrap(),
            "--steps",
            "5",
        ];
        args.extend_from_slice(target);
        assert_counts(&run_flags(&args).runs[0], 1, 5, 1);
    }
}

/// A task the model cannot have, or that does not read as a terms task: in process a
/// setup error naming the file; remote the server's `INVALID_ARGUMENT`, as for any bad
/// option of `CreateBatch`, with the same path and reason.
#[test]
fn a_bad_task_fails_the_setup_with_its_path() {
    let cases = [
        (
            "unknown_joint_task.json",
            r#"{"terms": [{"name": "a", "value": {"joint": "elbow"}}]}"#,
            "task.terms.terms[0].value.joint: unknown joint \"elbow\" (joints with a DOF: \
             \"upper\", \"forearm\")",
        ),
        (
            "bad_weight_task.json",
            r#"{"terms": [{"name": "a", "weight": "heavy", "ctrl_cost": {}}]}"#,
            "task.terms.terms[0].weight: invalid type: string \"heavy\", expected f64 at line 1 \
             column 42",
        ),
    ];
    for (name, json, reason) in cases {
        let path = tmp(name);
        std::fs::write(&path, json).expect("write the task");
        let file = path.to_str().expect("utf-8 path");

        let err = run(&config(&["--in-process", "--task", file, "--steps", "2"]))
            .expect_err("refused in process");
        assert!(!err.is_usage());
        assert_eq!(
            err.to_string(),
            format!("setup failed (in-process: --task '{file}'): {reason}")
        );

        let err = run(&config(&["--task", file, "--steps", "2"])).expect_err("refused remote");
        assert!(!err.is_usage());
        let message = err.to_string();
        assert!(
            message.starts_with("setup failed (client 0: CreateBatch on 127.0.0.1:"),
            "{message}"
        );
        assert!(
            message.ends_with(&format!("): invalid argument: {reason}")),
            "{message}"
        );
    }
}

/// A model with a passive joint takes one action value per actuated DOF, in process as on
/// the server (the in-process run once sized its actions by every DOF).
#[test]
fn a_model_with_a_passive_joint_runs_remote_and_in_process() {
    let mut doc: serde_json::Value =
        serde_json::from_str(gymfleet_load::ARM2).expect("arm2 is JSON");
    doc["assembly"]["joints"][1]["actuated"] = serde_json::json!(false);
    let path = tmp("arm2_passive_forearm.json");
    std::fs::write(&path, doc.to_string()).expect("write the model");
    let report = run_flags(&[
        "--compare",
        "--model",
        path.to_str().expect("utf-8 path"),
        "--n-envs",
        "4",
        "--steps",
        "5",
    ]);
    assert_eq!(report.runs.len(), 2);
    for r in &report.runs {
        assert_counts(r, 4, 5, 1);
    }
}
