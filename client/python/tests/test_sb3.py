"""gymfleet.sb3 against Stable-Baselines3's own code.

The reference is SB3's ``DummyVecEnv`` over single ``gymfleet/<Name>-v5`` envs (each in
SB3's ``Monitor``): the adapter over one batch must return the same observations, rewards,
dones and per-env infos (``terminal_observation``, ``TimeLimit.truncated``, ``episode``),
and SB3's wrappers (``VecMonitor``, ``VecCheckNan``) must run on it.

SB3's package imports torch, which CI never installs (``.ci/run`` installs SB3's files with
``--no-deps``). Where torch is missing, ``sb3`` below loads SB3's vec-env modules by path
under their own names, with ``torch`` an empty module (two placeholder classes for the
annotations SB3's functions carry): the code exercised here never touches it. With torch installed, SB3 is imported normally.
"""

from __future__ import annotations

import importlib
import importlib.util
import pathlib
import sys
import types
from typing import Any

import gymnasium
import numpy as np
import pytest

import gymfleet  # noqa: F401  (registers the ids)

MODULES = [
    "common.vec_env.base_vec_env",
    "common.vec_env.patch_gym",
    "common.preprocessing",
    "common.vec_env.util",
    "common.vec_env.dummy_vec_env",
    "common.vec_env.vec_monitor",
    "common.vec_env.vec_check_nan",
    "common.monitor",
]


def _load_sb3_without_torch() -> types.SimpleNamespace:
    spec = importlib.util.find_spec("stable_baselines3")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("stable-baselines3 is not installed (.ci/run installs its files)")
    root = pathlib.Path(list(spec.submodule_search_locations)[0])
    # Packages as namespaces, so that their __init__ (which imports torch) never runs.
    for name, path in [
        ("stable_baselines3", root),
        ("stable_baselines3.common", root / "common"),
        ("stable_baselines3.common.vec_env", root / "common" / "vec_env"),
    ]:
        if name not in sys.modules:
            package = types.ModuleType(name)
            package.__path__ = [str(path)]
            sys.modules[name] = package
    for name in ("torch", "torch.nn", "torch.nn.functional"):
        sys.modules.setdefault(name, types.ModuleType(name))
    torch = sys.modules["torch"]
    # Names that SB3's annotations evaluate when its functions are defined.
    for name in ("Tensor", "device"):
        if not hasattr(torch, name):
            setattr(torch, name, type(name, (), {}))
    torch.nn = sys.modules["torch.nn"]  # type: ignore[attr-defined]
    sys.modules["torch.nn"].functional = sys.modules["torch.nn.functional"]  # type: ignore[attr-defined]
    for module in MODULES:
        importlib.import_module(f"stable_baselines3.{module}")
    return _namespace()


def _namespace() -> types.SimpleNamespace:
    m = lambda name: sys.modules[f"stable_baselines3.{name}"]  # noqa: E731
    return types.SimpleNamespace(
        VecEnv=m("common.vec_env.base_vec_env").VecEnv,
        DummyVecEnv=m("common.vec_env.dummy_vec_env").DummyVecEnv,
        VecMonitor=m("common.vec_env.vec_monitor").VecMonitor,
        VecCheckNan=m("common.vec_env.vec_check_nan").VecCheckNan,
        Monitor=m("common.monitor").Monitor,
    )


@pytest.fixture(scope="module")
def sb3() -> types.SimpleNamespace:
    if importlib.util.find_spec("torch") is None:
        return _load_sb3_without_torch()
    for module in MODULES:
        importlib.import_module(f"stable_baselines3.{module}")
    return _namespace()


@pytest.fixture(scope="module")
def adapter(sb3: types.SimpleNamespace) -> Any:
    from gymfleet import sb3 as module

    return module


def _pair(sb3: Any, adapter: Any, name: str, n: int, seed: int, **kwargs: Any) -> Any:
    ours = adapter.make_vec_env(name, n_envs=n, seed=seed, **kwargs)
    reference = sb3.DummyVecEnv(
        [lambda: sb3.Monitor(gymnasium.make(name, **kwargs)) for _ in range(n)]
    )
    reference.seed(seed)
    return ours, reference


