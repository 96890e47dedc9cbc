//! Terms tasks and SI units over the wire: term names in the infos, each step's values in
//! single-env replies and batch rows (bitwise equal however a batch is sharded, values of
//! the step before a same-step autoreset), the `unhealthy` reason, and the proto-level
//! errors.

use gymfleet_client::{ActionType, Autoreset, BatchOptions, ClientError, EnvOptions, Task, Units};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};

use crate::{actions, bits};

const TASK: &str = r#"{
    "terms": [
        {"name": "speed", "weight": 1.0, "velocity": {"joint": "upper"}},
        {"name": "effort", "weight": -0.5, "ctrl_cost": {}},
        {"name": "alive", "weight": 1.0, "healthy": {}},
        {"name": "tip_z", "weight": 0.0, "value": {"instance": "forearm", "axis": "z"}}
    ],
    "healthy": {"ranges": [{"of": {"joint": "forearm"}, "min": -1.0}]},
    "reset_noise": {"position": {"uniform": 0.05}, "velocity": {"normal": 0.1}}
}"#;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_single_env_reports_each_term_in_si_units() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let env = client
        .create_env(
            EnvOptions::new(ARM2)
                .units(Units::Si)
                .task(Task::terms(TASK)),
        )
        .await
        .expect("create");
    assert_eq!(env.info().term_names, ["speed", "effort", "alive", "tip_z"]);
    assert_eq!(env.info().units, Units::Si);
    let first = env.reset(Some(1)).await.expect("reset");
    assert!(
        first.joint_positions.iter().all(|q| q.abs() <= 0.05 + 1e-6),
        "rad"
    );
    let mut before = first.joint_positions[0];
    for _ in 0..20 {
        let step = env
            .step(ActionType::Torque, &[0.0004, -0.0002])
            .await
            .expect("step");
        let [speed, effort, alive, tip_z] = step.terms[..] else {
            panic!("four values, got {:?}", step.terms)
        };
        let dt = env.info().dt as f32;
        let expected = (step.observation.joint_positions[0] - before) / dt;
        assert!((speed - expected).abs() < 1e-3 * expected.abs().max(1.0));
        assert!((effort - (0.0004f32.powi(2) + 0.0002f32.powi(2))).abs() < 1e-12);
        // Healthy while the forearm is above −1 rad; it falls under gravity.
        let healthy = step.observation.joint_positions[1] > -1.0;
        assert_eq!(alive, f32::from(u8::from(healthy)));
        assert_eq!(step.terminated, !healthy);
        assert!(tip_z.abs() < 1.0, "metres: {tip_z}");
        let reward = speed - 0.5 * effort + alive;
        assert!((step.reward - reward).abs() < 1e-4 * reward.abs().max(1.0));
        if step.terminated {
            assert_eq!(step.termination_reason.as_deref(), Some("unhealthy"));
            break;
        }
        before = step.observation.joint_positions[0];
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn term_values_are_bitwise_equal_however_a_batch_is_sharded() {
    const N: usize = 12;
    let options = || {
        BatchOptions::new(ARM2, N)
            .seed(5)
            .units(Units::Si)
            .autoreset(Autoreset::SameStep)
            .task(Task::terms(TASK))
    };
    let one = TestServer::start_default().await;
    let batch = one
        .client()
        .await
        .create_batch(options())
        .await
        .expect("one");
    let (_servers, fleet) = crate::two_server_fleet().await;
    let mut sharded = fleet.create_batch(options()).await.expect("sharded");
    assert_eq!(sharded.info().term_names, batch.info().term_names);
    let mut unhealthy = 0;
    for t in 0..200 {
        // Push the forearm down hard: it leaves the healthy range and the env restarts.
        let mut acts = actions(t, N * 2, 0.0005);
        for env in 0..N {
            acts[2 * env + 1] = -0.004;
        }
        let x = batch.step(ActionType::Torque, &acts).await.expect("step");
        let y = sharded.step(ActionType::Torque, &acts).await.expect("step");
        assert_eq!(x.terms().len(), N * 4);
        assert_eq!(bits(x.terms()), bits(y.terms()), "step {t}");
        assert_eq!(bits(x.rewards()), bits(y.rewards()), "step {t}");
        for env in 0..N {
            if x.termination_reason(env) == Some("unhealthy") {
                unhealthy += 1;
                // The values are the ending step's: not healthy, before the reset.
                assert_eq!(x.terms()[env * 4 + 2], 0.0);
                assert!(x.final_observation(env).is_some());
            }
        }
    }
    assert!(unhealthy > 0, "no env left the healthy range");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_terms_tasks_and_units_are_invalid_argument_with_their_paths() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    for (options, expected) in [
        (
            EnvOptions::new(PENDULUM).task(Task::terms(r#"{"terms": [{"name": "a", "value": {"joint": "elbow"}}]}"#)),
            "task.terms.terms[0].value.joint: unknown joint \"elbow\" (joints with a DOF: \"arm\")",
        ),
        (
            EnvOptions::new(PENDULUM).task(Task::terms("{\"terms\": [")),
            "task.terms.terms: EOF while parsing a list at line 1 column 11",
        ),
        (
            EnvOptions::new(PENDULUM).units(Units::Si).task(Task::from(gymfleet_client::UprightTask {
                instance: "arm".into(),
                axis: None,
                max_tilt_deg: 30.0,
            })),
            "task: reach, track and upright tasks are in the document's units (mm, deg); with units \"si\" use a terms task",
        ),
        (
            EnvOptions::new(PENDULUM).task(Task::terms(format!(
                "{{\"terms\": [], \"pad\": \"{}\"}}",
                "x".repeat(70_000)
            ))),
            "task.terms.json: expected at most 65536 bytes of JSON, got 70024",
        ),
    ] {
        let err = client.create_env(options).await.expect_err("refused");
        assert!(matches!(err, ClientError::InvalidArgument { .. }), "{err}");
        assert!(err.to_string().contains(expected), "{err}\nwant: {expected}");
    }
}
