#!/usr/bin/env python3
"""Remote trainers with a policy of realistic cost: env-steps/s of a training loop that runs
a numpy MLP (2 x 256 units over the batch) between steps, on a server in another process
(loopback) against the same loop on the in-process embedded server.

    python bench/python/async_bench.py                      # 16, 64, 256 envs; 3 rounds of 3 s
    python bench/python/async_bench.py --envs 64 --seconds 1 --rounds 1   # a smoke run

Modes, each over the same model (arm2), policy and pinning:
- ``embedded sync``: the in-process server, ``step`` of every env (the yardstick);
- ``embedded async``: the in-process server, EnvPool's loop below (nothing to overlap with:
  trainer and simulation share the core);
- ``remote sync``: a ``gymfleet-server`` process, ``step`` of every env;
- ``remote sync stream``: the same server, the same loop over the asynchronous API with
  ``batch_size = N`` (every env sent on the batch's stream, all received back: a
  synchronous step over ``StreamBatch``);
- ``remote async``: the same server, EnvPool's loop with ``batch_size = N/2`` (``recv`` M
  envs, the policy on them, ``send``): the policy on one half overlaps the server's
  stepping of the other.
The server runs with one pool thread, pinned to core 0, and the trainer on core 1 with BLAS
on one thread (``OMP_NUM_THREADS=1``); on this 2-core VM that is the whole machine. The
policy's own cost per batch is timed in the same run. Medians of alternated rounds.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import socket
import statistics
import subprocess
import sys
import time
from typing import Callable, Dict, List

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import gymfleet  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]
OPTIONS = dict(end_effector_ids=["forearm"], max_steps=200)


class Mlp:
    """A policy of 2 x 256 tanh units, observation -> action, in float32."""

    def __init__(self, obs_dim: int, act_dim: int, seed: int = 0) -> None:
        rng = np.random.default_rng(seed)
        dims = [obs_dim, 256, 256, act_dim]
        self.w = [rng.normal(0, 1 / np.sqrt(a), (a, b)).astype(np.float32) for a, b in zip(dims, dims[1:])]

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        x = np.asarray(obs, dtype=np.float32) * 1e-2
        for w in self.w[:-1]:
            x = np.tanh(x @ w)
        return np.tanh(x @ self.w[-1]) * 1e-3


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(binary: pathlib.Path) -> "tuple[subprocess.Popen[bytes], str]":
    addr = f"127.0.0.1:{free_port()}"
    cmd = ["taskset", "-c", "0", str(binary), "--listen", addr, "--threads", "1"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(200):
        try:
            with socket.create_connection(("127.0.0.1", int(addr.rsplit(":", 1)[1])), 0.1):
                return proc, addr
        except OSError:
            time.sleep(0.05)
    proc.kill()
    sys.exit(f"{binary} did not start listening on {addr}")


def sync_loop(envs: gymfleet.GymfleetVectorEnv, policy: Mlp, seconds: float) -> float:
    obs, _ = envs.reset(seed=0)
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        obs, *_ = envs.step(policy(obs))
        steps += envs.num_envs
    return steps / (time.perf_counter() - start)


def async_loop(envs: gymfleet.GymfleetVectorEnv, policy: Mlp, seconds: float) -> float:
    envs.async_reset()
    steps, start = 0, time.perf_counter()
    # The first half goes out before the loop, so that one half is always on the server.
    obs, _, _, _, info = envs.recv()
    envs.send(policy(obs), info["env_id"])
    while time.perf_counter() - start < seconds:
        obs, _, _, _, info = envs.recv()
        envs.send(policy(obs), info["env_id"])
        steps += len(info["env_id"])
    rate = steps / (time.perf_counter() - start)
    envs.recv()  # the last send's envs
    return rate


def stream_loop(envs: gymfleet.GymfleetVectorEnv, policy: Mlp, seconds: float) -> float:
    """Whole-batch steps over the stream: ``recv`` all N, the policy, ``send`` all N."""
    envs.async_reset()
    steps, start = 0, time.perf_counter()
    obs, _, _, _, info = envs.recv()
    while time.perf_counter() - start < seconds:
        envs.send(policy(obs), info["env_id"])
        obs, _, _, _, info = envs.recv()
        steps += len(info["env_id"])
    return steps / (time.perf_counter() - start)


def policy_cost(policy: Mlp, obs_dim: int, n: int) -> float:
    obs = np.zeros((n, obs_dim), dtype=np.float32)
    start, k = time.perf_counter(), 0
    while time.perf_counter() - start < 0.5:
        policy(obs)
        k += 1
    return (time.perf_counter() - start) / k * 1e6


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--envs", type=int, nargs="+", default=[16, 64, 256])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--seconds", type=float, default=3.0)
    p.add_argument("--server-bin", default=os.environ.get("GYMFLEET_SERVER_BIN", str(REPO / "target" / "release" / "gymfleet-server")))
    args = p.parse_args()
    os.sched_setaffinity(0, {1})
    proc, addr = start_server(pathlib.Path(args.server_bin))
    arm2 = str(REPO / "models" / "arm2.json")
    try:
        for n in args.envs:
            made: Dict[str, Callable[[], float]] = {}
            # (The lambdas run in this iteration only.)
            embedded = gymfleet.make_vec(arm2, n, **OPTIONS)
            remote = gymfleet.make_vec(arm2, n, server=addr, **OPTIONS)
            embedded_async = gymfleet.make_vec(arm2, n, batch_size=max(1, n // 2), **OPTIONS)
            remote_stream = gymfleet.make_vec(arm2, n, server=addr, batch_size=n, **OPTIONS)
            remote_async = gymfleet.make_vec(arm2, n, server=addr, batch_size=max(1, n // 2), **OPTIONS)
            policy = Mlp(embedded.single_observation_space.shape[0], embedded.single_action_space.shape[0])
            made["embedded sync"] = lambda: sync_loop(embedded, policy, args.seconds)
            made["remote sync"] = lambda: sync_loop(remote, policy, args.seconds)
            made["embedded async M=N/2"] = lambda: async_loop(embedded_async, policy, args.seconds)
            made["remote sync stream"] = lambda: stream_loop(remote_stream, policy, args.seconds)
            made["remote async M=N/2"] = lambda: async_loop(remote_async, policy, args.seconds)
            rates: Dict[str, List[float]] = {k: [] for k in made}
            for _ in range(args.rounds):
                for name, run in made.items():
                    rates[name].append(run())
            base = statistics.median(rates["embedded sync"])
            cost = policy_cost(policy, embedded.single_observation_space.shape[0], n)
            print(f"{n} envs (policy {cost:.0f} us per {n}-env batch):")
            for name, values in rates.items():
                m = statistics.median(values)
                print(f"  {name:22s} {m:10.0f} env-steps/s  {m / base:5.2f}x embedded sync")
            for envs in (embedded, embedded_async, remote, remote_stream, remote_async):
                envs.close()
    finally:
        proc.terminate()
        proc.wait()


if __name__ == "__main__":
    main()
