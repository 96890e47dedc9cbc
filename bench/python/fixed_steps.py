#!/usr/bin/env python3
"""A fixed number of `gymfleet/<Name>-v5` steps through `gymnasium.make_vec`, for instruction
counts: run it under callgrind at two step counts and divide the difference by
`envs × (steps₂ − steps₁)` to get instructions per env step, start-up cancelled. The figures
behind vendored Rapier patches 22–24 (`vendor/rapier3d/PATCHES.md`) came from this script
(then kept outside the repo, the same loop).

    valgrind --tool=callgrind --callgrind-out-file=cg.20 python bench/python/fixed_steps.py Reacher 64 20
    valgrind --tool=callgrind --callgrind-out-file=cg.120 python bench/python/fixed_steps.py Reacher 64 120
    # (summary of cg.120 − summary of cg.20) / (64 × 100)
"""
import sys

import gymnasium as gym
import numpy as np

import gymfleet  # noqa: F401  (registers the gymfleet/ ids)

name, n, steps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
env = gym.make_vec(f"gymfleet/{name}-v5", n)
env.reset(seed=0)
rng = np.random.default_rng(0)
for _ in range(steps):
    env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
