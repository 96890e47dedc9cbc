#!/usr/bin/env python3
"""Learning parity: does a policy learn on gymfleet's ``gymfleet/<Name>-v5`` as on
Gymnasium's MuJoCo ``<Name>-v5``? The same learner (Stable-Baselines3's PPO) with the same
hyperparameters (rl-baselines3-zoo's ``hyperparams/ppo.yml`` for each env: one env,
observation and reward normalisation), the same seeds and steps on both sides; the mean and
spread of the final returns, the wall time of each run, and the curves as one PNG.

    pip install ./client/python stable-baselines3 matplotlib mujoco
    python bench/python/learning_parity.py                        # 3 envs x 3 seeds x 300 000 steps x 2 sides
    python bench/python/learning_parity.py --names Hopper --seeds 0 --steps 20000   # a smoke run
    python bench/python/learning_parity.py --report      # the table and PNG of the runs so far
    python bench/python/learning_parity.py --jobs 12     # 12 runs at a time, one core each
    python bench/python/learning_parity.py --cross       # each final policy played on both sides and on perturbed MuJoCos

Not a test: torch never runs in CI. The final return of a run is the mean undiscounted return
of its last 10 finished episodes (SB3's ``Monitor`` on MuJoCo's side, the adapter's own
``episode`` info on gymfleet's). Runs go one at a time with torch on one thread, or with
``--jobs N`` N at a time, each process pinned to a core of its own (a machine with at least N
cores). Each run's final policy is exported to ``OUT/policies/<name>-<side>-<seed>.npz``
(``parity_policies.py``: numpy alone plays it back); ``--cross`` plays every exported policy
on both sides, and on MuJoCo with every geom's friction scaled by 0.8 and by 1.2 and its
integrator switched (the reference a transfer between engines is held to), which needs no
torch, and ends with the transfer table: each side's return as a fraction of the home one.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import pathlib
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import parity_policies  # noqa: E402

#: rl-baselines3-zoo's tuned PPO settings (hyperparams/ppo.yml, the -v3 entries), all with
#: `normalize: true` and `n_envs: 1`.
RELU_256 = "relu_256"
ZOO: Dict[str, Dict[str, Any]] = {
    "InvertedDoublePendulum": dict(
        batch_size=512, n_steps=128, gamma=0.98, learning_rate=0.000155454, ent_coef=1.05057e-06,
        clip_range=0.4, n_epochs=10, gae_lambda=0.8, max_grad_norm=0.5, vf_coef=0.695929,
    ),
    "Hopper": dict(
        batch_size=32, n_steps=512, gamma=0.999, learning_rate=9.80828e-05, ent_coef=0.00229519,
        clip_range=0.2, n_epochs=5, gae_lambda=0.99, max_grad_norm=0.7, vf_coef=0.835671,
        policy_kwargs=RELU_256,
    ),
    "HalfCheetah": dict(
        batch_size=64, n_steps=512, gamma=0.98, learning_rate=2.0633e-05, ent_coef=0.000401762,
        clip_range=0.1, n_epochs=20, gae_lambda=0.92, max_grad_norm=0.8, vf_coef=0.58096,
        policy_kwargs=RELU_256,
    ),
}


def run(
    name: str, side: str, seed: int, steps: int, policies: Optional[pathlib.Path] = None,
    xml: Optional[str] = None,
) -> Dict[str, Any]:
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import VecNormalize

    torch.set_num_threads(1)
    params = dict(ZOO[name])
    if params.get("policy_kwargs") == RELU_256:
        params["policy_kwargs"] = dict(
            log_std_init=-2, ortho_init=False, activation_fn=torch.nn.ReLU,
            net_arch=dict(pi=[256, 256], vf=[256, 256]),
        )
    env_kwargs = {"xml_file": xml} if xml else {}
    if side == "mujoco":
        venv = make_vec_env(f"{name}-v5", n_envs=1, seed=seed, env_kwargs=env_kwargs)
    else:
        from gymfleet.sb3 import make_vec_env as gymfleet_vec_env

        venv = gymfleet_vec_env(f"gymfleet/{name}-v5", n_envs=1, seed=seed, **env_kwargs)
    venv = VecNormalize(venv, gamma=params["gamma"])
    episodes: List[Tuple[int, float]] = []

    class Episodes(BaseCallback):
        def _on_step(self) -> bool:
            for info in self.locals["infos"]:
                if "episode" in info:
                    episodes.append((self.num_timesteps, float(info["episode"]["r"])))
            return True

    model = PPO("MlpPolicy", venv, seed=seed, device="cpu", verbose=0, **params)
    start = time.perf_counter()
    model.learn(total_timesteps=steps, callback=Episodes())
    wall = time.perf_counter() - start
    if policies is not None:
        try:
            stem = f"{name}-{side}-{seed}" + (f"-{pathlib.Path(xml).stem}" if xml else "")
            parity_policies.export(model, venv, policies / f"{stem}.npz")
        except Exception as exc:  # the run's returns are worth keeping without its policy
            print(f"{name} {side} seed {seed}: the policy was not exported: {exc!r}", flush=True)
    venv.close()
    return {
        "name": name, "side": side, "seed": seed, "steps": steps, "variant": variant_of(xml),
        "wall_s": round(wall, 1), "episodes": episodes, **finals(episodes, steps),
    }


def variant_of(xml: Optional[str]) -> str:
    """A run's model: "" for the id's own file, else the name of the file given."""
    return pathlib.Path(xml).name if xml else ""


def key_of(r: Dict[str, Any]) -> Tuple[str, str, int, int, str]:
    return (r["name"], r["side"], r["seed"], r["steps"], r.get("variant", ""))


def label(side: str, variant: str) -> str:
    return f"{side}, {variant}" if variant else side


def finals(episodes: List[Tuple[int, float]], steps: int) -> Dict[str, float]:
    """The final return two ways: the mean of the last 10 episodes, and the mean of the
    episodes that ended in the last sixth of the run (less noisy where returns are
    bimodal, as InvertedDoublePendulum's: an episode balances to the end or falls early)."""
    last = [r for _, r in episodes[-10:]]
    late = [r for s, r in episodes if s > steps * 5 / 6]
    return {
        "final_return": float(np.mean(last)) if last else float("nan"),
        "late_return": float(np.mean(late)) if late else float("nan"),
    }


def curve(episodes: List[Tuple[int, float]], grid: np.ndarray) -> np.ndarray:
    """The mean return of the last 10 episodes finished by each grid point."""
    out = np.full(len(grid), np.nan)
    steps = np.array([s for s, _ in episodes])
    returns = np.array([r for _, r in episodes])
    for k, g in enumerate(grid):
        done = returns[steps <= g]
        if done.size:
            out[k] = done[-10:].mean()
    return out


def plot(results: List[Dict[str, Any]], names: List[str], steps: int, path: pathlib.Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grid = np.linspace(steps / 50, steps, 50)
    names = [n for n in names if any(r["name"] == n for r in results)]
    if not names:
        return
    fig, axes = plt.subplots(1, len(names), figsize=(5 * len(names), 4), squeeze=False)
    colours = {"mujoco": "tab:blue", "gymfleet": "tab:orange"}
    for ax, name in zip(axes[0], names):
        others = iter(["tab:green", "tab:red", "tab:purple", "tab:brown"] * 4)
        for side, variant in sorted({(r["side"], r.get("variant", "")) for r in results if r["name"] == name},
                                    key=lambda sv: (sv[1], sv[0] != "mujoco")):
            colour = next(others) if variant else colours[side]
            runs = [curve(r["episodes"], grid) for r in results
                    if r["name"] == name and (r["side"], r.get("variant", "")) == (side, variant)]
            runs = np.array(runs)
            mean = np.nanmean(runs, 0)
            ax.plot(grid, mean, color=colour, label=f"{label(side, variant)} ({len(runs)} seeds)")
            if len(runs) > 1:
                ax.fill_between(grid, np.nanmin(runs, 0), np.nanmax(runs, 0), color=colour, alpha=0.2)
        ax.set_title(f"{name}-v5, SB3 PPO (rl-zoo)")
        ax.set_xlabel("env steps")
        ax.set_ylabel("episode return")
        ax.legend()
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    print(f"curves written to {path}")


def _pin(cores: "multiprocessing.Queue[int]") -> None:
    """A worker's initializer: it takes a core of its own (where the OS lets it)."""
    core = cores.get()
    try:
        os.sched_setaffinity(0, {core})
    except (AttributeError, OSError):
        pass


def _run_task(task: Tuple[str, str, int, int, str, Optional[str]]) -> Dict[str, Any]:
    name, side, seed, steps, policies, xml = task
    return run(name, side, seed, steps, pathlib.Path(policies), xml)


def _cross_task(task: Tuple[str, str, str, int]) -> Dict[str, Any]:
    path, name, side, episodes = task
    policy = parity_policies.Policy.load(pathlib.Path(path))
    return {"policy": pathlib.Path(path).stem, "played_on": side,
            **parity_policies.evaluate(policy, name, side, episodes)}


def in_pool(fn: Any, tasks: List[Any], jobs: int) -> Any:
    """Yields ``fn(task)`` for each task as it finishes: inline with one job, else in
    ``jobs`` spawned processes, each pinned to a core of its own."""
    if jobs <= 1:
        for task in tasks:
            yield fn(task)
        return
    ctx = multiprocessing.get_context("spawn")
    cores = ctx.Queue()
    available = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else list(range(jobs))
    for k in range(jobs):
        cores.put(available[k % len(available)])
    with ProcessPoolExecutor(jobs, mp_context=ctx, initializer=_pin, initargs=(cores,)) as pool:
        futures = {pool.submit(fn, task): task for task in tasks}
        for future in as_completed(futures):
            try:
                yield future.result()
            except Exception as exc:  # one failed run must not lose the others
                print(f"{futures[future][:3]} failed: {exc!r}", flush=True)


#: The perturbed MuJoCo sides every policy is also played on (parity_policies.make_env).
PERTURBED = ("mujoco*0.8", "mujoco*1.2")


def cross(out: pathlib.Path, names: List[str], episodes: int, jobs: int) -> None:
    """Every exported policy of ``names``, played on both sides and on the perturbed MuJoCos."""
    paths = sorted(p for p in (out / "policies").glob("*.npz") if p.stem.split("-")[0] in names)
    sides = ("mujoco", "gymfleet", *PERTURBED)
    tasks = [(str(p), p.stem.split("-")[0], side, episodes) for p in paths for side in sides]
    results = sorted(in_pool(_cross_task, tasks, jobs), key=lambda r: (r["policy"], r["played_on"]))
    (out / "cross.json").write_text(json.dumps(results))
    print(f"\n| policy (env-side-seed) | played on | return (mean ± sd over {episodes} episodes) | length | x at the end |")
    print("|---|---|---|---|---|")
    for r in results:
        print(f"| {r['policy']} | {r['played_on']} | {np.mean(r['returns']):.1f} ± {np.std(r['returns']):.1f} | "
              f"{np.mean(r['lengths']):.0f} | {np.nanmean(r['x_end']):.2f} |")
    transfer_table(results, sides)


def transfer_table(results: List[Dict[str, Any]], sides: Tuple[str, ...]) -> None:
    """Per env and training side: the home return (played where it was trained) and every
    other side's return as a fraction of it, averaged over the seeds' policies."""
    mean = {(r["policy"], r["played_on"]): float(np.mean(r["returns"])) for r in results}
    trained = sorted({(p.split("-")[0], p.split("-")[1]) for p, _ in mean})
    print("\n| env | trained on | policies | home return | " + " | ".join(f"on {s}" for s in sides) + " |")
    print("|---|---|---|---|" + "---|" * len(sides))
    for name, home in trained:
        policies = sorted({p for p, _ in mean if p.split("-")[:2] == [name, home]})
        homes = [mean[(p, home)] for p in policies]
        cells = []
        for side in sides:
            fractions = [mean[(p, side)] / mean[(p, home)] for p in policies if (p, side) in mean]
            returns = [mean[(p, side)] for p in policies if (p, side) in mean]
            cells.append(f"{np.mean(returns):.0f} ({np.mean(fractions):.0%})" if returns else "-")
        print(f"| {name} | {home} | {len(policies)} | {np.mean(homes):.0f} | " + " | ".join(cells) + " |")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--names", nargs="+", default=list(ZOO), choices=list(ZOO))
    p.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    p.add_argument("--steps", type=int, default=300_000)
    p.add_argument("--sides", nargs="+", default=["mujoco", "gymfleet"], choices=["mujoco", "gymfleet"])
    p.add_argument("--out", default="target/learning_parity")
    p.add_argument("--jobs", type=int, default=1, help="runs at a time, each on a core of its own")
    p.add_argument("--xml", help="a model file of one's own for every run (the envs' xml_file); "
                   "give these runs an OUT of their own")
    p.add_argument("--report", action="store_true",
                   help="run nothing: report the runs already in OUT/runs.json")
    p.add_argument("--cross", action="store_true",
                   help="train nothing: play each exported policy on both sides and on MuJoCo with "
                   "friction x0.8 and x1.2 and the integrator switched (numpy, no torch)")
    p.add_argument("--episodes", type=int, default=10, help="episodes per policy and side for --cross")
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.cross:
        cross(out, args.names, args.episodes, args.jobs)
        return
    # Runs are kept as they finish; a run already in runs.json (same env, side, seed and
    # steps) is not repeated, so an interrupted benchmark resumes.
    saved = out / "runs.json"
    results: List[Dict[str, Any]] = json.loads(saved.read_text()) if saved.exists() else []
    # Gymnasium reads a relative xml_file from its own assets folder.
    xml = str(pathlib.Path(args.xml).resolve()) if args.xml else None
    variant = variant_of(xml)
    keys = [(name, side, seed, args.steps, variant)
            for name in args.names for seed in args.seeds for side in args.sides]
    have = {key_of(r) for r in results}
    todo = [] if args.report else [(*key[:4], str(out / "policies"), xml) for key in keys if key not in have]
    for r in in_pool(_run_task, todo, args.jobs):
        results.append(r)
        saved.write_text(json.dumps(results))
        print(f"finished {r['name']} {r['side']} seed {r['seed']}: {r['wall_s']} s", flush=True)
    results = [r for r in results if r["name"] in args.names and r["steps"] == args.steps
               and r["side"] in args.sides and r["seed"] in args.seeds]
    for r in sorted(results, key=key_of):
        r.update(finals([tuple(e) for e in r["episodes"]], args.steps))
        print(f"{r['name']:<24} {label(r['side'], r.get('variant', '')):<9} seed {r['seed']}: "
              f"final return {r['final_return']:9.1f} (last sixth {r['late_return']:9.1f}), "
              f"{r['wall_s']:7.1f} s, {len(r['episodes'])} episodes", flush=True)
    print("\n| env | side | seeds | last 10 episodes (mean ± sd over seeds) | min .. max | "
          "last sixth of the run (mean ± sd) | wall s (mean) |")
    print("|---|---|---|---|---|---|---|")
    for name in args.names:
        groups = sorted({(r["side"], r.get("variant", "")) for r in results if r["name"] == name},
                        key=lambda sv: (sv[1], sv[0] != "mujoco"))
        for side, variant in groups:
            mine = [r for r in results if r["name"] == name and (r["side"], r.get("variant", "")) == (side, variant)]
            last = [r["final_return"] for r in mine]
            late = [r["late_return"] for r in mine]
            sd = lambda xs: statistics.stdev(xs) if len(xs) > 1 else 0.0  # noqa: E731
            print(f"| {name} | {label(side, variant)} | {len(mine)} | {statistics.mean(last):.1f} ± {sd(last):.1f} | "
                  f"{min(last):.1f} .. {max(last):.1f} | {statistics.mean(late):.1f} ± {sd(late):.1f} | "
                  f"{statistics.mean(r['wall_s'] for r in mine):.0f} |")
    plot(results, args.names, args.steps, out / "learning_parity.png")


if __name__ == "__main__":
    main()
