#!/usr/bin/env python3
"""Stable-Baselines3's PPO on ``gymfleet/Hopper-v5``: the whole batch is one SB3 ``VecEnv``
(``gymfleet.sb3``), so each of PPO's steps is one ``StepBatch`` on the server.

    pip install ./client/python stable-baselines3 matplotlib
    python client/python/examples/sb3_ppo_hopper.py                 # 100 000 steps, minutes on 2 cores
    python client/python/examples/sb3_ppo_hopper.py --steps 300000 --server host:50051

The hyperparameters are rl-zoo's for Hopper (``hyperparams/ppo.yml``: observation and reward
normalisation, 512 steps × 1 env per update, batch 32, 5 epochs, lr 9.8e-5, γ 0.999, λ 0.99,
a 256-256 ReLU policy with log-σ starting at −2), with ``--envs`` envs and
``n_steps = 512 / envs`` so that an update sees the same amount of experience. It prints the
learning curve (the mean return of the episodes finished in each update) and writes it as a
PNG. Gymnasium's own ``Hopper-v5`` trains the same way with ``--mujoco``.
"""

from __future__ import annotations

import argparse
import pathlib
import time
from typing import List, Tuple

import numpy as np


def make_env(args: argparse.Namespace):
    if args.mujoco:
        from stable_baselines3.common.env_util import make_vec_env

        return make_vec_env("Hopper-v5", n_envs=args.envs, seed=args.seed)
    from gymfleet.sb3 import make_vec_env

    kwargs = {"server": args.server} if args.server else {}
    return make_vec_env("gymfleet/Hopper-v5", n_envs=args.envs, seed=args.seed, **kwargs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=100_000, help="env steps in all")
    parser.add_argument("--envs", type=int, default=8, help="envs in the batch")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--server", default=None, help="a running server (default: in this process)")
    parser.add_argument("--mujoco", action="store_true", help="Gymnasium's MuJoCo Hopper-v5 instead")
    parser.add_argument("--plot", default="target/sb3_ppo_hopper.png", help="where the PNG goes")
    args = parser.parse_args()

    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecNormalize

    torch.set_num_threads(1)
    venv = VecNormalize(make_env(args), gamma=0.999)
    curve: List[Tuple[int, float]] = []

    class Curve(BaseCallback):
        """The mean return of the episodes finished during each rollout."""

        def __init__(self) -> None:
            super().__init__()
            self.returns: List[float] = []

        def _on_step(self) -> bool:
            for info in self.locals["infos"]:
                if "episode" in info:
                    self.returns.append(info["episode"]["r"])
            return True

        def _on_rollout_end(self) -> None:
            if self.returns:
                curve.append((self.num_timesteps, float(np.mean(self.returns))))
                print(f"{self.num_timesteps:>8} steps  return {curve[-1][1]:8.1f}  ({len(self.returns)} episodes)", flush=True)
            self.returns = []

    model = PPO(
        "MlpPolicy",
        venv,
        n_steps=max(1, 512 // args.envs),
        batch_size=32,
        n_epochs=5,
        learning_rate=9.80828e-05,
        gamma=0.999,
        gae_lambda=0.99,
        ent_coef=0.00229519,
        clip_range=0.2,
        max_grad_norm=0.7,
        vf_coef=0.835671,
        policy_kwargs=dict(
            log_std_init=-2, ortho_init=False, activation_fn=torch.nn.ReLU,
            net_arch=dict(pi=[256, 256], vf=[256, 256]),
        ),
        seed=args.seed,
        device="cpu",
        verbose=0,
    )
    start = time.perf_counter()
    model.learn(total_timesteps=args.steps, callback=Curve())
    wall = time.perf_counter() - start
    side = "MuJoCo Hopper-v5" if args.mujoco else "gymfleet/Hopper-v5"
    final = curve[-1][1] if curve else float("nan")
    print(f"{side}: {args.steps} steps in {wall:.0f} s ({args.steps / wall:.0f} steps/s), final return {final:.1f}")
    venv.close()
    write_plot(curve, args.plot, side)


def write_plot(curve: List[Tuple[int, float]], path: str, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = pathlib.Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4))
    if curve:
        ax.plot([s for s, _ in curve], [r for _, r in curve])
    ax.set_xlabel("env steps")
    ax.set_ylabel("mean episode return")
    ax.set_title(f"SB3 PPO on {title}")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print(f"learning curve written to {out}")


if __name__ == "__main__":
    main()
