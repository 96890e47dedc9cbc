"""The environments registered with gymnasium: the repository's seed models, with an
effort limit per joint so that their action spaces are bounded (as gymnasium's own envs'
are), and their end effectors observed.

``gymnasium.make("gymfleet/Arm2-v0")`` works once ``gymfleet`` is imported (or,
without importing it, ``gymnasium.make("gymfleet:gymfleet/Arm2-v0")``);
``gymnasium.make_vec("gymfleet/Arm2-v0", num_envs=256)`` makes one server-side batch.
Every keyword of :func:`gymfleet.make` (``server``, ``max_steps``, …) can be passed.
"""

from __future__ import annotations

import json
from typing import Any, Dict

import gymnasium

from . import _core

#: id → (seed model, end effectors, max_effort per joint in N·m: about 4× what holding
#: the arm level against gravity takes).
SEED_ENVS: Dict[str, Any] = {
    "gymfleet/Pendulum-v0": ("pendulum", ["arm"], {"*": 5e-4}),
    "gymfleet/Arm2-v0": ("arm2", ["forearm"], {"*": 1e-3}),
    "gymfleet/Arm6-v0": (
        "arm6",
        ["tool"],
        {
            "base_yaw": 2.0,
            "shoulder_pitch": 2.0,
            "elbow_pitch": 1.0,
            "wrist_roll": 0.2,
            "wrist_pitch": 0.2,
            "tool_roll": 0.1,
        },
    ),
}


def seed_document(env_id: str) -> Dict[str, Any]:
    """The document of a registered env: its seed model with the joints' ``max_effort``."""
    model, _, efforts = SEED_ENVS[env_id]
    document = json.loads(_core.seed_model(model))
    for joint in document["assembly"]["joints"]:
        joint["max_effort"] = efforts.get(joint.get("name", ""), efforts.get("*"))
    return document


def _options(env_id: str, kwargs: Dict[str, Any]) -> Dict[str, Any]:
    kwargs.setdefault("end_effector_ids", SEED_ENVS[env_id][1])
    return kwargs


def make_seed_env(env_id: str, **kwargs: Any) -> gymnasium.Env:
    from .env import GymfleetEnv

    return GymfleetEnv(seed_document(env_id), **_options(env_id, kwargs))


def make_seed_vector_env(env_id: str, num_envs: int = 1, **kwargs: Any) -> Any:
    from .vector import GymfleetVectorEnv

    return GymfleetVectorEnv(seed_document(env_id), num_envs, **_options(env_id, kwargs))


def register_envs() -> None:
    """Registers the seed envs (idempotent)."""
    for env_id in SEED_ENVS:
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=env_id,
            entry_point="gymfleet.registration:make_seed_env",
            vector_entry_point="gymfleet.registration:make_seed_vector_env",
            kwargs={"env_id": env_id},
            # The server truncates at `max_steps` (default 1000); no TimeLimit on top.
            max_episode_steps=None,
            disable_env_checker=False,
        )
