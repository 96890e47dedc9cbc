#!/usr/bin/env python3
"""Whether two builds step Gymnasium's v5 ids alike, bit for bit: the SHA-256 of every
observation and reward of `--steps` steps of `gymnasium.make_vec("gymfleet/<Name>-v5", 8)`
from `reset(seed=0)` under seeded uniform random actions. Run it once per build (for
instance each wheel installed with `pip install --no-deps --target DIR` and put first on
`PYTHONPATH`) and compare the lines. Not a test: a change that is meant to change no result
(vendored patches 23 and 24) is checked with it.

    python bench/python/hash_v5.py HalfCheetah Reacher Hopper Walker2d Ant Humanoid Pusher
"""

from __future__ import annotations

import argparse
import hashlib

import gymnasium as gym
import numpy as np

import gymfleet  # noqa: F401  (registers the gymfleet/<Name>-v5 ids)


def digest(name: str, envs: int, steps: int) -> str:
    env = gym.make_vec(f"gymfleet/{name}-v5", envs)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    h = hashlib.sha256()
    for _ in range(steps):
        action = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
        obs, reward, _, _, _ = env.step(action)
        h.update(obs.tobytes())
        h.update(np.asarray(reward).tobytes())
    env.close()
    return h.hexdigest()[:16]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("names", nargs="+")
    p.add_argument("--envs", type=int, default=8)
    p.add_argument("--steps", type=int, default=400)
    args = p.parse_args()
    for name in args.names:
        print(name, digest(name, args.envs, args.steps), flush=True)


if __name__ == "__main__":
    main()
