"""MuJoCo-shaped read access on the v5 ids: ``env.unwrapped.data`` (``qpos``, ``qvel``,
``ctrl``), ``model`` (``nq``, ``nv``, ``nu``, ``opt.timestep``, ``actuator_ctrlrange``),
``init_qpos``/``init_qvel`` and ``state_vector()``, in MuJoCo's shapes and SI units, checked
against Gymnasium's env; what is not offered says so."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet  # noqa: F401  (registers the ids)
from gymfleet.suite import SUITE

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("mujoco")

NAMES = [spec.name for spec in SUITE.values()]


@pytest.mark.parametrize("name", NAMES)
def test_data_and_model_have_mujocos_shapes_and_constants(name):
    ours = gymnasium.make(f"gymfleet/{name}-v5").unwrapped
    theirs = gymnasium.make(f"{name}-v5").unwrapped
    for field in ("nq", "nv", "nu"):
        assert getattr(ours.model, field) == getattr(theirs.model, field), field
    assert ours.model.opt.timestep == theirs.model.opt.timestep
    # The action space's float32 bounds, widened (MuJoCo's are the XML's float64).
    assert np.array_equal(
        ours.model.actuator_ctrlrange, theirs.model.actuator_ctrlrange.astype(np.float32)
    )
    assert ours.init_qpos.shape == theirs.init_qpos.shape
    assert ours.init_qvel.shape == theirs.init_qvel.shape
    assert not ours.init_qvel.any()
    ours.reset(seed=0)
    assert ours.data.qpos.shape == theirs.data.qpos.shape
    assert ours.data.qvel.shape == theirs.data.qvel.shape
    assert np.array_equal(ours.data.ctrl, np.zeros(theirs.model.nu))
    action = ours.action_space.sample()
    obs, *_ = ours.step(action)
    assert np.array_equal(ours.data.ctrl, action.astype(np.float64))
    assert np.array_equal(ours.state_vector(), np.concatenate([ours.data.qpos, ours.data.qvel]))
    ours.close()
    theirs.close()


def test_the_state_is_the_observations_and_a_noiseless_reset_is_init_qpos():
    env = gymnasium.make("gymfleet/Hopper-v5", reset_noise_scale=0.0).unwrapped
    theirs = gymnasium.make("Hopper-v5").unwrapped
    assert np.array_equal(env.init_qpos, theirs.init_qpos.astype(np.float32))
    obs, _ = env.reset(seed=0)
    assert np.array_equal(env.data.qpos, env.init_qpos)
    assert np.array_equal(env.data.qvel, env.init_qvel)
    for _ in range(5):
        obs, *_ = env.step(env.action_space.sample())
        # Hopper's observation is qpos[1:] and clip(qvel, ±10), float32.
        assert np.array_equal(obs[:5], env.data.qpos[1:].astype(np.float32))
        assert np.array_equal(obs[5:], np.clip(env.data.qvel, -10, 10).astype(np.float32))
    env.close()
    theirs.close()


def test_what_is_not_offered_says_so_and_nothing_is_writable():
    env = gymnasium.make("gymfleet/Hopper-v5").unwrapped
    env.reset(seed=0)
    with pytest.raises(AttributeError, match=r"^data\.xpos is not offered by gymfleet's envs yet \(they offer data\.qpos, data\.qvel, data\.ctrl\)"):
        env.data.xpos
    with pytest.raises(AttributeError, match=r"^model\.body_mass is not offered by gymfleet's envs yet"):
        env.model.body_mass
    with pytest.raises(ValueError, match="read-only"):
        env.data.qpos[0] = 1.0
    with pytest.raises(AttributeError, match=r"^model\.opt\.timestep cannot be changed on a gymfleet env"):
        env.model.opt.timestep = 0.05
    with pytest.raises(AttributeError, match=r"^model\.nq cannot be changed on a gymfleet env"):
        env.model.nq = 3
    env.close()


def test_a_server_with_room_for_one_env_makes_a_v5_env():
    # The noiseless twin that says where the env starts is closed before the env is made.
    with gymfleet.Server(threads=1, max_envs=1) as server:
        env = gymnasium.make("gymfleet/Hopper-v5", server=server.address)
        env.reset(seed=0)
        assert gymfleet.server_info(server.address)["envs"] == 1
        env.close()
