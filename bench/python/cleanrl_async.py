#!/usr/bin/env python3
"""Issue A, item 5: the CleanRL PPO example on a remote server, synchronous (the
example's gymnasium wrappers, one ``StepBatch`` per vector step) against EnvPool's
asynchronous loop with ``batch_size = N/2``, over several seeds.

    python bench/python/cleanrl_async.py --seeds 1 2 3 --steps 100000 --envs 8 \\
        --server-bin target/release/gymfleet-server --out target/cleanrl_async

It starts one ``gymfleet-server`` process (one pool thread, pinned to core 0 where the
machine has two), runs each (mode, seed) one after the other with the trainer pinned to
core 1 and torch on one thread, and writes each run's curve as JSON, a plot of every
curve (``curves.png``) and a table of final returns (the mean return of the episodes of
the last 5 updates) and wall times. Needs torch and matplotlib; not part of CI.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import socket
import subprocess
import sys
import time

REPO = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "client" / "python" / "examples" / "cleanrl_ppo_halfcheetah.py"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def pinned(core: int) -> list:
    return ["taskset", "-c", str(core)] if (os.cpu_count() or 1) >= 2 else []


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--steps", type=int, default=100_000)
    p.add_argument("--envs", type=int, default=8)
    p.add_argument("--server-bin", default=str(REPO / "target" / "release" / "gymfleet-server"))
    p.add_argument("--out", default="target/cleanrl_async")
    p.add_argument("--modes", nargs="+", choices=["sync", "async"], default=["sync", "async"])
    p.add_argument("--report", action="store_true", help="only print the table of the runs in --out")
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    modes = {"sync": [], "async": ["--batch-size", str(args.envs // 2)]}
    run_modes = {mode: modes[mode] for mode in args.modes}
    if not args.report:
        addr = f"127.0.0.1:{free_port()}"
        server = subprocess.Popen(pinned(0) + [args.server_bin, "--listen", addr, "--threads", "1"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            time.sleep(1.0)
            for seed in args.seeds:
                for mode, extra in run_modes.items():
                    curve = out / f"{mode}-{seed}.json"
                    cmd = pinned(1) + [sys.executable, str(EXAMPLE), "--steps", str(args.steps),
                                       "--envs", str(args.envs), "--seed", str(seed), "--server", addr,
                                       "--plot", str(out / f"{mode}-{seed}.png"), "--curve", str(curve), *extra]
                    print(" ".join(cmd), flush=True)
                    subprocess.run(cmd, check=True, env={**os.environ, "OMP_NUM_THREADS": "1"},
                                   stdout=subprocess.DEVNULL)
        finally:
            server.terminate()
            server.wait()
    report(out, modes)


def report(out: pathlib.Path, modes: dict) -> None:
    """Prints each run's final return and wall time, and each mode's spread; plots each
    mode's mean curve over its seeds with the band from its lowest to its highest."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    print("| mode | seed | final return (last 5 points) | wall time |")
    print("|---|---|---|---|")
    fig, ax = plt.subplots(figsize=(7, 4))
    for colour, mode in zip(("C0", "C1"), modes):
        finals, curves = [], []
        for f in sorted(out.glob(f"{mode}-*.json"), key=lambda f: int(f.stem.split("-")[1])):
            run = json.loads(f.read_text())
            curve = run["curve"]
            finals.append(float(np.mean([r for _, r in curve[-5:]])))
            curves.append(curve)
            print(f"| {mode} | {run['args']['seed']} | {finals[-1]:.1f} | {run['wall_s']:.0f} s |")
        if not curves:
            continue
        print(f"| {mode} | {len(finals)} seeds | mean {np.mean(finals):.1f}, "
              f"range {min(finals):.1f} to {max(finals):.1f} | |")
        n = min(len(c) for c in curves)
        steps = [s for s, _ in curves[0][:n]]
        returns = np.array([[r for _, r in c[:n]] for c in curves])
        ax.plot(steps, returns.mean(axis=0), color=colour, label=f"{mode}: mean of {len(curves)} seeds")
        ax.fill_between(steps, returns.min(axis=0), returns.max(axis=0), color=colour, alpha=0.2,
                        label=f"{mode}: lowest to highest seed")
    ax.set_xlabel("env steps")
    ax.set_ylabel("mean episode return")
    ax.set_title("CleanRL PPO, HalfCheetah, 8 envs on a remote server: sync vs async (M = 4)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "curves.png", dpi=100)
    print(f"curves written to {out / 'curves.png'}")


if __name__ == "__main__":
    main()
