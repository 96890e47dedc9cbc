"""manipulator-bring_ball against dm_control itself: where the ball and the target start
(in the hand, in the target, or anywhere, in dm_control's shares), the symmetric hand,
and the reward where the ball is brought. The shared checks (spec, observation and
reward on the same state, contact-free starts) are in ``test_dmc.py``."""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest

from gymfleet.dmc import TASKS

with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # glfw: no display
    from dm_control import suite

ID = "gymfleet/ManipulatorBringBall-v1"
STARTS = 300


def _kind(ball_q, ball_v, target, grasp, grasp_angle):
    """Which of dm_control's three starts a state is: ``ball_q`` (x, z, angle),
    ``target`` (x, z, angle) and the grasp site's (x, z) and turned angle. The ball may
    move along x in every kind: dm_control sets that velocity in its "anywhere" draw and
    keeps it when a draw is rejected and the next is another kind."""
    assert ball_v[1] == ball_v[2] == 0.0 and -5.0 <= ball_v[0] <= 5.0, ball_v
    if np.allclose(ball_q[:2], target[:2], atol=1e-5):
        assert ball_q[2] == pytest.approx(target[2], abs=1e-5)
        return "in_target"
    if np.allclose(ball_q[:2], grasp, atol=1e-5):
        assert np.cos(ball_q[2] - grasp_angle) == pytest.approx(1.0, abs=1e-6)
        return "in_hand"
    assert -0.5 <= ball_q[0] <= 0.5 and 0.0 <= ball_q[1] <= 0.7, ball_q
    assert 0.0 <= ball_q[2] <= 2 * np.pi, ball_q
    return "uniform"


def _grasp(physics):
    """The grasp site's (x, z), and dm_control's ball angle in the hand."""
    data = physics.named.data
    xx, zx = data.site_xmat["grasp", ["xx", "zx"]]
    return data.site_xpos["grasp", ["x", "z"]], np.pi - np.arctan2(zx, xx)


def _target_pose(xz, quat):
    w, y = quat[0], quat[2]
    return np.array([xz[0], xz[1], 2 * np.arctan2(y, w)])


def _dm_shares():
    theirs = suite.load("manipulator", "bring_ball", task_kwargs={"random": 7})
    kinds, moving = [], 0
    for _ in range(STARTS):
        theirs.reset()
        physics = theirs.physics
        q, v = physics.named.data.qpos, physics.named.data.qvel
        model = physics.named.model
        target = _target_pose(model.body_pos["target_ball", ["x", "z"]], model.body_quat["target_ball"])
        grasp, angle = _grasp(physics)
        kinds.append(_kind(q[["ball_x", "ball_z", "ball_y"]], v[["ball_x", "ball_z", "ball_y"]],
                           target, grasp, angle))
        moving += kinds[-1] != "uniform" and v["ball_x"] != 0.0
    return _shares(kinds, moving)


def _shares(kinds, moving):
    """Each kind's share of the starts, and the share placed in the hand or the target
    that still moves (a rejected draw's velocity)."""
    out = {k: kinds.count(k) / STARTS for k in ("in_hand", "in_target", "uniform")}
    out["moving"] = moving / STARTS
    return out


def test_the_ball_starts_in_the_hand_in_the_target_or_anywhere_in_dm_controls_shares():
    """Each of gymfleet's starts, put into dm_control's physics, is one of dm_control's
    three kinds exactly (the ball at the grasp site turned half a turn, at the target's
    pose, or in the box with an x velocity), with the hand symmetric, the target in its
    box, and no contact; the kinds' shares match dm_control's own starts (after both
    draw again while anything touches) within 0.06."""
    task = TASKS[ID]
    env = gym.make(ID)
    theirs = suite.load("manipulator", "bring_ball", task_kwargs={"random": 0})
    theirs.reset()
    physics = theirs.physics
    kinds, angles, moving = [], [], 0
    for seed in range(STARTS):
        env.reset(seed=seed)
        data = env.unwrapped.data
        q, v = data.qpos, data.qvel
        assert q[6] == q[4], "finger at thumb"
        obs = env.unwrapped.observation_dict()
        target = _target_pose(obs["target_pos"][:2], [obs["target_pos"][2], 0.0, obs["target_pos"][3]])
        assert -0.4 <= target[0] <= 0.4 and 0.1 <= target[1] <= 0.4
        angles.append(target[2])
        with physics.reset_context():
            physics.set_state(np.concatenate([q, v]))
        assert physics.data.ncon == 0, f"seed {seed}: {physics.data.ncon} contacts in MuJoCo"
        grasp, angle = _grasp(physics)
        kinds.append(_kind(q[8:11], v[8:11], target, grasp, angle))
        moving += kinds[-1] != "uniform" and v[8] != 0.0
    ours = _shares(kinds, moving)
    theirs_shares = _dm_shares()
    for kind, share in ours.items():
        assert share == pytest.approx(theirs_shares[kind], abs=0.06), (ours, theirs_shares)
    assert min(ours.values()) > 0.01, ours
    assert min(angles) < -2.5 and max(angles) > 2.5, "the target turned by any angle"
    env.close()
    assert task.reset_noise["choice"]["options"][0]["frame"] == "grasp"


def test_the_reward_where_the_ball_is_in_the_target_is_dm_controls():
    """Starts with the ball in the target earn about 1 (the target sits 1 mm behind the
    ball's plane), on both sides; near misses earn less, as dm_control computes."""
    env = gym.make(ID)
    theirs = suite.load("manipulator", "bring_ball", task_kwargs={"random": 0})
    theirs.reset()
    physics = theirs.physics
    zero = np.zeros(env.action_space.shape, dtype=np.float32)
    bands = set()
    for seed in range(60):
        env.reset(seed=seed)
        _, reward, *_ = env.step(zero)
        data = env.unwrapped.data
        bodies = env.unwrapped.gymfleet_env.bodies()
        centers = np.asarray(bodies["centers_of_mass"]).reshape(-1, 3)
        poses = np.asarray(bodies["site_poses"]).reshape(-1, 7)
        physics.named.model.body_pos["target_ball"] = centers[list(bodies["instances"]).index("target_ball")]
        physics.named.model.body_quat["target_ball"] = poses[list(bodies["sites"]).index("target_ball")][3:]
        with physics.reset_context():
            physics.set_state(np.concatenate([data.qpos, data.qvel]))
        want = theirs.task.get_reward(physics)
        assert reward == pytest.approx(want, abs=1e-4), seed
        bands.add(round(want, 1))
    assert 1.0 in bands and 0.0 in bands, bands
    env.close()
