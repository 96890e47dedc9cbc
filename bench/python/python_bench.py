#!/usr/bin/env python3
"""Python (gymfleet.make_vec) against the Rust client (gymfleet-load) on the same server,
in the same run, plus EnvPool's Reacher-v5 if it is installed.

One gymfleet-server process (release build) serves both clients. Rounds alternate
Rust, Python (and EnvPool), so drift on a noisy machine hits all alike; the report gives
each round's env-steps/s and the median ratio Python / Rust.

    cargo build --release -p gymfleet-server -p gymfleet-load
    pip install ./client/python          # a release build of the extension
    python bench/python/python_bench.py --rounds 5 --duration 5

Not a test: nothing here asserts a speed.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import socket
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[2]
RELEASE = REPO / "target" / "release"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(threads: int) -> tuple[subprocess.Popen, str]:
    import gymfleet

    addr = f"127.0.0.1:{free_port()}"
    proc = subprocess.Popen(
        [str(RELEASE / "gymfleet-server"), "--listen", addr, "--threads", str(threads)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 30
    while True:
        try:
            gymfleet.server_info(addr)
            return proc, addr
        except gymfleet.Unavailable:
            if proc.poll() is not None or time.monotonic() > deadline:
                sys.exit("gymfleet-server did not start (cargo build --release -p gymfleet-server?)")
            time.sleep(0.05)


def rust_round(addr: str, n_envs: int, duration: float, warmup: float) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "load.json"
        subprocess.run(
            [
                str(RELEASE / "gymfleet-load"),
                "--server", addr,
                "--model", "arm2",
                "--n-envs", str(n_envs),
                "--duration", str(duration),
                "--warmup", str(warmup),
                "--quiet",
                "--json", str(out),
            ],
            check=True,
            stdout=subprocess.DEVNULL,
        )
        return json.loads(out.read_text())["runs"][0]["env_steps_per_s"]


def actions_table(n_envs: int, dofs: int, amplitude: float, count: int = 64) -> list:
    """Slow sinusoids per env and DOF, like gymfleet-load's (precomputed, cycled)."""
    rng = np.random.default_rng(0)
    phase = rng.uniform(0, 2 * np.pi, size=(n_envs, dofs))
    period = rng.uniform(50, 200, size=(n_envs, dofs))
    return [
        (amplitude * np.sin(phase + 2 * np.pi * t / period)).astype(np.float32)
        for t in range(count)
    ]


def python_round(addr: str, n_envs: int, duration: float, warmup: float) -> float:
    import gymfleet

    envs = gymfleet.make_vec(
        REPO / "models" / "arm2.json", n_envs, server=addr, end_effector_ids=["forearm"]
    )
    table = actions_table(n_envs, 2, 1e-4)
    envs.reset(seed=0)
    t, end_warmup = 0, time.perf_counter() + warmup
    while time.perf_counter() < end_warmup:
        envs.step(table[t % len(table)])
        t += 1
    steps, start = 0, time.perf_counter()
    while (now := time.perf_counter()) - start < duration:
        envs.step(table[t % len(table)])
        t += 1
        steps += 1
    envs.close()
    return steps * n_envs / (now - start)


def envpool_round(n_envs: int, threads: int, duration: float, warmup: float) -> float | None:
    try:
        import envpool
    except ImportError:
        return None
    env = envpool.make(
        "Reacher-v5", env_type="gymnasium", num_envs=n_envs, batch_size=n_envs, num_threads=threads
    )
    action = np.zeros((n_envs, 2), dtype=np.float32)
    env.reset()
    end_warmup = time.perf_counter() + warmup
    while time.perf_counter() < end_warmup:
        env.step(action)
    steps, start = 0, time.perf_counter()
    while (now := time.perf_counter()) - start < duration:
        env.step(action)
        steps += 1
    env.close()
    return steps * n_envs / (now - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--duration", type=float, default=5.0, help="measured seconds per round")
    parser.add_argument("--warmup", type=float, default=1.0)
    parser.add_argument("--n-envs", type=int, default=256)
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 2)
    parser.add_argument("--no-envpool", action="store_true")
    args = parser.parse_args()

    import gymfleet

    proc, addr = start_server(args.threads)
    try:
        print(f"server {addr}: gymfleet {gymfleet.__version__}, {args.threads} threads; "
              f"arm2 × {args.n_envs}, unary StepBatch, torque; {args.duration} s per round")
        rows = []
        for r in range(args.rounds):
            rust = rust_round(addr, args.n_envs, args.duration, args.warmup)
            python = python_round(addr, args.n_envs, args.duration, args.warmup)
            pool = None if args.no_envpool else envpool_round(
                args.n_envs, args.threads, args.duration, args.warmup
            )
            rows.append((rust, python, pool))
            extra = "" if pool is None else f"  envpool Reacher-v5 {pool:10.0f}"
            print(f"round {r + 1}: rust {rust:10.0f}  python {python:10.0f}  "
                  f"python/rust {python / rust:5.3f}{extra}  env-steps/s")
        ratios = [p / r for r, p, _ in rows]
        print(f"median python/rust {statistics.median(ratios):.3f} "
              f"(min {min(ratios):.3f}, max {max(ratios):.3f})")
        pools = [(p, e) for _, p, e in rows if e is not None]
        if pools:
            print(f"median python/envpool {statistics.median(p / e for p, e in pools):.3f}")
    finally:
        proc.terminate()
        proc.wait()


if __name__ == "__main__":
    main()
