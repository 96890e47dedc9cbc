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

Not a test: torch never runs in CI. The final return of a run is the mean undiscounted return
of its last 10 finished episodes (SB3's ``Monitor`` on MuJoCo's side, the adapter's own
``episode`` info on gymfleet's). Runs go one at a time with torch on one thread.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import statistics
import time
from typing import Any, Dict, List, Tuple

import numpy as np

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


def run(name: str, side: str, seed: int, steps: int) -> Dict[str, Any]:
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
    if side == "mujoco":
        venv = make_vec_env(f"{name}-v5", n_envs=1, seed=seed)
    else:
        from gymfleet.sb3 import make_vec_env as gymfleet_vec_env

        venv = gymfleet_vec_env(f"gymfleet/{name}-v5", n_envs=1, seed=seed)
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
    venv.close()
    return {
        "name": name, "side": side, "seed": seed, "steps": steps, "wall_s": round(wall, 1),
        "episodes": episodes, **finals(episodes, steps),
    }


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
    for ax, name in zip(axes[0], names):
        for side, colour in (("mujoco", "tab:blue"), ("gymfleet", "tab:orange")):
            runs = [curve(r["episodes"], grid) for r in results if r["name"] == name and r["side"] == side]
            if not runs:
                continue
            runs = np.array(runs)
            mean = np.nanmean(runs, 0)
            ax.plot(grid, mean, color=colour, label=f"{side} ({len(runs)} seeds)")
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


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--names", nargs="+", default=list(ZOO), choices=list(ZOO))
    p.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    p.add_argument("--steps", type=int, default=300_000)
    p.add_argument("--sides", nargs="+", default=["mujoco", "gymfleet"], choices=["mujoco", "gymfleet"])
    p.add_argument("--out", default="target/learning_parity")
    p.add_argument("--report", action="store_true",
                   help="run nothing: report the runs already in OUT/runs.json")
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # Runs are kept as they finish; a run already in runs.json (same env, side, seed and
    # steps) is not repeated, so an interrupted benchmark resumes.
    saved = out / "runs.json"
    results: List[Dict[str, Any]] = json.loads(saved.read_text()) if saved.exists() else []
    for name in args.names:
        for seed in args.seeds:
            for side in args.sides:
                key = (name, side, seed, args.steps)
                done = [r for r in results if (r["name"], r["side"], r["seed"], r["steps"]) == key]
                if not done and args.report:
                    continue
                r = done[0] if done else run(name, side, seed, args.steps)
                r.update(finals([tuple(e) for e in r["episodes"]], args.steps))
                if not done:
                    results.append(r)
                    saved.write_text(json.dumps(results))
                print(f"{name:<24} {side:<9} seed {seed}: final return {r['final_return']:9.1f} "
                      f"(last sixth {r['late_return']:9.1f}), {r['wall_s']:7.1f} s, "
                      f"{len(r['episodes'])} episodes", flush=True)
    results = [r for r in results if r["name"] in args.names and r["steps"] == args.steps
               and r["side"] in args.sides and r["seed"] in args.seeds]
    print("\n| env | side | seeds | last 10 episodes (mean ± sd over seeds) | min .. max | "
          "last sixth of the run (mean ± sd) | wall s (mean) |")
    print("|---|---|---|---|---|---|---|")
    for name in args.names:
        for side in args.sides:
            mine = [r for r in results if r["name"] == name and r["side"] == side]
            if not mine:
                continue
            last = [r["final_return"] for r in mine]
            late = [r["late_return"] for r in mine]
            sd = lambda xs: statistics.stdev(xs) if len(xs) > 1 else 0.0  # noqa: E731
            print(f"| {name} | {side} | {len(mine)} | {statistics.mean(last):.1f} ± {sd(last):.1f} | "
                  f"{min(last):.1f} .. {max(last):.1f} | {statistics.mean(late):.1f} ± {sd(late):.1f} | "
                  f"{statistics.mean(r['wall_s'] for r in mine):.0f} |")
    plot(results, args.names, args.steps, out / "learning_parity.png")


if __name__ == "__main__":
    main()
