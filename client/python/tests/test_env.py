"""`gymfleet.make` and `gymnasium.make`: gymnasium's own checker, spaces, documents,
closing and garbage collection."""

from __future__ import annotations

import gc
import json
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import gymfleet
from conftest import MODELS

#: What check_env says about gymnasium's own MuJoCo envs too (docs/design.md §6.2): infinite
#: Box bounds (velocities are unbounded; so are torques without `max_effort`), and
#: un-normalised action ranges.
EXPECTED_WARNINGS = (
    "observation space minimum value is -infinity. This is probably too low.",
    "observation space maximum value is infinity. This is probably too high.",
    "action space minimum value is -infinity. This is probably too low.",
    "action space maximum value is infinity. This is probably too high.",
    "For Box action spaces, we recommend using a symmetric and normalized space",
)


def checked(env: gym.Env) -> list:
    """check_env's warnings about `env` that are not expected."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env)
    return [str(w.message) for w in caught if not any(e in str(w.message) for e in EXPECTED_WARNINGS)]


@pytest.mark.parametrize("env_id", ["gymfleet/Pendulum-v0", "gymfleet/Arm2-v0"])
def test_registered_seed_envs_pass_gymnasiums_checker(env_id):
    env = gym.make(env_id)
    assert checked(env.unwrapped) == []
    env.close()


@pytest.mark.parametrize("name,effector", [("pendulum", "arm"), ("arm2", "forearm")])
def test_make_of_the_seed_documents_passes_gymnasiums_checker(name, effector):
    env = gymfleet.make(MODELS / f"{name}.json", end_effector_ids=[effector])
    assert checked(env) == []
    env.close()


def test_spaces_come_from_the_envs_limits(arm2):
    arm2["assembly"]["joints"][0]["max_effort"] = 0.002
    env = gymfleet.make(arm2, end_effector_ids=["forearm"])
    assert env.observation_space.shape == (2 + 2 + 7,)
    assert env.observation_space.dtype == np.float32
    # The clamp bounds the first joint; the second has none, so the server derives its
    # bound from the model (twice the torque that holds the forearm level).
    forearm = env.env_info["joints"][1]
    assert forearm["max_effort"] is None
    derived = forearm["action_bounds"][0]
    assert 1e-6 < derived < 1e-3
    np.testing.assert_array_equal(env.action_space.low, np.float32([-0.002, -derived]))
    np.testing.assert_array_equal(env.action_space.high, np.float32([0.002, derived]))
    assert env.env_info["joints"][0]["max_effort"] == 0.002
    assert env.env_info["joints"][0]["action_bounds"] == [0.002]
    env.close()
    env = gymfleet.make(arm2, action_type="position")
    np.testing.assert_array_equal(env.action_space.low, [-90, -120])
    np.testing.assert_array_equal(env.action_space.high, [90, 0])
    env.close()
    env = gymfleet.make(arm2, action_type="velocity")
    assert np.all(np.isinf(env.action_space.high))
    env.close()


def test_normalize_actions_maps_minus_one_to_one_onto_the_range(arm2):
    env = gymfleet.make(arm2, action_type="position", normalize_actions=True, substeps=5)
    assert env.action_space == gym.spaces.Box(-1, 1, (2,), np.float32)
    raw = gymfleet.make(arm2, action_type="position", substeps=5)
    env.reset(seed=3)
    raw.reset(seed=3)
    for a in ([1.0, -1.0], [0.0, 0.5], [-1.0, 1.0]):
        # [-1, 1] onto [-90, 90] and [-120, 0]
        target = [90 * a[0], -60 + 60 * a[1]]
        assert np.array_equal(env.step(a)[0], raw.step(target)[0])
    with pytest.raises(gymfleet.InvalidArgument, match="normalize_actions: velocity targets have no range"):
        gymfleet.make(arm2, action_type="velocity", normalize_actions=True)


def test_a_document_without_max_effort_gets_sensible_torque_actions():
    """The seed arm, loaded by path, has no max_effort: its action space is still finite,
    sampled torques move it like a motor, not a cannon, and normalised torques work."""
    env = gymfleet.make(MODELS / "arm2.json", end_effector_ids=["forearm"], substeps=5)
    bounds = env.action_space.high
    assert np.all(np.isfinite(bounds)) and np.all(bounds > 0)
    np.testing.assert_array_equal(env.action_space.low, -bounds)
    # The shoulder holds the whole arm, the elbow the forearm alone.
    assert bounds[0] > bounds[1]
    env.action_space.seed(0)
    env.reset(seed=0)
    speeds = []
    for _ in range(60):
        obs, *_ = env.step(env.action_space.sample())
        speeds.append(np.abs(obs[2:4]).max())
    # deg/s: under a sampled torque within twice the gravity torque, the arm swings at
    # hundreds of deg/s at most (a 1 N·m sample used to reach ~1.4e6 deg/s).
    assert 1.0 < max(speeds) < 5000.0, max(speeds)
    env.close()
    normalized = gymfleet.make(MODELS / "arm2.json", normalize_actions=True)
    raw = gymfleet.make(MODELS / "arm2.json")
    normalized.reset(seed=1)
    raw.reset(seed=1)
    for a in ([1.0, -1.0], [0.25, 0.5]):
        np.testing.assert_array_equal(normalized.step(a)[0], raw.step(np.float32(a) * bounds)[0])
    normalized.close()
    raw.close()


def test_a_document_is_a_dict_a_json_string_or_a_path(arm2):
    for document in (arm2, json.dumps(arm2), MODELS / "arm2.json", str(MODELS / "arm2.json")):
        env = gymfleet.make(document, end_effector_ids=["forearm"])
        assert env.reset(seed=0)[0].shape == (11,)
        env.close()
    with pytest.raises(gymfleet.InvalidArgument, match="document: expected a dict, JSON, MJCF or URDF text or the path of a file, got 'no/such/file.json'"):
        gymfleet.make("no/such/file.json")
    with pytest.raises(TypeError, match="unexpected option.*end_effectors"):
        gymfleet.make(arm2, end_effectors=["forearm"])


def test_steps_report_measurements_and_episode_ends(pendulum):
    env = gymfleet.make(pendulum, end_effector_ids=["arm"], max_steps=3)
    obs, info = env.reset(seed=0)
    assert obs.dtype == np.float32 and info == {}
    for k in range(1, 4):
        obs, reward, terminated, truncated, info = env.step(np.array([1e-4]))
        assert (reward, terminated, info["episode_step"]) == (0.0, False, k)
        assert truncated == (k == 3)
    assert obs[0] > 0, "a positive torque turns the joint the positive way"
    env.close()


def test_close_frees_the_env_and_is_idempotent(server, arm2):
    env = gymfleet.make(arm2, server=server.address)
    assert gymfleet.server_info(server.address)["envs"] == 1
    env.close()
    env.close()
    assert gymfleet.server_info(server.address)["envs"] == 0
    with gymfleet.make(arm2, server=server.address) as env:
        env.reset()
    assert gymfleet.server_info(server.address)["envs"] == 0


def test_a_garbage_collected_env_is_freed(server, arm2):
    env = gymfleet.make(arm2, server=server.address)
    vec = gymfleet.make_vec(arm2, 8, server=server.address)
    info = gymfleet.server_info(server.address)
    assert (info["envs"], info["batches"], info["batch_envs"]) == (1, 1, 8)
    del env, vec
    gc.collect()
    info = gymfleet.server_info(server.address)
    assert (info["envs"], info["batches"]) == (0, 0)


def test_server_info_has_an_instance_id_per_server_process():
    a, b = gymfleet.Server(threads=1), gymfleet.Server(threads=1)
    try:
        ida = gymfleet.server_info(a.address)["instance_id"]
        assert len(ida) == 32 and int(ida, 16) >= 0
        assert gymfleet.server_info(a.address)["instance_id"] == ida
        assert gymfleet.server_info(b.address)["instance_id"] != ida
    finally:
        a.stop()
        b.stop()


def test_the_package_exports_its_own_names_only():
    """`dir(gymfleet)` holds `__all__`, the submodules and dunder names: no `typing` names,
    no helpers the package's code was written with."""
    import types

    extra = [n for n in dir(gymfleet) if not n.startswith("_") and n not in gymfleet.__all__]
    assert all(isinstance(getattr(gymfleet, n), types.ModuleType) for n in extra), extra
    assert not {"Any", "Optional", "Dict", "json", "gymnasium"} & set(dir(gymfleet))


