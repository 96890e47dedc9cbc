#!/usr/bin/env python3
"""Two builds of `gymfleet-load` against each other on the step path: each with its
embedded server (loopback gRPC, one pool thread), alternated round by round.

    git worktree add /tmp/before OLD_COMMIT && (cd /tmp/before && cargo build --release -p gymfleet-load)
    cargo build --release -p gymfleet-load
    python3 bench/python/wire_ab.py --before /tmp/before/target/release/gymfleet-load \\
        --after target/release/gymfleet-load --rounds 5
    python3 bench/python/wire_ab.py --before ... --after ... --callgrind   # instructions per step

Timings print each round's env-steps/s, the median ratio after / before and the median
p50 latency. On a noisy machine they cannot resolve a few per cent; `--callgrind` counts the
whole process's instructions (client and embedded server) at 1 000 and 3 000 single-env
steps and prints the slope, per step, which is repeatable to about 1 %.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile

WORKLOADS = {
    "env pendulum": ["--api", "env", "--model", "pendulum"],
    "batch arm2 x64": ["--api", "batch", "--model", "arm2", "--n-envs", "64"],
}


def timed(binary: str, args: list, out: str) -> tuple:
    subprocess.run([binary, *args, "--duration", "3", "--warmup", "1", "--threads", "1", "--json", out],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    run = json.load(open(out))["runs"][0]
    return run["env_steps_per_s"], run["latency_us"]["p50"]


def instructions(binary: str, steps: int, work: str) -> int:
    err = os.path.join(work, "callgrind.err")
    with open(err, "w") as f:
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={work}/cg.out", binary,
                        "--api", "env", "--model", "pendulum", "--steps", str(steps), "--warmup-steps", "50",
                        "--threads", "1"], check=True, stdout=subprocess.DEVNULL, stderr=f)
    return int(re.search(r"Collected : (\d+)", open(err).read()).group(1))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--before", required=True, help="the first build's gymfleet-load")
    p.add_argument("--after", required=True, help="the second build's gymfleet-load")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--callgrind", action="store_true", help="count instructions per step instead")
    args = p.parse_args()
    builds = {"before": args.before, "after": args.after}
    with tempfile.TemporaryDirectory() as work:
        if args.callgrind:
            for side, binary in builds.items():
                low, high = instructions(binary, 1000, work), instructions(binary, 3000, work)
                print(f"{side}: {(high - low) / 2000 / 1000:.1f} k instructions per step")
            return
        results = {(w, s): [] for w in WORKLOADS for s in builds}
        for r in range(args.rounds):
            for w, wargs in WORKLOADS.items():
                for side in (("before", "after") if r % 2 == 0 else ("after", "before")):
                    results[(w, side)].append(timed(builds[side], wargs, os.path.join(work, "run.json")))
    print("| workload | before, env-steps/s | after | after / before (medians) | p50 before / after |")
    print("|---|---|---|---|---|")
    for w in WORKLOADS:
        b, a = results[(w, "before")], results[(w, "after")]
        rate = lambda rows: statistics.median(x for x, _ in rows)  # noqa: E731
        p50 = lambda rows: statistics.median(p for _, p in rows)  # noqa: E731
        print(f"| {w} | {', '.join(f'{x:,.0f}' for x, _ in b)} | {', '.join(f'{x:,.0f}' for x, _ in a)} | "
              f"{rate(a) / rate(b):.3f} | {p50(b)} / {p50(a)} µs |")


if __name__ == "__main__":
    main()
