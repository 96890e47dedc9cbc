#!/usr/bin/env python3
"""Learning parity on the Control Suite: does SAC learn on gymfleet's
``gymfleet/<DomainTask>-v1`` as on dm_control's own task? The same learner
(Stable-Baselines3's SAC with its default hyperparameters), the same seeds and steps on
both sides; the final returns, each run's wall time, and the curves as one PNG.

    pip install './client/python[dmc]' stable-baselines3 matplotlib
    python bench/python/dmc_parity.py                         # cheetah-run, walker-walk x 3 seeds x 100 000 steps x 2 sides
    python bench/python/dmc_parity.py --seeds 0 1 --jobs 2    # 2 seeds, 2 runs at a time (one core each)
    python bench/python/dmc_parity.py --tasks cheetah-run --seeds 0 --steps 3000   # a smoke run
    python bench/python/dmc_parity.py --report                # the table and PNG of the runs so far

Not a test: torch never runs in CI. dm_control's side is its ``suite.load`` environment,
its observation dict flattened in key order (as gymfleet's id flattens it) and its episode
ended at its step limit as a truncation; gymfleet's is the registered id with float32
observations. An episode is 1000 control steps on both; its return is the sum of its
rewards (at most 1000). The final return of a run is the mean return of its last 10
episodes. Each run's record goes to ``OUT/<task>-<side>-<seed>.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import statistics
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, Dict, Tuple

import numpy as np

SIDES = ("dm_control", "gymfleet")
TASKS = ("cheetah-run", "walker-walk")


def dm_env(domain: str, task: str, seed: int) -> Any:
    """dm_control's task as a Gymnasium env: the flattened observation (float32), the
    step limit as a truncation."""
    import gymnasium as gym
    from gymnasium import spaces

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        from dm_control import suite

    class DmGym(gym.Env):
        def __init__(self) -> None:
            self._env = suite.load(domain, task, task_kwargs={"random": seed})
            size = sum(int(np.prod(s.shape)) for s in self._env.observation_spec().values())
            self.observation_space = spaces.Box(-np.inf, np.inf, (size,), np.float32)
            a = self._env.action_spec()
            self.action_space = spaces.Box(a.minimum.astype(np.float32), a.maximum.astype(np.float32))

        @staticmethod
        def _flat(obs: Dict[str, Any]) -> np.ndarray:
            return np.concatenate([np.ravel(v) for v in obs.values()]).astype(np.float32)

        def reset(self, *, seed: Any = None, options: Any = None) -> Tuple[np.ndarray, Dict[str, Any]]:
            super().reset(seed=seed)
            return self._flat(self._env.reset().observation), {}

        def step(self, action: np.ndarray) -> Tuple[np.ndarray, float, bool, bool, Dict[str, Any]]:
            ts = self._env.step(action)
            return self._flat(ts.observation), float(ts.reward), False, ts.last(), {}

    return DmGym()


def make(side: str, name: str, seed: int) -> Any:
    domain, task = name.split("-")
    if side == "dm_control":
        return dm_env(domain, task, seed)
    import gymnasium as gym

    from gymfleet.dmc import TASKS as IDS  # importing gymfleet registers the ids

    spec = next(t for t in IDS.values() if (t.domain, t.task) == (domain, task))
    return gym.make(spec.id, dtype=np.float32, task_kwargs={"random": seed})


def run(name: str, side: str, seed: int, steps: int, out: str) -> Dict[str, Any]:
    import torch
    from stable_baselines3 import SAC
    from stable_baselines3.common.monitor import Monitor

    torch.set_num_threads(1)
    env = Monitor(make(side, name, seed))
    model = SAC("MlpPolicy", env, seed=seed, verbose=0)
    start = time.perf_counter()
    model.learn(total_timesteps=steps)
    wall = time.perf_counter() - start
    returns = [float(r) for r in env.get_episode_rewards()]
    lengths = np.cumsum(env.get_episode_lengths()).tolist()
    record = {"task": name, "side": side, "seed": seed, "steps": steps, "wall_s": wall,
              "episodes": list(zip(lengths, returns))}
    path = pathlib.Path(out) / f"{name}-{side}-{seed}.json"
    path.write_text(json.dumps(record))
    env.close()
    return record


def _pinned(args: Tuple[str, str, int, int, str, int]) -> Dict[str, Any]:
    *task, core = args
    os.sched_setaffinity(0, {core})
    return run(*task)


def final(record: Dict[str, Any]) -> float:
    returns = [r for _, r in record["episodes"]][-10:]
    return statistics.fmean(returns) if returns else float("nan")


def report(out: pathlib.Path) -> None:
    records = [json.loads(p.read_text()) for p in sorted(out.glob("*.json"))]
    print("| task | side | seeds | final return (each) | mean | wall time per run |")
    print("|---|---|---|---|---|---|")
    for name in TASKS:
        for side in SIDES:
            rs = [r for r in records if r["task"] == name and r["side"] == side]
            if not rs:
                continue
            finals = [final(r) for r in rs]
            walls = ", ".join(f"{r['wall_s'] / 60:.0f} min" for r in rs)
            print(f"| {name} | {side} | {len(rs)} | {', '.join(f'{f:.0f}' for f in finals)} "
                  f"| {statistics.fmean(finals):.0f} | {walls} |")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    names = [n for n in TASKS if any(r["task"] == n for r in records)]
    fig, axes = plt.subplots(1, len(names), figsize=(6 * len(names), 4), squeeze=False)
    for ax, name in zip(axes[0], names):
        for r in (r for r in records if r["task"] == name):
            xs, ys = zip(*r["episodes"]) if r["episodes"] else ((), ())
            ax.plot(xs, ys, color="C0" if r["side"] == "dm_control" else "C1", alpha=0.8,
                    label=f"{r['side']} seed {r['seed']}")
        ax.set_title(f"{name}: SB3 SAC (defaults)")
        ax.set_xlabel("env steps")
        ax.set_ylabel("episode return")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "dmc_parity.png", dpi=80)
    print(f"curves: {out / 'dmc_parity.png'}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--tasks", nargs="+", default=list(TASKS), choices=list(TASKS))
    p.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    p.add_argument("--steps", type=int, default=100_000)
    p.add_argument("--sides", nargs="+", default=list(SIDES), choices=list(SIDES))
    p.add_argument("--out", default="target/dmc_parity")
    p.add_argument("--jobs", type=int, default=1, help="runs at a time, each on a core of its own")
    p.add_argument("--report", action="store_true", help="only the table and PNG of the runs in OUT")
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if not args.report:
        tasks = [(n, s, seed, args.steps, str(out)) for n in args.tasks for seed in args.seeds
                 for s in args.sides]
        cores = sorted(os.sched_getaffinity(0))
        if args.jobs > len(cores):
            sys.exit(f"--jobs {args.jobs}: this process may use {len(cores)} cores")
        with ProcessPoolExecutor(args.jobs) as pool:
            pending = {}
            queue = list(tasks)
            free = cores[: args.jobs]
            while queue or pending:
                while queue and free:
                    core = free.pop()
                    fut = pool.submit(_pinned, (*queue.pop(0), core))
                    pending[fut] = core
                for fut in as_completed(list(pending)):
                    free.append(pending.pop(fut))
                    r = fut.result()
                    print(f"{r['task']} {r['side']} seed {r['seed']}: final {final(r):.0f} "
                          f"in {r['wall_s']:.0f} s", flush=True)
                    break
    report(out)


if __name__ == "__main__":
    main()
