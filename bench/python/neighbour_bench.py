#!/usr/bin/env python3
"""The embedded server beside other work (issue P2): ``gymnasium.make_vec`` of Gymnasium's
locomotion v5 ids on gymfleet's embedded server against EnvPool's same task, on an idle
machine and beside CPU-bound neighbour processes at the default priority (``python -c
"while True: pass"``, as a trainer's own threads, a data loader or a compile would be).

Two loops per side, with random actions:
- ``step``: the vector step alone (env-steps/s);
- ``ppo``: the vector step, then a numpy MLP of 2 x 256 tanh units on the batch's
  observations in the same thread (a policy's forward pass, as a PPO rollout does it);
  BLAS is held to one thread (``OPENBLAS_NUM_THREADS=1`` and the like) so that the MLP runs
  in the calling thread as the issue asks.

Rounds alternate the sides (and the conditions), so drift on a noisy machine hits all
alike; the report gives each side's median, their ratio, and every round's own ratio.
Gymnasium's ``SyncVectorEnv`` is added with ``--sync``.

    pip install ./client/python            # a release build of the extension
    pip install envpool==1.2.5 mujoco
    python bench/python/neighbour_bench.py --neighbours 0 2 --rounds 3 --seconds 3

``--server ADDR`` steps a running gymfleet-server instead of the embedded one.
``--renice 10`` adds a third side: the embedded server with its pool threads reniced to 10
from outside, as every build before issue P2 ran them (and as ``--pool-niceness 10`` runs
a server's); the pool goes back to this process's priority for the plain side, which
needs root (or CAP_SYS_NICE). Not a test: nothing here asserts a speed.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from typing import Callable, Dict, Iterator, List  # noqa: E402

import gymnasium  # noqa: E402
import numpy as np  # noqa: E402

import gymfleet  # noqa: E402,F401  (registers the gymfleet/<Name>-v5 ids)

NAMES = ["HalfCheetah", "Hopper", "Walker2d", "Ant", "Humanoid"]


@contextlib.contextmanager
def neighbours(count: int) -> Iterator[None]:
    """`count` busy-loop processes at this process's priority, for the block's length."""
    procs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(count)]
    try:
        time.sleep(0.2 if count else 0.0)  # let them get going
        yield
    finally:
        for p in procs:
            p.kill()
        for p in procs:
            p.wait()


class Mlp:
    """A policy's forward pass: obs -> 256 -> 256 -> action, tanh, float32."""

    def __init__(self, obs_dim: int, act_dim: int) -> None:
        rng = np.random.default_rng(0)
        self.w = [
            (rng.standard_normal((a, b)) / np.sqrt(a)).astype(np.float32)
            for a, b in ((obs_dim, 256), (256, 256), (256, act_dim))
        ]

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        h = np.asarray(obs, dtype=np.float32)
        for w in self.w[:-1]:
            h = np.tanh(h @ w)
        return np.tanh(h @ self.w[-1])


def rate(envs, n: int, seconds: float, loop: str, low: np.ndarray, high: np.ndarray,
         seed: bool = True) -> float:
    """Env-steps/s of `loop` over `seconds` (after 20 warm-up steps)."""
    rng = np.random.default_rng(0)
    actions = [rng.uniform(low, high).astype(np.float32) for _ in range(64)]
    obs, _ = envs.reset(seed=0) if seed else envs.reset()
    policy = Mlp(int(np.prod(obs.shape[1:])), actions[0].shape[-1])
    steps = 0

    def one(k: int) -> None:
        nonlocal obs
        obs, *_ = envs.step(actions[k % 64])
        if loop == "ppo":
            policy(obs.reshape(n, -1))

    for k in range(20):
        one(k)
    start = time.perf_counter()
    while time.perf_counter() - start < seconds:
        one(steps)
        steps += 1
    return steps * n / (time.perf_counter() - start)


def renice_pool(niceness: int) -> None:
    """Sets this process's simulation threads (``gymfleet-step-N``) to `niceness`."""
    for task in os.scandir("/proc/self/task"):
        with open(f"{task.path}/comm", encoding="utf-8") as f:
            if f.read().startswith("gymfleet-step-"):
                os.setpriority(os.PRIO_PROCESS, int(task.name), niceness)


