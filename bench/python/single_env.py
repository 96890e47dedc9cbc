#!/usr/bin/env python3
"""One env's `step` from Python, gymfleet's `gymfleet/<Name>-v5` against Gymnasium's MuJoCo
`<Name>-v5`, in the same process and run: seeded uniform random actions (a table of 64,
reused), a warm-up of 200 steps, then `--steps` steps timed per round, the two sides
alternated for `--rounds` rounds (resets inside the timed loop when an episode ends, as a
training loop does). Prints each id's median and fastest-round µs per step and their
ratio (gymfleet / MuJoCo: below 1 is faster). `--profile NAME` instead prints cProfile's
top functions of gymfleet's step for that id.

Setup (not part of CI): `pip install ./client/python` (release) and `pip install mujoco`
in one venv.

    python bench/python/single_env.py --rounds 5 --steps 2000
"""

from __future__ import annotations

import argparse
import statistics
import time

import gymnasium as gym
import numpy as np

import gymfleet  # noqa: F401  (registers the gymfleet/<Name>-v5 ids)
from gymfleet.suite import SUITE

NAMES = [spec.name for spec in SUITE.values()]


def timed(env, actions, steps: int) -> float:
    """µs per step over `steps` steps."""
    start = time.perf_counter()
    for k in range(steps):
        _, _, terminated, truncated, _ = env.step(actions[k % len(actions)])
        if terminated or truncated:
            env.reset()
    return (time.perf_counter() - start) / steps * 1e6


def compare(name: str, rounds: int, steps: int) -> str:
    sides = {"gymfleet": gym.make(f"gymfleet/{name}-v5"), "mujoco": gym.make(f"{name}-v5")}
    rng = np.random.default_rng(0)
    shape = sides["mujoco"].action_space.shape
    low, high = sides["mujoco"].action_space.low, sides["mujoco"].action_space.high
    actions = [rng.uniform(low, high, shape).astype(np.float32) for _ in range(64)]
    times = {side: [] for side in sides}
    for env in sides.values():
        env.reset(seed=0)
        timed(env, actions, 200)
    for r in range(rounds):
        order = list(sides) if r % 2 == 0 else list(reversed(sides))
        for side in order:
            times[side].append(timed(sides[side], actions, steps))
    for env in sides.values():
        env.close()
    ours, theirs = times["gymfleet"], times["mujoco"]
    return (
        f"{name:24} gymfleet {statistics.median(ours):7.1f} µs (fastest {min(ours):6.1f}), "
        f"MuJoCo {statistics.median(theirs):7.1f} µs (fastest {min(theirs):6.1f}); ratio "
        f"{statistics.median(ours) / statistics.median(theirs):.2f} "
        f"(fastest rounds {min(ours) / min(theirs):.2f})"
    )


def profile(name: str, steps: int) -> None:
    import cProfile
    import pstats

    env = gym.make(f"gymfleet/{name}-v5")
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    actions = [env.action_space.sample() for _ in range(64)]
    timed(env, actions, 200)
    profiler = cProfile.Profile()
    profiler.enable()
    timed(env, actions, steps)
    profiler.disable()
    pstats.Stats(profiler).sort_stats("tottime").print_stats(25)
    del rng


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--names", nargs="*", default=NAMES, choices=NAMES)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--profile", choices=NAMES)
    args = ap.parse_args()
    if args.profile:
        profile(args.profile, args.steps)
        return
    for name in args.names:
        print(compare(name, args.rounds, args.steps), flush=True)


if __name__ == "__main__":
    main()
