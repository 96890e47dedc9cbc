"""The v5 ids' vector envs have the asynchronous API too (``batch_size``, ``async_reset``,
``send``, ``recv``, ``step(actions, env_id)``, ``step_async``/``step_wait``): each env's
observations, rewards, flags and ``info`` are the synchronous path's, bit for bit, in
whatever grouping envs come back, in both autoreset modes."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import gymfleet

N = 6
STEPS = 12


def actions_for(space, e, k):
    rng = np.random.default_rng(1000 * e + k)
    return rng.uniform(space.low, space.high).astype(np.float32)


def per_env(info, row):
    """One row's info values (masked keys only), as comparable bytes."""
    out = {}
    for key, value in info.items():
        if key.startswith("_") or key in ("env_id", "final_info"):
            continue
        if not info["_" + key][row]:
            continue
        out[key] = np.asarray(value[row]).tobytes()
    return out


def async_run(name, mode, batch_size, kwargs):
    envs = gymfleet.make_vec(f"gymfleet/{name}-v5", N, autoreset_mode=mode, batch_size=batch_size, **kwargs)
    assert envs.batch_size == batch_size
    space = envs.single_action_space
    envs.reset(seed=7)  # seeds the generators as the sync run's first reset does
    envs.async_reset()
    seen = [[] for _ in range(N)]
    while True:
        try:
            obs, rew, term, trunc, info = envs.recv()
        except RuntimeError:
            break
        ids = info["env_id"]
        assert obs.shape == (batch_size,) + envs.single_observation_space.shape
        assert rew.dtype == np.float64
        for row, e in enumerate(ids.tolist()):
            if not seen[e]:
                seen[e].append((obs[row].tobytes(), per_env(info, row)))
            else:
                seen[e].append((obs[row].tobytes(), float(rew[row]), bool(term[row]), bool(trunc[row]), per_env(info, row)))
        going = [int(e) for e in ids[::-1] if len(seen[e]) <= STEPS]
        if going:
            envs.send(np.stack([actions_for(space, e, len(seen[e]) - 1) for e in going]), np.array(going))
    envs.close()
    return seen


@pytest.mark.parametrize("name, kwargs", [
    ("Hopper", {"max_episode_steps": 5}),
    ("HalfCheetah", {"max_episode_steps": 5}),
    ("Ant", {"max_episode_steps": 5}),
])
@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
def test_each_envs_results_are_the_sync_paths_bit_for_bit(name, kwargs, mode):
    # Both runs start from the same draws: the async run's reset is not seeded (EnvPool's
    # async_reset takes no seed), so both runs reset once seeded and the sync run compares
    # from its second reset on.
    want = sync_run_after_reset(name, mode, kwargs)
    got = async_run(name, mode, 2, kwargs)
    for e in range(N):
        assert len(got[e]) == STEPS + 1
        for k, (g, w) in enumerate(zip(got[e], want[e])):
            assert g == w, f"{name} env {e} step {k} ({mode})"


def sync_run_after_reset(name, mode, kwargs):
    """The sync path from an unseeded reset that follows a seeded one (what
    ``async_reset`` does after ``reset(seed=7)``)."""
    envs = gymfleet.make_vec(f"gymfleet/{name}-v5", N, autoreset_mode=mode, **kwargs)
    space = envs.single_action_space
    envs.reset(seed=7)
    obs, info = envs.reset()
    seen = [[(obs[e].tobytes(), per_env(info, e))] for e in range(N)]
    for k in range(STEPS):
        obs, rew, term, trunc, info = envs.step(np.stack([actions_for(space, e, k) for e in range(N)]))
        for e in range(N):
            seen[e].append((obs[e].tobytes(), float(rew[e]), bool(term[e]), bool(trunc[e]), per_env(info, e)))
    envs.close()
    return seen


def test_step_async_and_step_wait_equal_step():
    a = gymfleet.make_vec("gymfleet/Hopper-v5", N)
    b = gymfleet.make_vec("gymfleet/Hopper-v5", N)
    a.reset(seed=1), b.reset(seed=1)
    for k in range(6):
        actions = np.stack([actions_for(a.single_action_space, e, k) for e in range(N)])
        b.step_async(actions)
        want = a.step(actions)
        got = b.step_wait()
        for x, y in zip(want[:4], got[:4]):
            np.testing.assert_array_equal(x, y)
        assert want[4].keys() == got[4].keys()
        for key in want[4]:
            np.testing.assert_array_equal(np.asarray(want[4][key]), np.asarray(got[4][key]))
    a.close(), b.close()


def test_step_with_env_id_is_send_then_recv():
    envs = gymfleet.make_vec("gymfleet/Walker2d-v5", 4, batch_size=4)
    envs.async_reset()
    _, _, _, _, info = envs.recv()
    assert info["env_id"].tolist() == [0, 1, 2, 3]
    ids = np.array([2, 0, 3, 1])
    obs, rew, _, _, info = envs.step(np.zeros((4,) + envs.single_action_space.shape, np.float32), ids)
    assert sorted(info["env_id"].tolist()) == [0, 1, 2, 3]
    assert "x_velocity" in info and info["_x_velocity"].all()
    envs.close()


@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
def test_a_control_suite_tasks_async_results_are_the_sync_paths(mode):
    pytest.importorskip("dm_control")
    name = "gymfleet/CheetahRun-v1"
    kwargs = {"task_kwargs": {"time_limit": 0.05}}  # 5 steps of 0.01 s: episodes end

    def run(batch_size):
        envs = gymfleet.make_vec(name, 4, autoreset_mode=mode, batch_size=batch_size, **kwargs)
        space = envs.single_action_space
        envs.reset(seed=7)
        seen = [[] for _ in range(4)]
        if batch_size == 4:
            obs, info = envs.reset()
            for e in range(4):
                seen[e].append(obs[e].tobytes())
            for k in range(8):
                obs, rew, term, trunc, info = envs.step(np.stack([actions_for(space, e, k) for e in range(4)]))
                for e in range(4):
                    seen[e].append((obs[e].tobytes(), float(rew[e]), bool(trunc[e]), per_env(info, e)))
        else:
            envs.async_reset()
            while True:
                try:
                    obs, rew, term, trunc, info = envs.recv()
                except RuntimeError:
                    break
                for row, e in enumerate(info["env_id"].tolist()):
                    if not seen[e]:
                        seen[e].append(obs[row].tobytes())
                    else:
                        seen[e].append((obs[row].tobytes(), float(rew[row]), bool(trunc[row]), per_env(info, row)))
                going = [int(e) for e in info["env_id"] if len(seen[e]) <= 8]
                if going:
                    envs.send(np.stack([actions_for(space, e, len(seen[e]) - 1) for e in going]), np.array(going))
        envs.close()
        return seen

    want, got = run(4), run(2)
    assert any(s[2] for w in want for s in w[1:]), "episodes ended on the way"
    assert got == want
