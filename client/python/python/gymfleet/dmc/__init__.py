"""The DeepMind Control Suite on gymfleet: ``gymfleet/<DomainTask>-v1`` ids (EnvPool's
names) with dm_control's contract: its observation dict flattened in key order (each
key's length in ``observation_structure``), its reward (computed in the server from the
task's terms), its control timestep, its 1000-step episodes (truncation) and its
episodes' starts, built at run time from the XML files of the installed ``dm_control``
(``pip install './client/python[dmc]'``). :mod:`gymfleet.dm_control` serves the same
tasks through the ``dm_env`` interface.

>>> import gymnasium, gymfleet
>>> env = gymnasium.make("gymfleet/CheetahRun-v1")
>>> envs = gymnasium.make_vec("gymfleet/WalkerWalk-v1", 64)   # one server-side batch

Registered: the tasks in :data:`TASKS` (27 of ``suite.BENCHMARKING``'s 28; docs/suites.md's
table lists which).
"""

from __future__ import annotations

from typing import Any

import gymnasium

from .envs import DmcEnv, DmcVectorEnv, Setup
from .tasks import TASKS, Task

__all__ = ["DmcEnv", "DmcVectorEnv", "Setup", "TASKS", "Task", "register_dmc"]


def make_dmc_env(env_id: str, **kwargs: Any) -> DmcEnv:
    return DmcEnv(env_id, **kwargs)


def make_dmc_vector_env(env_id: str, num_envs: int = 1, **kwargs: Any) -> DmcVectorEnv:
    return DmcVectorEnv(env_id, num_envs, **kwargs)


def register_dmc() -> None:
    """Registers the ``gymfleet/<DomainTask>-v1`` ids (idempotent)."""
    for env_id in TASKS:
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=env_id,
            entry_point="gymfleet.dmc:make_dmc_env",
            vector_entry_point="gymfleet.dmc:make_dmc_vector_env",
            kwargs={"env_id": env_id},
            # dm_control's step limit truncates, on the server (time_limit may change it).
            max_episode_steps=None,
        )
