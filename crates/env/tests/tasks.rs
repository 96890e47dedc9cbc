//! Tasks: rewards against hand-computed values, goal and fall terminations, targets drawn
//! from a box by seed, and exact errors for bad task specs.

use gymfleet_env::{ActionType, EnvConfig, EnvError, ReachTarget, RobotEnv, TaskKind, TaskSpec};

const PENDULUM: &str = include_str!("../../../models/pendulum.json");

/// The seed pendulum: the 4×4×40 mm arm stands upright on a hinge about +Y; its
/// instance frame is at (8, 8, 5) mm, so its centre of mass starts at (10, 10, 25) mm.
fn pendulum(task: TaskKind, action_cost: f64) -> RobotEnv {
    let config = EnvConfig {
        end_effector_ids: vec!["arm".into()],
        task: Some(TaskSpec {
            kind: task,
            action_cost,
        }),
        ..EnvConfig::default()
    };
    RobotEnv::from_json(PENDULUM, config).expect("pendulum with a task")
}

fn reach(target: [f64; 3]) -> TaskKind {
    TaskKind::Reach {
        end_effector: "arm".into(),
        point: None,
        target: ReachTarget::Fixed(target),
        success_radius: 0.0,
        terminate_on_success: false,
    }
}

fn error(task: TaskKind, action_cost: f64) -> String {
    let config = EnvConfig {
        task: Some(TaskSpec {
            kind: task,
            action_cost,
        }),
        ..EnvConfig::default()
    };
    match RobotEnv::from_json(PENDULUM, config) {
        Err(e @ EnvError::BadTask { .. }) => e.to_string(),
        Err(other) => panic!("not a task error: {other}"),
        Ok(_) => panic!("accepted"),
    }
}

#[test]
fn reach_rewards_minus_the_distance_in_mm_and_observes_the_target() {
    let mut env = pendulum(reach([20.0, 0.0, 40.0]), 0.0);
    let spec = env.spec().clone();
    assert_eq!(spec.observation_dim, 1 + 1 + 7 + 3);
    let layout: Vec<(&str, usize)> = spec
        .observation_layout
        .iter()
        .map(|s| (s.name, s.size))
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
    let first = env.reset(None);
    assert_eq!(first.task, [20.0, 0.0, 40.0]);
    // The upright arm barely moves in one step with no torque: |(10, 10, 25) − (20, 0, 40)|.
    let step = env.step(ActionType::Torque, &[0.0]).unwrap();
    let expected = -(100.0f64 + 100.0 + 225.0).sqrt();
    assert!(
        (f64::from(step.flags.reward) - expected).abs() < 1e-4,
        "{}",
        step.flags.reward
    );
    assert_eq!(step.observation.task, [20.0, 0.0, 40.0]);
    assert!(!step.flags.terminated);
}

#[test]
fn reach_measures_from_a_point_in_the_instances_frame() {
    let task = TaskKind::Reach {
        end_effector: "arm".into(),
        // The arm's top centre: (2, 2, 40) from its frame's origin (8, 8, 5).
        point: Some([2.0, 2.0, 40.0]),
        target: ReachTarget::Fixed([20.0, 0.0, 45.0]),
        success_radius: 0.0,
        terminate_on_success: false,
    };
    let mut env = pendulum(task, 0.0);
    let step = env.step(ActionType::Torque, &[0.0]).unwrap();
    // |(10, 10, 45) − (20, 0, 45)| = √200.
    assert!((f64::from(step.flags.reward) + 200f64.sqrt()).abs() < 1e-4);
}

#[test]
fn the_action_cost_is_its_weight_times_the_sum_of_squared_actions() {
    let mut free = pendulum(reach([20.0, 0.0, 40.0]), 0.0);
    let mut costly = pendulum(reach([20.0, 0.0, 40.0]), 4.0);
    for torque in [0.5_f32, -0.25] {
        let a = free
            .step(ActionType::Torque, &[torque])
            .unwrap()
            .flags
            .reward;
        let b = costly
            .step(ActionType::Torque, &[torque])
            .unwrap()
            .flags
            .reward;
        let cost = 4.0 * f64::from(torque).powi(2);
        assert!(
            (f64::from(a - b) - cost).abs() < 1e-5,
            "{a} − {b} vs {cost}"
        );
    }
}

#[test]
fn a_reached_goal_terminates_with_goal_reached_only_when_asked() {
    for terminate in [true, false] {
        let task = TaskKind::Reach {
            end_effector: "arm".into(),
            point: None,
            target: ReachTarget::Fixed([10.0, 10.0, 25.0]),
            success_radius: 1.0,
            terminate_on_success: terminate,
        };
        let mut env = pendulum(task, 0.0);
        let flags = env.step(ActionType::Torque, &[0.0]).unwrap().flags;
        assert_eq!(flags.terminated, terminate);
        assert_eq!(
            flags.termination.map(|t| t.as_str()),
            terminate.then_some("goal_reached")
        );
        assert!(flags.reward > -1e-3);
    }
}

