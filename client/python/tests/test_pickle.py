"""Envs pickle (``pickle`` and ``cloudpickle``), and through ``multiprocessing`` with
spawn: the copy is the same id, keyword arguments and server and, a gymfleet extension,
continues from the original's state bit for bit. Vector envs refuse, saying what to do."""

from __future__ import annotations

import multiprocessing
import pickle

import numpy as np
import pytest

import gymfleet

gymnasium = pytest.importorskip("gymnasium")
cloudpickle = pytest.importorskip("cloudpickle")

ACTIONS = np.random.default_rng(3).uniform(-1, 1, (20, 3)).astype(np.float32)


def _steps(env, actions):
    return [env.step(a)[0] for a in actions]


def _child_steps(blob, actions):
    """In a spawned process: unpickle the env and step it."""
    env = pickle.loads(blob)
    try:
        return [obs.tobytes() for obs in _steps(env, actions)], env.spec.id
    finally:
        env.close()


@pytest.mark.parametrize("dumps,loads", [(pickle.dumps, pickle.loads), (cloudpickle.dumps, cloudpickle.loads)])
def test_a_v5_env_pickles_with_its_id_arguments_and_state(dumps, loads):
    env = gymnasium.make("gymfleet/Hopper-v5", ctrl_cost_weight=2e-3)
    env.reset(seed=4)
    _steps(env, ACTIONS[:5])
    copy = loads(dumps(env))
    try:
        assert copy.spec.id == "gymfleet/Hopper-v5"
        assert copy.spec.kwargs == env.spec.kwargs
        assert copy.unwrapped._made_with == env.unwrapped._made_with
        assert copy.unwrapped.gymfleet_env.server == env.unwrapped.gymfleet_env.server
        # Both continue alike from the state the original had when it was pickled.
        ours, theirs = _steps(env, ACTIONS[5:]), _steps(copy, ACTIONS[5:])
        assert [o.tobytes() for o in ours] == [o.tobytes() for o in theirs]
    finally:
        copy.close()
        env.close()


def test_an_env_survives_a_round_trip_through_a_spawned_process():
    env = gymnasium.make("gymfleet/Hopper-v5")
    env.reset(seed=9)
    _steps(env, ACTIONS[:3])
    blob = pickle.dumps(env)
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        child, env_id = pool.apply(_child_steps, (blob, ACTIONS[3:]))
    # The child's embedded server is its own; the state it loaded is the original's.
    assert env_id == "gymfleet/Hopper-v5"
    assert child == [obs.tobytes() for obs in _steps(env, ACTIONS[3:])]
    env.close()


def test_a_document_env_pickles_too(arm2):
    env = gymfleet.make(arm2)
    env.reset(seed=1)
    env.step(np.array([0.01, -0.02], dtype=np.float32))
    copy = pickle.loads(pickle.dumps(env))
    try:
        assert copy.spec.kwargs == env.spec.kwargs
        a = np.array([0.02, 0.01], dtype=np.float32)
        assert env.step(a)[0].tobytes() == copy.step(a)[0].tobytes()
    finally:
        copy.close()
        env.close()


def test_vector_envs_say_they_do_not_pickle():
    envs = gymnasium.make_vec("gymfleet/Hopper-v5", 2, vectorization_mode="vector_entry_point")
    with pytest.raises(TypeError, match="SuiteVectorEnv does not pickle: it is a batch on its server"):
        pickle.dumps(envs)
    envs.close()
