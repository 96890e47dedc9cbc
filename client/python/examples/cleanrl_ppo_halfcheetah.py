#!/usr/bin/env python3
"""A CleanRL-style single-file PPO (after CleanRL's ``ppo_continuous_action.py``) on
``gymfleet/HalfCheetah-v5``, with the batch made by ``gymfleet.make_vec``: one
``StepBatch`` per vector step, gymnasium's own vector wrappers for statistics and
normalisation.

    pip install ./client/python torch matplotlib
    python client/python/examples/cleanrl_ppo_halfcheetah.py            # 100 000 steps, minutes on 2 cores
    python client/python/examples/cleanrl_ppo_halfcheetah.py --env-id HalfCheetah-v5   # MuJoCo's

CleanRL's defaults otherwise (lr 3e-4 annealed, 2048 steps per update over the envs,
32 minibatches, 10 epochs, γ 0.99, λ 0.95, clip 0.2, 64-64 tanh networks). It prints the
learning curve (mean return of the episodes finished in each update) and writes it as a PNG.
"""

from __future__ import annotations

import argparse
import pathlib
import time
from typing import List, Tuple

import gymnasium as gym
import numpy as np

import gymfleet  # noqa: F401  (registers gymfleet/<Name>-v5)


def make_envs(env_id: str, n: int, gamma: float) -> gym.vector.VectorEnv:
    if env_id.startswith("gymfleet/"):
        envs = gymfleet.make_vec(env_id, n)
    else:
        envs = gym.make_vec(env_id, n, vectorization_mode="sync")
    w = gym.wrappers.vector
    envs = w.RecordEpisodeStatistics(envs)
    envs = w.ClipAction(envs)
    envs = w.NormalizeObservation(envs)
    envs = w.TransformObservation(envs, lambda o: np.clip(o, -10, 10))
    envs = w.NormalizeReward(envs, gamma=gamma)
    envs = w.TransformReward(envs, lambda r: np.clip(r, -10, 10))
    return envs


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--env-id", default="gymfleet/HalfCheetah-v5")
    p.add_argument("--steps", type=int, default=100_000)
    p.add_argument("--envs", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--plot", default="target/cleanrl_ppo_halfcheetah.png")
    args = p.parse_args()

    import torch
    import torch.nn as nn
    from torch.distributions.normal import Normal

    torch.set_num_threads(1)
    torch.manual_seed(args.seed)
    np.random.seed(args.seed)
    gamma, lam, lr, clip, epochs, minibatches = 0.99, 0.95, 3e-4, 0.2, 10, 32
    num_steps = max(1, 2048 // args.envs)
    batch = num_steps * args.envs
    updates = max(1, args.steps // batch)

    envs = make_envs(args.env_id, args.envs, gamma)
    obs_dim = int(np.prod(envs.single_observation_space.shape))
    act_dim = int(np.prod(envs.single_action_space.shape))

    def layer(i: int, o: int, std: float = np.sqrt(2)) -> nn.Linear:
        lin = nn.Linear(i, o)
        nn.init.orthogonal_(lin.weight, std)
        nn.init.constant_(lin.bias, 0.0)
        return lin

    class Agent(nn.Module):
        def __init__(self) -> None:
            super().__init__()
            self.critic = nn.Sequential(layer(obs_dim, 64), nn.Tanh(), layer(64, 64), nn.Tanh(), layer(64, 1, 1.0))
            self.actor_mean = nn.Sequential(
                layer(obs_dim, 64), nn.Tanh(), layer(64, 64), nn.Tanh(), layer(64, act_dim, 0.01)
            )
            self.actor_logstd = nn.Parameter(torch.zeros(1, act_dim))

        def value(self, x: torch.Tensor) -> torch.Tensor:
            return self.critic(x)

        def act(self, x: torch.Tensor, action: "torch.Tensor | None" = None):
            mean = self.actor_mean(x)
            dist = Normal(mean, self.actor_logstd.expand_as(mean).exp())
            if action is None:
                action = dist.sample()
            return action, dist.log_prob(action).sum(1), dist.entropy().sum(1), self.critic(x)

    agent = Agent()
    optimizer = torch.optim.Adam(agent.parameters(), lr=lr, eps=1e-5)
    obs_buf = torch.zeros((num_steps, args.envs, obs_dim))
    act_buf = torch.zeros((num_steps, args.envs, act_dim))
    logp_buf = torch.zeros((num_steps, args.envs))
    rew_buf = torch.zeros((num_steps, args.envs))
    done_buf = torch.zeros((num_steps, args.envs))
    val_buf = torch.zeros((num_steps, args.envs))

    curve: List[Tuple[int, float]] = []
    step = 0
    start = time.perf_counter()
    obs, _ = envs.reset(seed=args.seed)
    next_obs = torch.tensor(obs, dtype=torch.float32)
    next_done = torch.zeros(args.envs)
    # Gymnasium's vector envs reset a finished env on the next step (NEXT_STEP): that
    # step's reward and observation belong to no episode and are masked out of learning.
    autoreset = np.zeros(args.envs, dtype=bool)
    for update in range(updates):
        optimizer.param_groups[0]["lr"] = lr * (1.0 - update / updates)
        returns: List[float] = []
        for t in range(num_steps):
            step += args.envs
            obs_buf[t], done_buf[t] = next_obs, next_done
            with torch.no_grad():
                action, logp, _, value = agent.act(next_obs)
            val_buf[t], act_buf[t], logp_buf[t] = value.flatten(), action, logp
            obs, reward, term, trunc, infos = envs.step(action.numpy())
            reward = np.where(autoreset, 0.0, reward)
            autoreset = np.logical_or(term, trunc)
            rew_buf[t] = torch.tensor(reward, dtype=torch.float32)
            next_obs = torch.tensor(obs, dtype=torch.float32)
            next_done = torch.tensor(autoreset, dtype=torch.float32)
            if "episode" in infos:
                returns.extend(infos["episode"]["r"][infos["_episode"]].tolist())
        if returns:
            curve.append((step, float(np.mean(returns))))
            print(f"{step:>8} steps  return {curve[-1][1]:8.1f}  ({len(returns)} episodes)", flush=True)

        with torch.no_grad():
            next_value = agent.value(next_obs).reshape(1, -1)
            adv = torch.zeros_like(rew_buf)
            last = 0
            for t in reversed(range(num_steps)):
                nonterminal = 1.0 - (next_done if t == num_steps - 1 else done_buf[t + 1])
                nxt = next_value if t == num_steps - 1 else val_buf[t + 1]
                delta = rew_buf[t] + gamma * nxt * nonterminal - val_buf[t]
                adv[t] = last = delta + gamma * lam * nonterminal * last
            ret = adv + val_buf

        b_obs, b_act = obs_buf.reshape(-1, obs_dim), act_buf.reshape(-1, act_dim)
        b_logp, b_adv, b_ret = logp_buf.reshape(-1), adv.reshape(-1), ret.reshape(-1)
        size = max(1, batch // minibatches)
        for _ in range(epochs):
            order = np.random.permutation(batch)
            for s in range(0, batch, size):
                mb = order[s : s + size]
                _, logp, entropy, value = agent.act(b_obs[mb], b_act[mb])
                ratio = (logp - b_logp[mb]).exp()
                a = b_adv[mb]
                a = (a - a.mean()) / (a.std() + 1e-8)
                pg = torch.max(-a * ratio, -a * ratio.clamp(1 - clip, 1 + clip)).mean()
                v = 0.5 * ((value.view(-1) - b_ret[mb]) ** 2).mean()
                loss = pg - 0.0 * entropy.mean() + 0.5 * v
                optimizer.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), 0.5)
                optimizer.step()

    wall = time.perf_counter() - start
    final = curve[-1][1] if curve else float("nan")
    print(f"{args.env_id}: {step} steps in {wall:.0f} s ({step / wall:.0f} steps/s), final return {final:.1f}")
    envs.close()
    write_plot(curve, args.plot, args.env_id)


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
    ax.set_title(f"CleanRL-style PPO on {title}")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print(f"learning curve written to {out}")


if __name__ == "__main__":
    main()