@pytest.mark.parametrize("n", [4, 1])
def test_the_adapter_steps_like_sb3s_dummy_vec_env_over_the_same_envs(sb3: Any, adapter: Any, n: int) -> None:
    # Hopper falls under random actions (terminated) and a 25-step limit cuts the rest
    # (truncated): both kinds of episode end, several times per env. One env is stepped
    # as the id's single env, not as a batch of one.
    ours, reference = _pair(sb3, adapter, "gymfleet/Hopper-v5", n, seed=3, max_episode_steps=25)
    assert isinstance(ours, sb3.VecEnv)
    assert ours.num_envs == n
    assert ours.observation_space == reference.observation_space
    assert ours.action_space == reference.action_space
    np.testing.assert_array_equal(ours.reset(), reference.reset())
    rng = np.random.default_rng(0)
    ends = {"terminated": 0, "truncated": 0}
    for _ in range(320 // n):
        actions = rng.uniform(-1, 1, (n, 3)).astype(np.float32)
        obs, rewards, dones, infos = ours.step(actions)
        ref_obs, ref_rewards, ref_dones, ref_infos = reference.step(actions)
        np.testing.assert_array_equal(obs, ref_obs)
        assert rewards.dtype == ref_rewards.dtype == np.float32
        np.testing.assert_array_equal(rewards, ref_rewards)
        assert dones.dtype == ref_dones.dtype == np.bool_
        np.testing.assert_array_equal(dones, ref_dones)
        assert len(infos) == n
        for i in range(n):
            assert infos[i]["TimeLimit.truncated"] == ref_infos[i]["TimeLimit.truncated"]
            assert ("terminal_observation" in infos[i]) == bool(ref_dones[i])
            for key in ("x_position", "z_distance_from_origin", "reward_forward", "reward_ctrl"):
                assert infos[i][key] == ref_infos[i][key], key
            if ref_dones[i]:
                np.testing.assert_array_equal(
                    infos[i]["terminal_observation"], ref_infos[i]["terminal_observation"]
                )
                episode, ref_episode = infos[i]["episode"], ref_infos[i]["episode"]
                assert episode["l"] == ref_episode["l"]
                assert episode["r"] == pytest.approx(ref_episode["r"], rel=1e-6)
                ends["truncated" if infos[i]["TimeLimit.truncated"] else "terminated"] += 1
                assert ours.reset_infos[i].keys() == reference.reset_infos[i].keys()
            else:
                assert "episode" not in infos[i]
    assert ends["terminated"] >= 2 and ends["truncated"] >= 2, ends
    ours.close()
    reference.close()


def test_sb3s_wrappers_run_on_the_adapter(sb3: Any, adapter: Any) -> None:
    venv = adapter.make_vec_env("gymfleet/InvertedPendulum-v5", n_envs=8, seed=0)
    # The adapter writes Monitor's episode info itself, and says so: VecMonitor warns.
    assert venv.env_is_wrapped(sb3.Monitor) == [True] * 8
    assert venv.env_is_wrapped(gymnasium.wrappers.RecordEpisodeStatistics) == [False] * 8
    with pytest.warns(UserWarning, match="already wrapped with a `Monitor`"):
        monitored = sb3.VecMonitor(venv)
    checked = sb3.VecCheckNan(monitored, raise_exception=True)
    checked.reset()
    episodes = 0
    for _ in range(60):
        _, _, dones, infos = checked.step(np.full((8, 1), 3.0, dtype=np.float32))
        for i in np.flatnonzero(dones):
            episodes += 1
            # VecMonitor's own count of the episode agrees with the adapter's.
            assert infos[i]["episode"]["l"] > 0
    assert episodes >= 8
    with pytest.raises(ValueError, match="found nan in actions"):
        checked.step(np.full((8, 1), np.nan, dtype=np.float32))
    checked.close()


def test_seeds_attributes_and_methods(sb3: Any, adapter: Any) -> None:
    venv = adapter.make_vec_env("gymfleet/Reacher-v5", n_envs=3)
    assert venv.get_attr("render_mode") == [None] * 3
    assert venv.render_mode is None
    assert venv.has_attr("single_observation_space")
    assert not venv.has_attr("no_such_attribute")
    venv.seed(11)
    first = venv.reset()
    second = venv.reset()  # seeds are used once, as in SB3
    assert not np.array_equal(first, second)
    venv.seed(11)
    np.testing.assert_array_equal(venv.reset(), first)
    # Env i gets seed + i: env 1 of seed 11 starts like env 0 of seed 12.
    venv.seed(12)
    np.testing.assert_array_equal(venv.reset()[0], first[1])
    with pytest.warns(UserWarning, match="without a render_mode"):
        assert venv.env_method("render") == [None] * 3
    venv.close()
    # Any gymfleet batch that resets in the same step, e.g. a document's.
    from conftest import MODELS

    batch = gymfleet.make_vec(str(MODELS / "pendulum.json"), 3, autoreset_mode="same_step")
    venv = adapter.GymfleetSb3VecEnv(batch)
    venv.reset()
    assert venv.env_method("observe")[0].shape[0] == 3
    _, rewards, dones, infos = venv.step(np.zeros((3, 1), dtype=np.float32))
    assert rewards.shape == dones.shape == (3,) and len(infos) == 3
    venv.close()


def test_misuse_is_refused_with_a_clear_message(sb3: Any, adapter: Any) -> None:
    with pytest.raises(ValueError, match="autoreset_mode is set by the adapter"):
        adapter.make_vec_env("gymfleet/Reacher-v5", n_envs=2, autoreset_mode="next_step")
    plain = gymnasium.make_vec("gymfleet/Reacher-v5", 2, vectorization_mode="vector_entry_point")
    with pytest.raises(ValueError, match="must reset in the same step"):
        adapter.GymfleetSb3VecEnv(plain)
    plain.close()
    venv = adapter.make_vec_env("gymfleet/Reacher-v5", n_envs=2)
    venv.reset()
    with pytest.raises(RuntimeError, match="call step_async first"):
        venv.step_wait()
    venv.step_async(np.zeros((2, 2), dtype=np.float32))
    with pytest.raises(RuntimeError, match="a step is pending; call step_wait first"):
        venv.step_async(np.zeros((2, 2), dtype=np.float32))
    venv.step_wait()
    with pytest.raises(ValueError, match="one batch; an attribute can be set for all"):
        venv.set_attr("anything", 1, indices=[0])
    with pytest.raises(ValueError, match="one batch; a method is called once"):
        venv.env_method("observe", indices=1)
    venv.set_options([{"a": 1}, {"b": 2}])
    with pytest.raises(ValueError, match="one set of reset options"):
        venv.reset()
    venv.close()