def gymfleet_side(name: str, n: int, seconds: float, loop: str, server: str | None,
                  niceness: int | None = None) -> float:
    envs = gymnasium.make_vec(f"gymfleet/{name}-v5", n, vectorization_mode="vector_entry_point",
                              **({"server": server} if server else {}))
    if niceness is not None:
        renice_pool(niceness)
    space = envs.action_space
    try:
        return rate(envs, n, seconds, loop, space.low, space.high)
    finally:
        envs.close()


def envpool_side(name: str, n: int, seconds: float, loop: str, threads: int) -> float:
    import envpool

    envs = envpool.make_gymnasium(f"{name}-v5", num_envs=n, batch_size=n, num_threads=threads,
                                  seed=0)
    space = envs.action_space
    low = np.broadcast_to(space.low, (n,) + space.shape)
    high = np.broadcast_to(space.high, (n,) + space.shape)
    try:
        return rate(envs, n, seconds, loop, low, high, seed=False)  # seeded at creation
    finally:
        envs.close()


def sync_side(name: str, n: int, seconds: float, loop: str) -> float:
    envs = gymnasium.make_vec(f"{name}-v5", n, vectorization_mode="sync")
    space = envs.action_space
    try:
        return rate(envs, n, seconds, loop, space.low, space.high)
    finally:
        envs.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--names", nargs="*", default=NAMES)
    ap.add_argument("--envs", type=int, default=64)
    ap.add_argument("--neighbours", type=int, nargs="*", default=[0, 2],
                    help="busy-loop processes beside the run, one condition each")
    ap.add_argument("--loops", nargs="*", default=["step", "ppo"], choices=["step", "ppo"])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--threads", type=int, default=2, help="EnvPool's threads")
    ap.add_argument("--server", default=None, help="a running gymfleet-server; default: embedded")
    ap.add_argument("--sync", action="store_true", help="add gymnasium's SyncVectorEnv")
    ap.add_argument("--renice", type=int, default=None, metavar="N",
                    help="add the embedded server with its pool reniced to N (needs root)")
    args = ap.parse_args()
    n = args.envs
    print(f"# {n} envs, EnvPool on {args.threads} threads, {os.cpu_count()} CPUs, "
          f"{args.rounds} rounds of {args.seconds} s, gymfleet on "
          f"{args.server or 'the embedded server'}", flush=True)
    for name in args.names:
        for loop in args.loops:
            runs: Dict[int, Dict[str, List[float]]] = {
                k: {"gymfleet": [], "envpool": [], "sync": [], "reniced": []}
                for k in args.neighbours
            }
            for _ in range(args.rounds):
                for k in args.neighbours:
                    with neighbours(k):
                        r = runs[k]
                        base = os.getpriority(os.PRIO_PROCESS, 0)
                        r["gymfleet"].append(
                            gymfleet_side(name, n, args.seconds, loop, args.server,
                                          base if args.renice is not None else None))
                        if args.renice is not None:
                            r["reniced"].append(gymfleet_side(name, n, args.seconds, loop, None,
                                                              args.renice))
                        r["envpool"].append(envpool_side(name, n, args.seconds, loop, args.threads))
                        if args.sync:
                            r["sync"].append(sync_side(name, n, args.seconds, loop))
            for k in args.neighbours:
                r = runs[k]
                g, e = statistics.median(r["gymfleet"]), statistics.median(r["envpool"])
                each = ", ".join(f"{a / b:.2f}" for a, b in zip(r["gymfleet"], r["envpool"]))
                line = (f"{name}-v5 {loop:<4} beside {k} busy: gymfleet {g:8.0f} env-steps/s, "
                        f"EnvPool {e:8.0f} ({g / e:.2f}x; rounds {each})")
                if r["sync"]:
                    s = statistics.median(r["sync"])
                    line += f", SyncVectorEnv {s:8.0f} ({g / s:.2f}x)"
                if r["reniced"]:
                    q = statistics.median(r["reniced"])
                    line += f"; pool at nice {args.renice} {q:8.0f} ({q / e:.2f}x EnvPool)"
                print(line, flush=True)


if __name__ == "__main__":
    main()
