"""Saved states from Python: try actions and take them back, bit for bit; move envs
between servers and between the envs of a (sharded) vector env; bad states raise."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet


def _actions(k: int, n: int = 2) -> np.ndarray:
    return np.array([0.03 * np.sin(0.3 * k + j) for j in range(n)], dtype=np.float32)


def test_an_env_takes_actions_back_bitwise(arm2):
    env = gymfleet.make(arm2, end_effector_ids=["forearm"], max_steps=25)
    env.reset(seed=3)
    for k in range(10):
        env.step(_actions(k))
    state = env.save_state()
    assert isinstance(state, bytes) and state[:4] == b"GFST"
    here = env.observe()

    first = [env.step(_actions(k))[0] for k in range(10, 40)]  # crosses the episode's end
    np.testing.assert_array_equal(env.load_state(state), here)
    again = [env.step(_actions(k))[0] for k in range(10, 40)]
    for a, b in zip(first, again):
        assert a.tobytes() == b.tobytes()

    # Another env of the same document and options, on another server, loads it too.
    with gymfleet.Server(threads=1) as other:
        twin = gymfleet.make(
            arm2, end_effector_ids=["forearm"], max_steps=25, seed=99, server=other.address
        )
        np.testing.assert_array_equal(twin.load_state(state), here)
        assert twin.step(_actions(10))[0].tobytes() == first[0].tobytes()
        twin.close()
    env.close()


def test_bad_states_raise_with_the_reason(arm2, pendulum):
    env = gymfleet.make(arm2, end_effector_ids=["forearm"])
    state = env.save_state()
    with pytest.raises(TypeError, match="state: expected the bytes save_state returned, got str"):
        env.load_state("GFST")
    with pytest.raises(gymfleet.InvalidArgument, match="checksum mismatch"):
        env.load_state(state[:-3])
    with pytest.raises(gymfleet.InvalidArgument, match="not a gymfleet env state"):
        env.load_state(b"hello, world")
    other = gymfleet.make(pendulum, end_effector_ids=["arm"])
    with pytest.raises(
        gymfleet.InvalidArgument,
        match="state.document: the state was saved from an env of another document",
    ):
        other.load_state(state)
    other.close()
    env.close()


def test_vector_envs_save_and_load_across_shards(arm2):
    a, b = gymfleet.Server(threads=1), gymfleet.Server(threads=1)
    try:
        envs = gymfleet.make_vec(arm2, 6, server=f"{a.address},{b.address}")
        envs.reset(seed=1)
        for k in range(5):
            envs.step(np.tile(_actions(k), (6, 1)) * np.arange(1, 7)[:, None])
        at_save = envs.observe()
        states = envs.save_states([1, 4])  # one on each shard
        assert len(states) == 2
        assert envs.save_states([]) == []
        for k in range(5, 9):
            envs.step(np.tile(_actions(k), (6, 1)))
        obs = envs.load_states([states[1], states[0]], [1, 4])  # crosswise, across shards
        np.testing.assert_array_equal(obs[1], at_save[4])
        np.testing.assert_array_equal(obs[4], at_save[1])
        all_states = envs.save_states()
        assert len(all_states) == 6
        envs.load_states(all_states)
        with pytest.raises(gymfleet.InvalidArgument, match="expected one state per env index"):
            envs.load_states(all_states[:2])
        envs.close()
    finally:
        a.stop()
        b.stop()
