#!/usr/bin/env python3
"""The Control Suite's tasks three ways, in one run: ``gymfleet.make_vec`` of the
``gymfleet/<DomainTask>-v1`` id (one server batch), EnvPool's same ``<DomainTask>-v1``
task (gymnasium API), and dm_control's own loop (``suite.load`` envs stepped one after
another, as a single-process trainer steps them): env-steps/s with random actions, full
observations and rewards, and resets at the time limit (so reset cost counts: cheetah's
200 settling steps, humanoid's draws). Rounds alternate the sides; the report gives each
side's median over rounds and the ratios of the medians.

    python -m venv target/benchenv && target/benchenv/bin/pip install ./client/python[dmc] envpool==1.2.5
    target/benchenv/bin/python bench/python/dmc_bench.py --envs 64 --rounds 3 --seconds 2

``--tasks`` picks ids by name (default: every served task). Not a test: nothing here
asserts a speed.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings
from typing import Callable, Dict, List

import numpy as np

import gymfleet  # noqa: F401  (registers the gymfleet/<DomainTask>-v1 ids)
from gymfleet.dmc import TASKS


def rate(step: Callable[[int], None], n: int, seconds: float) -> float:
    """Env-steps/s of ``step`` over ``seconds`` (after 10 warm-up steps)."""
    for k in range(10):
        step(k)
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        step(steps)
        steps += 1
    return steps * n / (time.perf_counter() - start)


def gymfleet_side(task, n: int, seconds: float) -> float:
    envs = gymfleet.make_vec(task.id, n)
    envs.reset(seed=0)
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (64, *envs.action_space.shape)).astype(np.float32)
    try:
        return rate(lambda k: envs.step(actions[k % 64]), n, seconds)
    finally:
        envs.close()


def envpool_side(task, n: int, seconds: float) -> float:
    import envpool

    envs = envpool.make_gymnasium(f"{task.name}-v1", num_envs=n, seed=0)
    envs.reset()
    rng = np.random.default_rng(0)
    shape = (n, *envs.action_space.shape[-1:])
    actions = rng.uniform(-1, 1, (64, *shape))
    try:
        return rate(lambda k: envs.step(actions[k % 64]), n, seconds)
    finally:
        envs.close()


def dm_control_side(task, n: int, seconds: float) -> float:
    """dm_control's own envs, ``min(n, 8)`` of them stepped in turn (one process; the
    rate per env step does not depend on how many)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        from dm_control import suite
    m = min(n, 8)
    envs = [suite.load(task.domain, task.task, task_kwargs={"random": k}) for k in range(m)]
    for e in envs:
        e.reset()
    spec = envs[0].action_spec()
    rng = np.random.default_rng(0)
    actions = rng.uniform(spec.minimum, spec.maximum, (64, *spec.shape))

    def step(k: int) -> None:
        for e in envs:
            ts = e.step(actions[k % 64])
            if ts.last():
                e.reset()

    return rate(step, m, seconds)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--envs", type=int, nargs="+", default=[64])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--tasks", nargs="*", default=None, help="names such as CheetahRun")
    args = parser.parse_args()
    try:
        import envpool  # noqa: F401

        have_envpool = True
    except ImportError:
        have_envpool = False
    tasks = [t for t in TASKS.values() if not args.tasks or t.name in args.tasks]
    sides: Dict[str, Callable] = {"gymfleet": gymfleet_side, "dm_control": dm_control_side}
    if have_envpool:
        sides["envpool"] = envpool_side
    print(f"| task | envs | gymfleet | EnvPool | dm_control | gymfleet/EnvPool | gymfleet/dm_control |")
    print("|---|---|---|---|---|---|---|")
    for task in tasks:
        for n in args.envs:
            rates: Dict[str, List[float]] = {s: [] for s in sides}
            for _ in range(args.rounds):
                for name, side in sides.items():
                    try:
                        rates[name].append(side(task, n, args.seconds))
                    except Exception as err:  # EnvPool lacks a task: say so, go on
                        rates[name].append(float("nan"))
                        if name != "envpool":
                            raise
                        last_error = err  # noqa: F841
            med = {s: statistics.median(r) for s, r in rates.items()}
            ep = med.get("envpool", float("nan"))
            print(
                f"| {task.name} | {n} | {med['gymfleet']:,.0f} | {ep:,.0f} | {med['dm_control']:,.0f} "
                f"| {med['gymfleet'] / ep:.2f} | {med['gymfleet'] / med['dm_control']:.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
