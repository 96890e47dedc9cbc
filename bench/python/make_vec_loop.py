#!/usr/bin/env python3
"""Env-steps per second of one `gymfleet/<Name>-v5` id through `gymnasium.make_vec`: uniform
random actions in the action space, rounds of a fixed length, the best round printed. A
quick before/after check of one change (suite_bench.py compares against EnvPool).

  python bench/python/make_vec_loop.py --id gymfleet/Humanoid-v5 --envs 64
"""
import argparse
import time

import gymnasium as gym
import numpy as np

import gymfleet  # noqa: F401  (registers the gymfleet/ ids)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--id", default="gymfleet/Humanoid-v5")
    ap.add_argument("--envs", type=int, default=64)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=2.0)
    args = ap.parse_args()
    env = gym.make_vec(args.id, args.envs)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    space = env.single_action_space
    acts = rng.uniform(space.low, space.high, (64, args.envs) + space.shape).astype(np.float32)
    for i in range(20):
        env.step(acts[i % 64])
    best = 0.0
    for _ in range(args.rounds):
        start, k = time.perf_counter(), 0
        while time.perf_counter() - start < args.seconds:
            env.step(acts[k % 64])
            k += 1
        best = max(best, k * args.envs / (time.perf_counter() - start))
    print(f"{args.id}, {args.envs} envs: {best:.0f} env-steps/s "
          f"(best of {args.rounds} rounds of {args.seconds:g} s)")
    env.close()


if __name__ == "__main__":
    main()