def test_a_fork_continues_from_the_same_state_on_its_own(arm2):
    env = gymfleet.make(arm2, end_effector_ids=["forearm"], reset_noise=5.0)
    env.reset(seed=3)
    for _ in range(5):
        env.step(np.array([2e-4, -1e-4], dtype=np.float32))
    twin = env.fork()
    assert twin.env_id != env.env_id
    np.testing.assert_array_equal(twin.observe(), env.observe())
    for _ in range(10):
        a = env.step(np.array([-1e-4, 2e-4], dtype=np.float32))
        b = twin.step(np.array([-1e-4, 2e-4], dtype=np.float32))
        np.testing.assert_array_equal(a[0], b[0])
        assert a[1:4] == b[1:4]
    # Independent: stepping one leaves the other where it was.
    before = twin.observe()
    env.step(np.array([1e-3, 1e-3], dtype=np.float32))
    np.testing.assert_array_equal(twin.observe(), before)
    twin.close()
    env.close()


def test_a_forked_batch_continues_every_env(arm2):
    envs = gymfleet.make_vec(arm2, 3, end_effector_ids=["forearm"], reset_noise=5.0)
    envs.reset(seed=1)
    actions = np.full((3, 2), 1e-4, dtype=np.float32)
    envs.step(actions)
    twin = envs.fork()
    assert twin.num_envs == 3
    for _ in range(5):
        np.testing.assert_array_equal(envs.step(actions)[0], twin.step(actions)[0])
    twin.close()
    envs.close()


def test_list_models_shows_the_servers_library(tmp_path):
    for name in ("arm2", "pendulum"):
        (tmp_path / f"{name}.json").write_text((MODELS / f"{name}.json").read_text())
    with gymfleet.Server(threads=1, models=str(tmp_path)) as server:
        assert gymfleet.list_models(server.address) == [
            {"name": "arm2", "format": "json", "dofs": 2, "action_dim": 2},
            {"name": "pendulum", "format": "json", "dofs": 1, "action_dim": 1},
        ]
        env = gymfleet.make(model="arm2", server=server.address)
        assert env.action_space.shape == (2,)
        env.close()
    # The embedded server has no library.
    assert gymfleet.list_models() == []
