#!/usr/bin/env python3
"""One SB3 VecEnv step with one env, with ``VecNormalize`` as rl-zoo trains Hopper:
gymfleet's adapter (``gymfleet.sb3.make_vec_env``) against SB3's ``DummyVecEnv`` over
Gymnasium's MuJoCo env, the same random actions, sides alternated round by round.

    pip install ./client/python stable-baselines3 mujoco
    python bench/python/sb3_step.py --name Hopper --steps 5000 --rounds 2

Not a test (timings). Episodes end as random actions make them end, so resets count too.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def per_step(venv, steps: int) -> float:
    """Mean µs per ``venv.step`` over ``steps`` uniform random actions (seed 0)."""
    venv.reset()
    dim = venv.action_space.shape[0]
    actions = np.random.default_rng(0).uniform(-1, 1, size=(steps, 1, dim)).astype(np.float32)
    start = time.perf_counter()
    for action in actions:
        venv.step(action)
    return (time.perf_counter() - start) / steps * 1e6


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--name", default="Hopper")
    p.add_argument("--steps", type=int, default=5000)
    p.add_argument("--rounds", type=int, default=2)
    args = p.parse_args()
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import VecNormalize

    from gymfleet.sb3 import make_vec_env as gymfleet_vec_env

    for r in range(args.rounds):
        theirs = VecNormalize(make_vec_env(f"{args.name}-v5", n_envs=1, seed=0), gamma=0.999)
        ours = VecNormalize(gymfleet_vec_env(f"gymfleet/{args.name}-v5", n_envs=1, seed=0), gamma=0.999)
        print(f"round {r}: mujoco {per_step(theirs, args.steps):.1f} µs/step, "
              f"gymfleet {per_step(ours, args.steps):.1f} µs/step", flush=True)
        theirs.close()
        ours.close()


if __name__ == "__main__":
    main()
