//! Tasks over the wire: the target in single-env observations and batch rows, the
//! layout in the infos, termination reasons, bitwise-equal rewards however a batch is
//! sharded, and the proto-level errors.

use gymfleet_client::{
    ActionType, Autoreset, BatchOptions, ClientError, EnvOptions, Fleet, FleetEndpoints, ReachTask,
    Task, TrackTask,
};
use gymfleet_e2e::{TestServer, ARM2, PENDULUM};

use crate::{actions, bits};

fn reach_box() -> Task {
    Task::from(ReachTask {
        end_effector: "forearm".into(),
        point: Some([1.5, 1.5, 25.0]),
        target_box: Some(([15.0, 0.0, 30.0], [30.0, 0.0, 45.0])),
        success_radius: 5.0,
        terminate_on_success: true,
        ..ReachTask::default()
    })
    .with_action_cost(0.01)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_single_env_reports_its_target_reward_and_goal() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let task = ReachTask {
        end_effector: "arm".into(),
        target: Some([10.0, 10.0, 25.0]),
        success_radius: 1.0,
        terminate_on_success: true,
        ..ReachTask::default()
    };
    let env = client
        .create_env(EnvOptions::new(PENDULUM).end_effectors(["arm"]).task(task))
        .await
        .expect("create");
    let layout: Vec<(&str, usize)> = env
        .info()
        .observation_layout
        .iter()
        .map(|(n, s)| (n.as_str(), *s))
        .collect();
    assert_eq!(
        layout,
        [
            ("joint_positions", 1),
            ("joint_velocities", 1),
            ("end_effector_poses", 7),
            ("target", 3)
        ]
    );
    assert_eq!(env.info().observation_dim, 12);
    let first = env.reset(Some(0)).await.expect("reset");
    assert_eq!(first.task_observation, [10.0, 10.0, 25.0]);
    let step = env.step(ActionType::Torque, &[0.0]).await.expect("step");
    assert!(step.terminated && step.done);
    assert_eq!(step.termination_reason.as_deref(), Some("goal_reached"));
    assert!(step.reward > -1e-3 && step.reward <= 0.0, "{}", step.reward);
    assert_eq!(step.observation.task_observation, [10.0, 10.0, 25.0]);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn task_rewards_are_bitwise_equal_however_a_batch_is_sharded() {
    const N: usize = 24;
    let options = || {
        BatchOptions::new(ARM2, N)
            .end_effectors(["forearm"])
            .seed(3)
            .reset_noise(5.0)
            .autoreset(Autoreset::SameStep)
            .task(reach_box())
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
    assert_eq!(
        sharded.info().observation_layout,
        batch.info().observation_layout
    );

    let a = batch
        .reset(Some(7))
        .await
        .expect("reset")
        .into_observations();
    let b = sharded
        .reset(Some(7))
        .await
        .expect("reset")
        .into_observations();
    assert_eq!(bits(&a), bits(&b), "the same targets, env by env");
    let targets: Vec<&[f32]> = a.chunks_exact(14).map(|row| &row[11..]).collect();
    assert_ne!(targets[0], targets[1], "each env draws its own target");
    let mut reasons = 0;
    for t in 0..60 {
        // Random targets, then every arm to (60°, −60°): its tip at (26, 0, 45) mm, on
        // the box's top face, within 5 mm of some envs' targets.
        let acts = if t < 20 {
            actions(t, N * 2, 40.0)
        } else {
            [60.0, -60.0].repeat(N)
        };
        let x = batch.step(ActionType::Position, &acts).await.expect("step");
        let y = sharded
            .step(ActionType::Position, &acts)
            .await
            .expect("step");
        assert_eq!(bits(x.observations()), bits(y.observations()), "step {t}");
        assert_eq!(bits(x.rewards()), bits(y.rewards()), "step {t}");
        assert_eq!(x.terminated(), y.terminated());
        for env in 0..N {
            assert_eq!(x.termination_reason(env), y.termination_reason(env));
            if let Some(reason) = x.termination_reason(env) {
                assert_eq!(reason, "goal_reached");
                reasons += 1;
            }
        }
        assert!(
            x.rewards().iter().all(|&r| r < 0.0),
            "minus a distance, minus a cost"
        );
    }
    assert!(reasons > 0, "no env reached its target");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_tasks_are_invalid_argument_with_their_paths() {
    let server = TestServer::start_default().await;
    let client = server.client().await;
    let cases: [(Task, &str); 3] = [
        (
            ReachTask {
                end_effector: "forearm".into(),
                ..ReachTask::default()
            }
            .into(),
            "task.reach.target: expected exactly one of target and target_box",
        ),
        (
            ReachTask {
                end_effector: "hand".into(),
                target: Some([0.0; 3]),
                ..ReachTask::default()
            }
            .into(),
            "task.reach.end_effector: unknown instance \"hand\" (known: \"base\", \"upper\", \"forearm\")",
        ),
        (
            TrackTask {
                targets: vec![0.0, 10.0],
                ..TrackTask::default()
            }
            .into(),
            "task.track.targets[1]: 10 is outside joint \"forearm\"'s limits [-120, 0]",
        ),
    ];
    for (task, message) in cases {
        let err = client
            .create_env(EnvOptions::new(ARM2).task(task))
            .await
            .expect_err("refused");
        match err {
            ClientError::InvalidArgument { message: got, .. } => assert_eq!(got, message),
            other => panic!("{other:?}"),
        }
    }
    assert_eq!(client.server_info().await.expect("info").envs, 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn randomization_draws_are_readable_and_the_same_however_a_batch_is_sharded() {
    use gymfleet_client::Randomization;
    let randomize = Randomization {
        mass_scale: Some([0.5, 2.0]),
        gain_scale: Some([0.8, 1.2]),
        ..Randomization::default()
    };
    let options = || {
        BatchOptions::new(ARM2, 6)
            .seed(9)
            .randomize(randomize.clone())
    };
    let one = TestServer::start_default().await;
    let client = one.client().await;
    let batch = client.create_batch(options()).await.expect("batch");
    let mut servers = Vec::new();
    for _ in 0..2 {
        servers.push(TestServer::start_default().await);
    }
    let endpoints =
        FleetEndpoints::new(servers.iter().map(|s| s.addr().to_string())).expect("endpoints");
    let fleet = Fleet::connect(endpoints).await.expect("fleet");
    let mut sharded = fleet.create_batch(options()).await.expect("sharded");
    batch.reset(Some(1)).await.expect("reset");
    sharded.reset(Some(1)).await.expect("reset");
    let mut masses = Vec::new();
    for env in 0..6 {
        let a = batch.randomization(env).await.expect("draws");
        let b = sharded.randomization(env).await.expect("draws");
        assert_eq!(a, b, "env {env}");
        let names: Vec<&str> = a.instances.iter().map(|(n, _, _)| n.as_str()).collect();
        assert_eq!(names, ["base", "upper", "forearm"]);
        assert!(a
            .instances
            .iter()
            .all(|(_, m, f)| (0.5..=2.0).contains(m) && *f == 1.0));
        assert!(a
            .joints
            .iter()
            .all(|(_, d, g)| *d == 1.0 && (0.8..=1.2).contains(g)));
        masses.push(a.instances[1].1);
    }
    masses.dedup();
    assert_eq!(masses.len(), 6, "each env draws its own factors");
    let acts = actions(1, 12, 1e-4);
    let x = batch.step(ActionType::Torque, &acts).await.expect("step");
    let y = sharded.step(ActionType::Torque, &acts).await.expect("step");
    assert_eq!(bits(x.observations()), bits(y.observations()));

    let err = batch.randomization(6).await.expect_err("past the end");
    assert_eq!(
        err.to_string(),
        "invalid argument: env_index: 6 is out of range: the batch has 6 envs"
    );
    let plain = client
        .create_env(EnvOptions::new(ARM2))
        .await
        .expect("plain env");
    let err = plain.randomization().await.expect_err("no draws");
    assert_eq!(
        err.to_string(),
        "failed precondition: \"sim_1\" was created without randomize: it draws no factors"
    );
}
