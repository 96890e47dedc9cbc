"""MuJoCo-shaped state access on the v5 ids: ``env.unwrapped.data`` (``qpos``, ``qvel``,
``ctrl``, ``xpos``, ``xquat``, ``xipos``, ``site_xpos``, ``cinert``, ``cvel``, ``cfrc_ext``,
``qfrc_actuator``, ``body()``, ``site()``), ``model`` (``nq``, ``nv``, ``nu``, ``nbody``,
``body_mass``, ``opt.timestep``, ``actuator_ctrlrange``), ``init_qpos``/``init_qvel``,
``set_state``, ``get_body_com``, ``state_vector()`` and ``observation_structure``, in MuJoCo's shapes and SI units,
checked against Gymnasium's env on the same state; what is not offered says so."""

from __future__ import annotations

import warnings

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
    with pytest.raises(AttributeError, match=r"^data\.qacc is not offered by gymfleet's envs \(they offer data\.qpos, data\.qvel, data\.ctrl, data\.xpos"):
        env.data.qacc
    with pytest.raises(AttributeError, match=r"^model\.geom_size is not offered by gymfleet's envs \(they offer model\.nq"):
        env.model.geom_size
    with pytest.raises(ValueError, match="read-only"):
        env.data.qpos[0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        env.data.xpos[1, 0] = 1.0
    with pytest.raises(AttributeError, match=r"^model\.opt\.timestep cannot be changed on a gymfleet env"):
        env.model.opt.timestep = 0.05
    with pytest.raises(AttributeError, match=r"^model\.nq cannot be changed on a gymfleet env"):
        env.model.nq = 3
    with pytest.raises(KeyError, match=r"Invalid name 'head'\. Valid names: \['world', 'torso', 'thigh', 'leg', 'foot'\]"):
        env.data.body("head")
    with pytest.raises(KeyError, match=r"Invalid body id 5: the model has 5"):
        env.data.body(5)
    env.close()


def test_a_server_with_room_for_one_env_makes_a_v5_env():
    # The noiseless twin that says where the env starts is closed before the env is made.
    with gymfleet.Server(threads=1, max_envs=1) as server:
        env = gymnasium.make("gymfleet/Hopper-v5", server=server.address)
        env.reset(seed=0)
        assert gymfleet.server_info(server.address)["envs"] == 1
        env.close()


def _same_state(ours, theirs, seed=1, steps=5):
    """Both envs stepped with the same actions; then MuJoCo's state, each limited joint's
    position put inside its range (MuJoCo's soft limits let a state sit past it), set on
    both sides. Returns that qpos and qvel."""
    ours.reset(seed=seed)
    theirs.reset(seed=seed)
    theirs.action_space.seed(seed)
    for _ in range(steps):
        action = theirs.action_space.sample()
        ours.step(action)
        theirs.step(action)
    qpos, qvel = theirs.data.qpos.copy(), theirs.data.qvel.copy()
    m = theirs.model
    for j in range(m.njnt):
        if m.jnt_limited[j] and m.jnt_type[j] in (2, 3):  # slide, hinge
            lo, hi = m.jnt_range[j]
            a = m.jnt_qposadr[j]
            qpos[a] = np.clip(qpos[a], lo + 1e-6, hi - 1e-6)
    ours.set_state(qpos, qvel)
    theirs.set_state(qpos, qvel)
    return qpos, qvel


#: Tolerances against MuJoCo on the same state (gymfleet's physics is float32).
POSE_ATOL = 1e-5
C_ATOL = 1e-4


@pytest.mark.parametrize("name", NAMES)
def test_every_field_is_mujocos_on_the_same_state(name):
    ours = gymnasium.make(f"gymfleet/{name}-v5").unwrapped
    theirs = gymnasium.make(f"{name}-v5").unwrapped
    qpos, qvel = _same_state(ours, theirs)
    assert np.array_equal(ours.data.qpos, qpos) and np.array_equal(ours.data.qvel, qvel)
    m, d = theirs.model, theirs.data
    assert ours.model.nbody == m.nbody and ours.model.nsite == m.nsite
    # Body masses: MuJoCo's from the geoms; the conversion's helpers weigh 1 mg each.
    np.testing.assert_allclose(ours.model.body_mass, m.body_mass, rtol=1e-6, atol=1e-5)
    for field in ("xpos", "xipos", "site_xpos"):
        np.testing.assert_allclose(getattr(ours.data, field), getattr(d, field), atol=POSE_ATOL, err_msg=field)
    # A quaternion and its negative are one orientation.
    ours_q, theirs_q = ours.data.xquat, d.xquat
    sign = np.where(np.sum(ours_q * theirs_q, axis=1) < 0, -1.0, 1.0)[:, None]
    np.testing.assert_allclose(ours_q * sign, theirs_q, atol=POSE_ATOL)
    np.testing.assert_allclose(ours.data.qfrc_actuator, d.qfrc_actuator, rtol=1e-5, atol=1e-5)
    # cinert and cvel are taken about each tree's root subtree centre of mass in MuJoCo,
    # about the robot's in gymfleet: the same point where the model is one tree.
    if len(set(m.body_rootid[1:])) == 1:
        np.testing.assert_allclose(ours.data.cinert, d.cinert, atol=C_ATOL, err_msg="cinert")
        np.testing.assert_allclose(ours.data.cvel, d.cvel, atol=C_ATOL, err_msg="cvel")
    # Contact forces depend on each solver's contacts: only the shape is MuJoCo's.
    assert ours.data.cfrc_ext.shape == d.cfrc_ext.shape
    assert np.array_equal(ours.get_body_com(m.body(1).name), ours.data.xpos[1])
    ours.close()
    theirs.close()


def test_a_set_state_then_steps_as_its_saved_state_does():
    first = gymnasium.make("gymfleet/Hopper-v5").unwrapped
    second = gymnasium.make("gymfleet/Hopper-v5").unwrapped
    theirs = gymnasium.make("Hopper-v5").unwrapped
    _same_state(first, theirs)
    second.reset(seed=7)
    second.gymfleet_env.load_state(first.gymfleet_env.save_state())
    first.action_space.seed(3)
    for _ in range(20):
        action = first.action_space.sample()
        a, *_ = first.step(action)
        b, *_ = second.step(action)
        assert np.array_equal(a, b), "bit for bit"
    for env in (first, second, theirs):
        env.close()


def test_set_state_refuses_a_wrong_shape_or_a_non_finite_value_and_changes_nothing():
    env = gymnasium.make("gymfleet/Hopper-v5").unwrapped
    env.reset(seed=0)
    qpos, qvel = env.data.qpos.copy(), env.data.qvel.copy()
    xpos = env.data.xpos.copy()
    cases = [
        (qpos[None, :], qvel, r"^set_state: qpos has shape \(1, 6\); the model's is \(6,\) \(model\.nq\)$"),
        (qpos, qvel[:5], r"^set_state: qvel has shape \(5,\); the model's is \(6,\) \(model\.nv\)$"),
        (np.where(np.arange(6) == 2, np.nan, qpos), qvel, r"^set_state: qpos\[2\] is nan; expected finite numbers$"),
        (qpos, np.full(6, np.inf), r"^set_state: qvel\[0\] is inf; expected finite numbers$"),
        ("up", qvel, r"^set_state: qpos must be numbers, got str$"),
    ]
    for q, v, message in cases:
        with pytest.raises(gymfleet.InvalidArgument, match=message):
            env.set_state(q, v)
        assert np.array_equal(env.data.qpos, qpos) and np.array_equal(env.data.xpos, xpos)
    env.close()


def test_a_state_past_a_soft_limit_is_taken_as_mujoco_takes_it():
    """MuJoCo's limits are soft (vendored patch 44): a joint may sit past one, pushed back
    by the limit's spring, so a state there is a state. (A document's hard limit clamps it,
    with a warning: `crates/env/tests/set_state.rs`.)"""
    env = gymnasium.make("gymfleet/Hopper-v5").unwrapped
    env.reset(seed=0)
    # Gymnasium's test_set_state's state: the leg joint (range [-150°, 0°]) at +0.0031327 rad.
    qpos = np.array([0.00136962, 1.24769787, -0.00459026, -0.00483472, 0.0031327, 0.00412756])
    qvel = np.zeros(6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        env.set_state(qpos, qvel)
    assert np.array_equal(env.data.qpos, qpos)
    server = env.gymfleet_env.observe()
    assert abs(server[4] - qpos[4]) < 1e-6 and abs(server[3] - qpos[3]) < 1e-6
    # The limit's spring pushes it back toward its range, as MuJoCo's does.
    theirs = gymnasium.make("Hopper-v5").unwrapped
    theirs.reset(seed=0)
    theirs.set_state(qpos, qvel)
    env.step(np.zeros(3, np.float32))
    theirs.step(np.zeros(3))
    assert env.data.qpos[4] < qpos[4] and theirs.data.qpos[4] < qpos[4]
    assert env.data.qpos[4] == pytest.approx(theirs.data.qpos[4], abs=1e-4)
    theirs.close()
    env.close()


def test_bodies_and_sites_by_name_and_the_fields_are_read_once_per_state():
    env = gymnasium.make("gymfleet/InvertedDoublePendulum-v5", reset_noise_scale=0.0).unwrapped
    env.reset(seed=0)
    calls = []
    inner = env.gymfleet_env

    class Counting:
        def bodies(self):
            calls.append(1)
            return inner.bodies()

    env._frames._env = Counting()
    # The tip's height at the start: 1.2 m, to float32 rounding.
    assert env.data.site("tip").xpos[2] == pytest.approx(1.2, abs=1e-6)
    assert np.array_equal(env.data.site(0).xpos, env.data.site_xpos[0])
    body = env.data.body("pole")
    assert np.array_equal(body.xpos, env.get_body_com("pole")) and body.id == 2
    assert env.model.body("pole").mass.shape == (1,)
    assert len(calls) == 1, "one read for the state"
    env.step(env.action_space.sample())
    assert len(calls) == 1, "a step reads nothing it is not asked for"
    env.data.xpos
    assert len(calls) == 2
    env.close()


#: Keywords that change an observation's structure, per id (besides the defaults).
_STRUCTURE_KWARGS = {
    "Hopper": {"exclude_current_positions_from_observation": False},
    "Swimmer": {"exclude_current_positions_from_observation": False},
    "Ant": {"include_cfrc_ext_in_observation": False},
    "Humanoid": {"include_cinert_in_observation": False, "include_qfrc_actuator_in_observation": False},
    "HumanoidStandup": {"exclude_current_positions_from_observation": False, "include_cvel_in_observation": False},
}


@pytest.mark.parametrize(
    "name,kwargs",
    [(name, {}) for name in NAMES] + list(_STRUCTURE_KWARGS.items()),
    ids=[f"{name}" for name in NAMES] + [f"{name}-switched" for name in _STRUCTURE_KWARGS],
)
def test_observation_structure_is_gymnasiums(name, kwargs):
    ours = gymnasium.make(f"gymfleet/{name}-v5", **kwargs).unwrapped
    theirs = gymnasium.make(f"{name}-v5", **kwargs).unwrapped
    # Reacher, Pusher and InvertedDoublePendulum have none, on both sides.
    assert hasattr(ours, "observation_structure") == hasattr(theirs, "observation_structure")
    if hasattr(theirs, "observation_structure"):
        assert ours.observation_structure == theirs.observation_structure
        assert all(type(v) is int for v in ours.observation_structure.values())
        # The parts but the skipped qpos fill the observation.
        parts = {k: v for k, v in ours.observation_structure.items() if k != "skipped_qpos"}
        assert sum(parts.values()) == ours.observation_space.shape[0]
    ours.close()
    theirs.close()
