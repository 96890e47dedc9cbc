#!/usr/bin/env python3
"""Gymnasium's MuJoCo v5 tasks, three ways, in one run: ``gymfleet.make_vec`` of the
``gymfleet/<Name>-v5`` id (one server batch), EnvPool's same v5 task, and gymnasium's own
``SyncVectorEnv`` over ``gymnasium.make("<Name>-v5")``: env-steps/s with random actions,
full observations, rewards, terminations and autoreset on every side (so reset cost
counts). Rounds alternate the sides, so drift on a noisy machine hits all alike; the
report gives the median of each side and their ratio, the fastest round of each side and
theirs (the least disturbed rounds on a shared machine), and each round's own ratio.

    pip install ./client/python            # a release build of the extension
    pip install envpool==1.2.5 mujoco
    python bench/python/suite_bench.py --envs 64 256 --rounds 3 --seconds 3

``--json PATH`` also writes every round's figures, with the commit and the date, for
``bench/plots.py`` (``bench/results/suite.json`` is the report's).

``--server ADDR`` steps a running gymfleet-server (e.g. ``target/release/gymfleet-server
--threads 2``) instead of the server embedded in this process. Not a test: nothing here
asserts a speed.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from typing import Callable, Dict, List

import gymnasium
import numpy as np

import gymfleet  # noqa: F401  (registers the gymfleet/<Name>-v5 ids)

NAMES = [
    "InvertedPendulum",
    "InvertedDoublePendulum",
    "Reacher",
    "Pusher",
    "HalfCheetah",
    "Hopper",
    "Walker2d",
    "Ant",
    "Swimmer",
    "Humanoid",
    "HumanoidStandup",
]


def rate(step: Callable[[np.ndarray], None], sample: Callable[[], np.ndarray], n: int, seconds: float) -> float:
    """Env-steps/s of `step` over `seconds` (after 20 warm-up steps)."""
    actions = [sample() for _ in range(64)]
    for k in range(20):
        step(actions[k % 64])
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        step(actions[steps % 64])
        steps += 1
    return steps * n / (time.perf_counter() - start)


def gymfleet_side(name: str, n: int, seconds: float, server: str | None) -> float:
    envs = gymnasium.make_vec(f"gymfleet/{name}-v5", n, vectorization_mode="vector_entry_point",
                              **({"server": server} if server else {}))
    envs.reset(seed=0)
    rng = np.random.default_rng(0)
    space = envs.action_space
    r = rate(lambda a: envs.step(a), lambda: rng.uniform(space.low, space.high).astype(np.float32), n, seconds)
    envs.close()
    return r


def envpool_side(name: str, n: int, seconds: float, threads: int) -> float:
    import envpool

    envs = envpool.make_gymnasium(f"{name}-v5", num_envs=n, batch_size=n, num_threads=threads, seed=0)
    envs.reset()
    rng = np.random.default_rng(0)
    space = envs.action_space
    r = rate(lambda a: envs.step(a), lambda: rng.uniform(space.low, space.high, (n,) + space.shape), n, seconds)
    envs.close()
    return r


def sync_side(name: str, n: int, seconds: float) -> float:
    envs = gymnasium.make_vec(f"{name}-v5", n, vectorization_mode="sync")
    envs.reset(seed=0)
    rng = np.random.default_rng(0)
    space = envs.action_space
    r = rate(lambda a: envs.step(a), lambda: rng.uniform(space.low, space.high), n, seconds)
    envs.close()
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--names", nargs="*", default=NAMES)
    ap.add_argument("--envs", type=int, nargs="*", default=[64, 256])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--threads", type=int, default=2, help="EnvPool's threads")
    ap.add_argument("--server", default=None, help="a running gymfleet-server; default: embedded")
    ap.add_argument("--no-sync", action="store_true", help="leave gymnasium's SyncVectorEnv out")
    ap.add_argument("--json", default=None, help="also write the rounds here (bench/plots.py reads them)")
    args = ap.parse_args()
    rows = []
    for name in args.names:
        for n in args.envs:
            runs: Dict[str, List[float]] = {"gymfleet": [], "envpool": [], "sync": []}
            for _ in range(args.rounds):
                runs["gymfleet"].append(gymfleet_side(name, n, args.seconds, args.server))
                runs["envpool"].append(envpool_side(name, n, args.seconds, args.threads))
                if not args.no_sync:
                    runs["sync"].append(sync_side(name, n, args.seconds))
            g, e = statistics.median(runs["gymfleet"]), statistics.median(runs["envpool"])
            line = (f"{name}-v5, {n} envs: gymfleet make_vec {g:9.0f} env-steps/s, EnvPool "
                    f"{e:9.0f} ({g / e:.2f}x)")
            if runs["sync"]:
                s = statistics.median(runs["sync"])
                line += f", gymnasium SyncVectorEnv {s:9.0f} ({g / s:.2f}x)"
            fg, fe = max(runs["gymfleet"]), max(runs["envpool"])
            rounds = ", ".join(f"{a / b:.2f}" for a, b in zip(runs["gymfleet"], runs["envpool"]))
            line += (f"; fastest rounds {fg:9.0f} vs {fe:9.0f} ({fg / fe:.2f}x);"
                     f" each round vs EnvPool: {rounds}")
            print(line, flush=True)
            rows.append({"name": name, "envs": n, **runs})
    if args.json:
        from provenance import provenance

        meta = provenance()  # before `open` truncates the file: that would read as "-dirty"
        with open(args.json, "w") as f:
            json.dump({**meta, "envpool_threads": args.threads, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
