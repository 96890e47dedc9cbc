#!/usr/bin/env python3
"""An A/B of package builds on a machine whose cores change distance: alternates
`wrapper_share.py NAME --envs N` over the given installs for `--minutes`, runs
`cross_core_probe.c` before each round, and prints each build's median batch step (and the
Python thread's CPU time per step) for the rounds the probe found the two cores near and
far (`--far-ns`: a cache line's round trip between CPUs 0 and 1 at or above it). The probe's
whole line is printed with each round, its loopback TCP round trips included. On a cloud VM
the hypervisor moves the vCPUs: here
the round trip reads 80–110 ns for minutes, then 380–450 ns (bench/journal/2026-12-07-benchmarks-notebook.md, "Each pool thread
keeps its envs").

    pip wheel --no-deps ./client/python -w /tmp/w_a   # one build; the other likewise
    pip install --no-deps --target /tmp/site_a /tmp/w_a/*.whl
    python bench/python/cross_core_ab.py /tmp/site_a /tmp/site_b --minutes 10

Needs gcc and a machine with at least two CPUs. Not a test: nothing here asserts a speed.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent


def build_probe(directory: str) -> str:
    probe = os.path.join(directory, "cross_core_probe")
    source = str(HERE / "cross_core_probe.c")
    subprocess.run(["gcc", "-O2", "-pthread", source, "-o", probe], check=True)
    return probe


def probe_round_trip(probe: str) -> tuple[float, str]:
    out = subprocess.run([probe], capture_output=True, text=True, check=True).stdout.strip()
    return float(re.search(r"round_trip_ns=([\d.]+)", out).group(1)), out


def batch_step_us(site: str, name: str, envs: int, steps: int) -> tuple[float, float]:
    """The batch step's wall time and the Python thread's CPU time per step, in µs."""
    env = dict(os.environ, PYTHONPATH=site)
    out = subprocess.run(
        [sys.executable, str(HERE / "wrapper_share.py"), name, "--envs", str(envs), "--steps", str(steps)],
        capture_output=True, text=True, check=True, env=env,
    ).stdout
    wall = float(re.search(r"(\d+) us per batch step", out).group(1))
    return wall, float(re.search(r"the Python thread's CPU (\d+)", out).group(1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sites", nargs="+", help="directories with an installed gymfleet package")
    ap.add_argument("--name", default="HalfCheetah")
    ap.add_argument("--envs", type=int, default=64)
    ap.add_argument("--steps", type=int, default=1500)
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--far-ns", type=float, default=250.0)
    args = ap.parse_args()
    labels = [pathlib.Path(s).name for s in args.sites]
    rounds = []
    with tempfile.TemporaryDirectory() as tmp:
        probe = build_probe(tmp)
        end = time.time() + args.minutes * 60
        while time.time() < end:
            round_trip, line = probe_round_trip(probe)
            steps = [batch_step_us(s, args.name, args.envs, args.steps) for s in args.sites]
            rounds.append((round_trip, steps))
            print(time.strftime("%H:%M:%S"), line, " ".join(f"{l}={w:.0f}/{c:.0f}" for l, (w, c) in zip(labels, steps)), flush=True)
    for state, pick in (("near", lambda r: r < args.far_ns), ("far", lambda r: r >= args.far_ns)):
        chosen = [steps for round_trip, steps in rounds if pick(round_trip)]
        if not chosen:
            print(f"{state}: no rounds")
            continue
        medians = ", ".join(
            f"{l} {statistics.median(s[i][0] for s in chosen):.1f} µs (fastest "
            f"{min(s[i][0] for s in chosen):.0f}; Python thread's CPU {statistics.median(s[i][1] for s in chosen):.1f})"
            for i, l in enumerate(labels)
        )
        faster = ", ".join(
            f"{l} faster than {labels[0]} in {sum(s[i][0] < s[0][0] for s in chosen)}"
            for i, l in enumerate(labels) if i
        )
        print(f"{state} ({len(chosen)} rounds): {args.name} {args.envs}-env batch step, medians: {medians}; {faster}")


if __name__ == "__main__":
    main()
