"""The asynchronous API against EnvPool's own: EnvPool's documented loop (``async_reset``,
then ``recv`` M envs, ``send`` their actions with ``info["env_id"]``) driven over EnvPool's
``HalfCheetah-v5`` and over ``gymfleet/HalfCheetah-v5`` with the same ``num_envs`` and
``batch_size``: the same shapes and types, the same env groups in the same order, every env
back once a cycle, and ``step(actions, env_id)`` as ``send`` then ``recv``. (gymfleet is
stricter in one place: it refuses to send an env that is still in flight, where EnvPool
takes it.)"""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet

envpool = pytest.importorskip("envpool")

N, M, ROUNDS = 6, 2, 12


def envpool_loop(env, action_dim):
    """EnvPool's async loop (its README's), recording what each ``recv`` returns."""
    env.async_reset()
    seen = []
    rng = np.random.default_rng(0)
    for _ in range(ROUNDS):
        obs, rew, terminated, truncated, info = env.recv()
        env_id = info["env_id"]
        seen.append({
            "ids": env_id.tolist(),
            "shapes": (obs.shape, rew.shape, terminated.shape, truncated.shape, env_id.shape),
            "types": (terminated.dtype, truncated.dtype, env_id.dtype),
            "finite": bool(np.isfinite(obs).all() and np.isfinite(rew).all()),
        })
        action = rng.uniform(-1, 1, (len(env_id), action_dim)).astype(np.float32)
        env.send(action, env_id)
    # EnvPool's `step(action, env_id)`: send, then recv.
    obs, *_, info = env.step(np.zeros((M, action_dim), np.float32), env.recv()[4]["env_id"])
    seen.append({"step": (obs.shape, info["env_id"].shape)})
    return seen


def test_envpools_async_loop_sees_the_same_contract_on_both():
    theirs = envpool.make("HalfCheetah-v5", env_type="gymnasium", num_envs=N, batch_size=M,
                          num_threads=1, seed=0)
    ours = gymfleet.make_vec("gymfleet/HalfCheetah-v5", N, batch_size=M)
    dim = theirs.action_space.shape[0]
    assert ours.single_action_space.shape == (dim,)
    want, got = envpool_loop(theirs, dim), envpool_loop(ours, dim)
    theirs.close(), ours.close()
    assert [s.get("ids") for s in got] == [s.get("ids") for s in want]
    assert [s.get("shapes") for s in got] == [s.get("shapes") for s in want]
    assert [s.get("types") for s in got] == [s.get("types") for s in want]
    assert got[-1] == want[-1]
    assert all(s["finite"] for s in got[:-1])
    # Every env comes back once in each cycle of N / M receives.
    for cycle in range(ROUNDS // (N // M)):
        ids = [e for s in got[cycle * 3 : cycle * 3 + 3] for e in s["ids"]]
        assert sorted(ids) == list(range(N)), cycle
