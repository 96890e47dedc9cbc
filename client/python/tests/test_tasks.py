"""Tasks from Python: rewards, terminations and the target in the observation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import gymfleet

REACH = {"reach": {"end_effector": "arm", "target": [20, 0, 40]}}


def test_the_guides_reaching_loop_is_one_task_field(pendulum):
    env = gymfleet.make(pendulum, end_effector_ids=["arm"], task=REACH)
    layout = env.env_info["observation_layout"]
    assert layout == [("joint_positions", 1), ("joint_velocities", 1), ("end_effector_poses", 7), ("target", 3)]
    obs, _ = env.reset(seed=0)
    assert obs.shape == (12,) and list(obs[-3:]) == [20, 0, 40]
    _, reward, terminated, _, _ = env.step([0.0])
    assert reward == pytest.approx(-math.sqrt(425), abs=1e-4) and not terminated
    env.close()


def test_goal_reached_is_a_termination_reason_in_batches(pendulum):
    task = {
        "reach": {"end_effector": "arm", "target": {"x": 10, "y": 10, "z": 25},
                  "success_radius": 1, "terminate_on_success": True},
        "action_cost": 0.5,
    }
    envs = gymfleet.make_vec(pendulum, 3, task=task, autoreset_mode=AutoresetMode.NEXT_STEP)
    envs.reset(seed=0)
    _, rewards, terminations, _, infos = envs.step(np.zeros((3, 1)))
    assert terminations.all()
    assert list(infos["termination_reason"]) == ["goal_reached"] * 3
    assert rewards.dtype == np.float32 and (rewards > -1e-3).all()
    envs.close()


def test_box_targets_differ_by_env_and_replay_by_seed(pendulum):
    task = {"reach": {"end_effector": "arm", "target_box": {"min": [0, -10, 30], "max": [20, 10, 50]}}}
    envs = gymfleet.make_vec(pendulum, 4, task=task)
    first, _ = envs.reset(seed=5)
    targets = first[:, -3:]
    assert len({tuple(t) for t in targets}) == 4
    assert ((targets >= [0, -10, 30]) & (targets <= [20, 10, 50])).all()
    again, _ = envs.reset(seed=5)
    np.testing.assert_array_equal(again[:, -3:], targets)
    envs.close()


def test_bad_tasks_are_invalid_argument_with_their_paths(pendulum):
    with pytest.raises(gymfleet.InvalidArgument, match='task.reach.end_effector: unknown instance "tip"'):
        gymfleet.make(pendulum, task={"reach": {"end_effector": "tip", "target": [0, 0, 0]}})
    with pytest.raises(gymfleet.InvalidArgument, match="task.reach.target: expected exactly one of target and target_box"):
        gymfleet.make(pendulum, task={"reach": {"end_effector": "arm"}})
    with pytest.raises(gymfleet.InvalidArgument, match="task: expected exactly one of reach, track, upright"):
        gymfleet.make(pendulum, task={"reach": {"end_effector": "arm"}, "track": {}})
    with pytest.raises(gymfleet.InvalidArgument, match="task.track: unknown field.*tolerence"):
        gymfleet.make(pendulum, task={"track": {"targets": [0], "tolerence": 1}})
    with pytest.raises(gymfleet.InvalidArgument, match="task.upright.max_tilt_deg: expected an angle in \\(0, 180\\) deg, got 0"):
        gymfleet.make(pendulum, task={"upright": {"instance": "arm"}})


def test_randomized_envs_report_their_draws(pendulum, arm2):
    envs = gymfleet.make_vec(arm2, 3, randomize={"mass_scale": [0.5, 2.0], "damping_scale": {"min": 1, "max": 3}})
    envs.reset(seed=2)
    draws = [envs.randomization(i) for i in range(3)]
    assert [n for n, _, _ in draws[0]["instances"]] == ["base", "upper", "forearm"]
    assert len({d["instances"][1][1] for d in draws}) == 3, "each env draws its own"
    assert all(0.5 <= m <= 2.0 and f == 1.0 for d in draws for _, m, f in d["instances"])
    envs.reset(seed=2)
    assert [envs.randomization(i) for i in range(3)] == draws, "the same seed, the same draws"
    envs.close()
    # A heavier arm turns less under the same torque.
    turns = []
    for factor in (1.0, 2.0):
        env = gymfleet.make(pendulum, randomize={"mass_scale": [factor, factor]})
        env.reset()
        turns.append(env.step([1e-4])[0][0])
        draw = env.randomization()["instances"][1]
        assert draw == ("arm", factor, 1.0)
        assert (draw.name, draw.mass_scale, draw.friction_scale) == ("arm", factor, 1.0)
        assert isinstance(draw, gymfleet.InstanceDraw)
        joint = env.randomization()["joints"][0]
        assert isinstance(joint, gymfleet.JointDraw)
        assert (joint.damping_scale, joint.gain_scale) == (1.0, 1.0)
        env.close()
    assert turns[1] == pytest.approx(turns[0] / 2, rel=0.01)
    env = gymfleet.make(pendulum)
    with pytest.raises(gymfleet.FailedPrecondition, match="was created without randomize"):
        env.randomization()
    with pytest.raises(gymfleet.InvalidArgument, match=r"randomize.mass_scale: expected factors 0.01 <= min <= max <= 100, got \[2, 1\]"):
        gymfleet.make(pendulum, randomize={"mass_scale": [2, 1]})
    with pytest.raises(gymfleet.InvalidArgument, match="randomize: unknown field.*mass"):
        gymfleet.make(pendulum, randomize={"mass": [1, 2]})