#[test]
fn track_rewards_minus_the_joint_error_and_stops_within_tolerance() {
    let task = |tolerance| TaskKind::Track {
        targets: vec![30.0],
        tolerance,
        terminate_on_success: tolerance > 0.0,
    };
    let mut env = pendulum(task(0.0), 0.0);
    let step = env.step(ActionType::Torque, &[0.0]).unwrap();
    assert!((f64::from(step.flags.reward) + 30.0).abs() < 1e-4);
    // Position control to the target: the goal band is entered, and that ends it.
    let mut env = pendulum(task(0.5), 0.0);
    let mut reached = None;
    for k in 0..240 {
        let flags = env.step(ActionType::Position, &[30.0]).unwrap().flags;
        if flags.terminated {
            reached = Some((k, flags));
            break;
        }
    }
    let (_, flags) = reached.expect("the joint settles at 30 deg within a second");
    assert_eq!(flags.termination.map(|t| t.as_str()), Some("goal_reached"));
    assert!(flags.reward >= -0.5);
}

#[test]
fn upright_pays_one_per_step_and_ends_with_fell_when_the_tilt_crosses_the_bound() {
    let task = TaskKind::Upright {
        instance: "arm".into(),
        axis: [0.0, 0.0, 1.0],
        max_tilt_deg: 30.0,
    };
    let mut env = pendulum(task, 0.0);
    // A push, then the upright arm falls under gravity; its tilt is its hinge angle.
    let mut action = [1e-4_f32];
    let mut previous_angle = 0.0_f32;
    for _ in 0..480 {
        let step = env.step(ActionType::Torque, &action).unwrap();
        action = [0.0];
        let angle = step.observation.joint_positions[0].abs();
        if step.flags.terminated {
            assert_eq!(step.flags.termination.map(|t| t.as_str()), Some("fell"));
            assert_eq!(step.flags.reward, 0.0);
            assert!(
                angle > 30.0 && previous_angle <= 30.0,
                "{previous_angle} → {angle}"
            );
            return;
        }
        assert_eq!(step.flags.reward, 1.0);
        assert!(angle <= 30.0 + 1e-3, "{angle}");
        previous_angle = angle;
    }
    panic!("the pendulum never fell");
}

#[test]
fn box_targets_are_drawn_per_reset_and_replay_by_seed() {
    let task = TaskKind::Reach {
        end_effector: "arm".into(),
        point: None,
        target: ReachTarget::Box {
            min: [0.0, -10.0, 30.0],
            max: [20.0, 10.0, 30.0],
        },
        success_radius: 0.0,
        terminate_on_success: false,
    };
    let mut env = pendulum(task, 0.0);
    let a = env.reset(Some(1)).task;
    let b = env.reset(None).task;
    assert_ne!(a, b, "a new target every reset");
    for t in [&a, &b] {
        assert!(
            (0.0..=20.0).contains(&t[0]) && (-10.0..=10.0).contains(&t[1]) && t[2] == 30.0,
            "{t:?}"
        );
    }
    assert_eq!(
        env.reset(Some(1)).task,
        a,
        "the same seed draws the same target"
    );
    assert_ne!(env.reset(Some(2)).task, a);
}

#[test]
fn bad_tasks_get_exact_errors_with_their_paths() {
    let cases = [
        (
            reach_to("tip"),
            0.0,
            "task.reach.end_effector: unknown instance \"tip\" (known: \"base\", \"arm\")",
        ),
        (
            reach([f64::NAN, 0.0, 0.0]),
            0.0,
            "task.reach.target.x: expected a finite coordinate within ±100000000 mm, got NaN",
        ),
        (
            reach([0.0; 3]),
            -1.0,
            "task.action_cost: expected a finite weight >= 0, got -1",
        ),
        (
            TaskKind::Reach {
                end_effector: "arm".into(),
                point: None,
                target: ReachTarget::Box {
                    min: [0.0, 5.0, 0.0],
                    max: [1.0, 4.0, 1.0],
                },
                success_radius: 0.0,
                terminate_on_success: false,
            },
            0.0,
            "task.reach.target_box.max.y: expected at least min.y = 5, got 4",
        ),
        (
            TaskKind::Reach {
                end_effector: "arm".into(),
                point: None,
                target: ReachTarget::Fixed([0.0; 3]),
                success_radius: 0.0,
                terminate_on_success: true,
            },
            0.0,
            "task.reach.terminate_on_success: needs a success_radius > 0 (mm)",
        ),
        (
            TaskKind::Track {
                targets: vec![1.0, 2.0],
                tolerance: 0.0,
                terminate_on_success: false,
            },
            0.0,
            "task.track.targets: expected one target per DOF (1), got 2",
        ),
        (
            TaskKind::Upright {
                instance: "arm".into(),
                axis: [0.0; 3],
                max_tilt_deg: 10.0,
            },
            0.0,
            "task.upright.axis: expected a direction, got the zero vector",
        ),
        (
            TaskKind::Upright {
                instance: "arm".into(),
                axis: [0.0, 0.0, 1.0],
                max_tilt_deg: 180.0,
            },
            0.0,
            "task.upright.max_tilt_deg: expected an angle in (0, 180) deg, got 180",
        ),
    ];
    for (task, cost, message) in cases {
        assert_eq!(error(task, cost), message);
    }
}

