"""Gymnasium's MuJoCo suite on gymfleet: ``gymfleet/<Name>-v5`` ids with Gymnasium v5's
contract (spaces, observation contents in SI units, actions as MuJoCo's ctrl, reward
terms and their weights, ``info`` scalars, termination, truncation, frame skip, reset
noise and keyword arguments), built at run time from the XML files of the installed
``gymnasium`` package.

>>> import gymnasium, gymfleet
>>> env = gymnasium.make("gymfleet/Hopper-v5")           # was: gymnasium.make("Hopper-v5")
>>> envs = gymnasium.make_vec("gymfleet/Hopper-v5", 64)  # one server-side batch

Registered: all eleven of Gymnasium's MuJoCo v5 envs (InvertedPendulum,
InvertedDoublePendulum, Reacher, Pusher, HalfCheetah, Hopper, Walker2d, Ant, Swimmer,
Humanoid, HumanoidStandup). What still differs from MuJoCo's is in each spec's ``note``
and in the README.
"""

from __future__ import annotations

from typing import Any

import gymnasium

from .envs import SuiteEnv
from .vector_env import SuiteVectorEnv
from .specs import SUITE

__all__ = ["SuiteEnv", "SuiteVectorEnv", "SUITE", "register_suite"]


def make_suite_env(env_id: str, **kwargs: Any) -> SuiteEnv:
    return SuiteEnv(env_id, **kwargs)


def make_suite_vector_env(env_id: str, num_envs: int = 1, **kwargs: Any) -> SuiteVectorEnv:
    return SuiteVectorEnv(env_id, num_envs, **kwargs)


def register_suite() -> None:
    """Registers the ``gymfleet/<Name>-v5`` ids (idempotent)."""
    for env_id, spec in SUITE.items():
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=env_id,
            entry_point="gymfleet.suite:make_suite_env",
            vector_entry_point="gymfleet.suite:make_suite_vector_env",
            kwargs={"env_id": env_id},
            max_episode_steps=spec.max_episode_steps,
            reward_threshold=spec.reward_threshold,
        )
