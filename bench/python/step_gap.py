#!/usr/bin/env python3
"""Microseconds per iteration of a training-like loop: one `make_vec` step of a
`gymfleet/<Name>-v5` batch, then `--gap-us` of the caller's own CPU work (a spin, standing
for a policy's forward pass) before the next step. Shows what the server's helpers cost
or save when the caller comes back late or soon (`HELPERS_LINGER`, bench/journal/2026-12-07-benchmarks-notebook.md, "The calling
thread runs its own pool work"). Seeded random actions, 100 warm-up iterations.

    python bench/python/step_gap.py HalfCheetah --envs 64 --gap-us 500

Not a test: nothing here asserts a speed.
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

import gymfleet  # noqa: F401  (registers the gymfleet/<Name>-v5 ids)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("name")
    ap.add_argument("--envs", type=int, default=64)
    ap.add_argument("--gap-us", type=float, default=500.0)
    ap.add_argument("--iterations", type=int, default=600)
    args = ap.parse_args()
    env = gym.make_vec(f"gymfleet/{args.name}-v5", args.envs)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    actions = [rng.uniform(-1, 1, env.action_space.shape).astype(np.float32) for _ in range(64)]
    gap = args.gap_us * 1e-6

    def iterate(i: int) -> None:
        env.step(actions[i % 64])
        spun = time.perf_counter()
        while time.perf_counter() - spun < gap:
            pass

    for i in range(100):
        iterate(i)
    start = time.perf_counter()
    for i in range(args.iterations):
        iterate(i)
    per = (time.perf_counter() - start) / args.iterations * 1e6
    env.close()
    print(f"{args.name}, {args.envs} envs, {args.gap_us:.0f} us between steps: {per:.0f} us per iteration")


if __name__ == "__main__":
    main()
