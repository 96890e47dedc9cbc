#!/usr/bin/env python3
"""Env-steps per second through the Python package on its embedded server (`server=None`):
a single `gymfleet.make` env and `gymfleet.make_vec` batches of 1, 16 and 256 arm2 envs,
small random torques, rounds of a fixed length; prints one JSON line (best and median of
the rounds per case). The transport's share shows at small batches.

An A/B of two builds of the package: build a wheel of each
(`pip wheel --no-deps ./client/python -w DIR`), then alternate
`pip install --force-reinstall --no-deps DIR/*.whl` and this script, twice each.

  python bench/python/embedded_loop.py LABEL

Not a test: nothing here asserts a speed.
"""
import json
import pathlib
import statistics
import sys
import time

import numpy as np

import gymfleet

ARM2 = str(pathlib.Path(__file__).resolve().parents[2] / "models" / "arm2.json")


def rounds(step, per_step, seconds=1.5, n=5):
    """Best and median env-steps/s over `n` rounds of `seconds`."""
    rates = []
    for _ in range(n):
        k, t0 = 0, time.perf_counter()
        while time.perf_counter() - t0 < seconds:
            step(k)
            k += 1
        rates.append(k * per_step / (time.perf_counter() - t0))
    return max(rates), statistics.median(rates)


def batch(n_envs):
    env = gymfleet.make_vec(ARM2, n_envs)
    env.reset(seed=0)
    acts = np.random.default_rng(0).uniform(-0.05, 0.05, (64, n_envs, 2)).astype(np.float32)
    for i in range(50):
        env.step(acts[i % 64])
    try:
        return rounds(lambda k: env.step(acts[k % 64]), n_envs)
    finally:
        env.close()


def single():
    env = gymfleet.make(ARM2)
    env.reset(seed=0)
    acts = np.random.default_rng(0).uniform(-0.05, 0.05, (64, 2)).astype(np.float32)
    for i in range(50):
        env.step(acts[i % 64])
    try:
        return rounds(lambda k: env.step(acts[k % 64]), 1)
    finally:
        env.close()


if __name__ == "__main__":
    label = sys.argv[1] if len(sys.argv) > 1 else "this build"
    report = {"label": label, "single": single()}
    report.update({f"batch_{n}": batch(n) for n in (1, 16, 256)})
    print(json.dumps(report))
