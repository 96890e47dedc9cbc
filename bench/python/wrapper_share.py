#!/usr/bin/env python3
"""How much of a `gymfleet/<Name>-v5` vector step is the Python suite wrapper's own work: the
time of `gymnasium.make_vec(...).step` against the time of the batch step underneath it
(`GymfleetVectorEnv.step`, which calls the extension), seeded uniform random actions, one
warm-up of 200 steps, then `--steps` steps timed. Also the CPU time of the Python thread
itself per step (`time.thread_time`: the wrapper, the in-process call's own work and
numpy's, not the pool's threads).

    python bench/python/wrapper_share.py Humanoid Ant Reacher --envs 64
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

import gymfleet  # noqa: F401  (registers the gymfleet/<Name>-v5 ids)


def share(name: str, envs: int, steps: int) -> str:
    env = gym.make_vec(f"gymfleet/{name}-v5", envs)
    env.reset(seed=0)
    inner = env.unwrapped._envs
    rng = np.random.default_rng(0)
    actions = [rng.uniform(-1, 1, env.action_space.shape).astype(np.float32) for _ in range(64)]
    step, spent = inner.step, [0.0]

    def timed(a):
        t = time.perf_counter()
        out = step(a)
        spent[0] += time.perf_counter() - t
        return out

    inner.step = timed
    for i in range(200):
        env.step(actions[i % 64])
    spent[0] = 0.0
    t, cpu = time.perf_counter(), time.thread_time()
    for i in range(steps):
        env.step(actions[i % 64])
    total = time.perf_counter() - t
    cpu = time.thread_time() - cpu
    env.close()
    wrapper = total - spent[0]
    return (
        f"{name}, {envs} envs: {total / steps * 1e6:.0f} us per batch step, the batch step "
        f"{spent[0] / steps * 1e6:.0f}, the wrapper {wrapper / steps * 1e6:.0f} "
        f"({wrapper / total * 100:.1f} %); the Python thread's CPU {cpu / steps * 1e6:.0f}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="+")
    ap.add_argument("--envs", type=int, default=64)
    ap.add_argument("--steps", type=int, default=2000)
    args = ap.parse_args()
    for name in args.names:
        print(share(name, args.envs, args.steps), flush=True)


if __name__ == "__main__":
    main()