fn reach_to(instance: &str) -> TaskKind {
    TaskKind::Reach {
        end_effector: instance.into(),
        point: None,
        target: ReachTarget::Fixed([0.0; 3]),
        success_radius: 0.0,
        terminate_on_success: false,
    }
}

/// A cart-pole from primitives: a grounded rail, a cart on a driven slider along +X
/// (anchor at the cart's centre, (0, 0, 10) mm), and a 200 mm pole on a passive hinge
/// about +Y at the cart's top, standing upright.
fn cart_pole(pole_joint_extra: serde_json::Value) -> String {
    let mut hinge = serde_json::json!({
        "type": "revolute", "name": "hinge", "parent": "cart", "child": "pole",
        "anchor": {"x": 0, "y": 0, "z": 20}, "axis": {"x": 0, "y": 1, "z": 0},
        "actuated": false
    });
    if let (Some(h), serde_json::Value::Object(extra)) = (hinge.as_object_mut(), pole_joint_extra) {
        h.extend(extra);
    }
    serde_json::json!({
        "parts": [
            {"name": "Rail", "primitive": {"type": "cube", "size": {"x": 400, "y": 20, "z": 10}}},
            {"name": "Cart", "primitive": {"type": "cube", "size": {"x": 40, "y": 30, "z": 20}}},
            {"name": "Pole", "primitive": {"type": "cube", "size": {"x": 4, "y": 4, "z": 200}}}
        ],
        "assembly": {
            "instances": [
                {"part": "Rail", "name": "rail", "position": {"x": -200, "y": -10, "z": -10}},
                {"part": "Cart", "name": "cart", "position": {"x": -20, "y": -15, "z": 0}},
                {"part": "Pole", "name": "pole", "position": {"x": -2, "y": -2, "z": 20}}
            ],
            "joints": [
                {"type": "prismatic", "name": "slider", "parent": "rail", "child": "cart",
                 "anchor": {"x": 0, "y": 0, "z": 10}, "axis": {"x": 1, "y": 0, "z": 0},
                 "min": -150, "max": 150},
                hinge
            ]
        }
    })
    .to_string()
}

#[test]
fn a_passive_joint_is_observed_but_takes_no_action() {
    let upright = TaskKind::Upright {
        instance: "pole".into(),
        axis: [0.0, 0.0, 1.0],
        max_tilt_deg: 12.0,
    };
    let config = EnvConfig {
        task: Some(TaskSpec {
            kind: upright,
            action_cost: 0.0,
        }),
        ..EnvConfig::default()
    };
    let mut env = RobotEnv::from_json(&cart_pole(serde_json::json!({})), config).unwrap();
    let spec = env.spec().clone();
    assert_eq!(
        (spec.action_dim, spec.num_dofs, spec.observation_dim),
        (1, 2, 4)
    );
    assert!(spec.dofs[0].actuated && !spec.dofs[1].actuated);
    let err = env.step(ActionType::Torque, &[0.0, 0.0]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "values: expected 1 action value (one per actuated DOF), got 2"
    );
    // Pushing the cart along +X tips the free pole back (a negative angle about +Y)
    // until it falls past 12°.
    let mut fell = None;
    for k in 0..480 {
        let step = env.step(ActionType::Torque, &[0.05]).unwrap();
        if step.flags.terminated {
            fell = Some((k, step));
            break;
        }
        assert_eq!(step.flags.reward, 1.0);
    }
    let (_, step) = fell.expect("the pole falls");
    assert_eq!(step.flags.termination.map(|t| t.as_str()), Some("fell"));
    let [cart_x, pole_angle] = [
        step.observation.joint_positions[0],
        step.observation.joint_positions[1],
    ];
    assert!(
        cart_x > 0.0 && pole_angle < -12.0,
        "cart {cart_x} mm, pole {pole_angle} deg"
    );
}

#[test]
fn a_passive_joint_gets_no_motor_under_position_targets() {
    let mut env =
        RobotEnv::from_json(&cart_pole(serde_json::json!({})), EnvConfig::default()).unwrap();
    for _ in 0..5 {
        env.step(ActionType::Torque, &[0.05]).unwrap();
    }
    // Hold the cart still by position control: the tipped pole keeps falling.
    let mut angle = 0.0;
    for _ in 0..480 {
        angle = env
            .step(ActionType::Position, &[0.0])
            .unwrap()
            .observation
            .joint_positions[1];
    }
    assert!(angle < -30.0, "the pole fell freely: {angle} deg");
}

#[test]
fn a_passive_joint_with_max_effort_is_refused() {
    let document = cart_pole(serde_json::json!({"max_effort": 1.0}));
    let Err(err) = RobotEnv::from_json(&document, EnvConfig::default()) else {
        panic!("accepted");
    };
    assert!(
        err.to_string().contains(
            "assembly.joints[1].max_effort: a passive joint (\"actuated\": false) takes no effort to clamp"
        ),
        "{err}"
    );
}
