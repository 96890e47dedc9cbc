#!/usr/bin/env python3
"""How ``gymnasium.make_vec("gymfleet/<Name>-v5", n)`` scales with the envs of a batch and
the cores it may use, beside EnvPool's same v5 task on as many threads: env-steps/s with
random actions, full observations, rewards and autoreset on both sides.

Each thread count runs in a process of its own, pinned to that many cores before gymfleet
is imported (its embedded server starts one pool thread per core the process may use);
EnvPool gets ``num_threads`` = the same count. Within it, each env count alternates the two
sides for ``--rounds`` rounds (odd rounds gymfleet first); the medians are reported and
written, every round with them, to ``--json`` for ``bench/plots.py``.

    pip install ./client/python            # a release build of the extension
    pip install envpool==1.2.5 mujoco
    python bench/python/scaling.py --names Hopper HalfCheetah --json bench/results/scaling.json

Not a test: nothing here asserts a speed.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def worker(name: str, sizes: list[int], threads: int, rounds: int, seconds: float) -> list[dict]:
    """Runs in the pinned process: the rounds of each env count."""
    import gymnasium

    import gymfleet  # noqa: F401  (registers the ids; the embedded server sizes its pool now)
    from suite_bench import envpool_side, gymfleet_side

    gymnasium.logger.min_level = 40
    rows = []
    for n in sizes:
        runs: dict[str, list[float]] = {"gymfleet": [], "envpool": []}
        for r in range(rounds):
            sides = [("gymfleet", lambda: gymfleet_side(name, n, seconds, None)),
                     ("envpool", lambda: envpool_side(name, n, seconds, threads))]
            for side, run in sides if r % 2 == 0 else reversed(sides):
                runs[side].append(run())
        rows.append({"name": name, "threads": threads, "envs": n, **runs})
        g, e = statistics.median(runs["gymfleet"]), statistics.median(runs["envpool"])
        print(f"{name}-v5, {threads} thread(s), {n:5} envs: gymfleet {g:9.0f} env-steps/s, "
              f"EnvPool {e:9.0f} ({g / e:.2f}x)", file=sys.stderr, flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--names", nargs="*", default=["Hopper", "HalfCheetah"])
    ap.add_argument("--envs", type=int, nargs="*", default=[1, 4, 16, 64, 256, 1024])
    ap.add_argument("--threads", type=int, nargs="*", default=[1, 2])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=2.0)
    ap.add_argument("--json", default=None, help="write the rounds here (bench/plots.py reads them)")
    ap.add_argument("--worker", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker is not None:
        os.sched_setaffinity(0, sorted(os.sched_getaffinity(0))[: args.worker])
        rows = [row for name in args.names
                for row in worker(name, args.envs, args.worker, args.rounds, args.seconds)]
        json.dump(rows, sys.stdout)
        return
    cores = len(os.sched_getaffinity(0))
    rows = []
    for t in args.threads:
        if t > cores:
            sys.exit(f"{t} threads asked for, but this process may use {cores} cores")
        out = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", str(t),
                              "--names", *args.names, "--rounds", str(args.rounds),
                              "--seconds", str(args.seconds), "--envs", *map(str, args.envs)],
                             check=True, capture_output=True, text=True, cwd=HERE)
        sys.stderr.write("".join(line + "\n" for line in out.stderr.splitlines()
                                 if "env-steps/s" in line))
        rows.extend(json.loads(out.stdout))
    if args.json:
        from provenance import provenance

        meta = provenance()  # before `open` truncates the file: that would read as "-dirty"
        with open(args.json, "w") as f:
            json.dump({**meta, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
