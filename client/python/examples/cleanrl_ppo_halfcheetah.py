#!/usr/bin/env python3
"""A CleanRL-style single-file PPO (after CleanRL's ``ppo_continuous_action.py``) on
``gymfleet/HalfCheetah-v5``, with the batch made by ``gymfleet.make_vec``: one
``StepBatch`` per vector step, gymnasium's own vector wrappers for statistics and
normalisation.

    pip install ./client/python torch matplotlib
    python client/python/examples/cleanrl_ppo_halfcheetah.py            # 100 000 steps, minutes on 2 cores
    python client/python/examples/cleanrl_ppo_halfcheetah.py --env-id HalfCheetah-v5   # MuJoCo's
    python client/python/examples/cleanrl_ppo_halfcheetah.py --server 127.0.0.1:50051 --batch-size 4

``--server`` trains on a remote server (or a fleet: a comma-separated list).
``--batch-size M`` (< ``--envs``) collects with EnvPool's asynchronous loop: ``recv``
takes the M envs that finished, the policy acts on them, ``send`` sends them back while
the other envs step. The wrappers' work (observation and reward normalisation, clipping,
episode returns) is then done per received env, as gymnasium's vector wrappers do it per
step (their running statistics see M envs at a time instead of all). Over 8 seeds on a
remote server, the asynchronous loop's mean curve lies inside the synchronous seeds' band
(bench/journal/2026-12-07-benchmarks-notebook.md, "Asynchronous stepping from Python"; `bench/python/cleanrl_async.py`).

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


def make_envs(env_id: str, n: int, gamma: float, server: "str | None" = None) -> gym.vector.VectorEnv:
    if env_id.startswith("gymfleet/"):
        envs = gymfleet.make_vec(env_id, n, server=server)
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


class AsyncRollout:
    """EnvPool's asynchronous loop over ``envs`` (``batch_size`` M < N), with the sync
    path's wrappers done per received env: observation normalisation and clipping, reward
    normalisation (a discounted return per env) and clipping, episode returns. Envs go
    out in groups of M and come back in the same groups, so each group has taken the same
    number of steps of a rollout."""

    def __init__(self, envs, gamma: float) -> None:
        from gymnasium.wrappers.utils import RunningMeanStd

        self.envs, self.gamma = envs, gamma
        n, dim = envs.num_envs, envs.single_observation_space.shape[0]
        self.low, self.high = envs.single_action_space.low, envs.single_action_space.high
        self.obs_rms, self.ret_rms = RunningMeanStd(shape=(dim,)), RunningMeanStd(shape=())
        self.acc = np.zeros(n)  # the discounted return NormalizeReward keeps per env
        self.episode = np.zeros(n)  # the raw return of each env's current episode
        self.autoreset = np.zeros(n, dtype=bool)
        self.next_obs = np.zeros((n, dim), dtype=np.float32)
        self.next_done = np.zeros(n, dtype=np.float32)
        self.waiting: List[np.ndarray] = []  # groups received and not sent again
        envs.async_reset()
        for _ in range(n // envs.batch_size):
            obs, _, _, _, info = envs.recv()
            self.next_obs[info["env_id"]] = self._normalize(obs)
            self.waiting.append(info["env_id"])

    def _normalize(self, obs: np.ndarray) -> np.ndarray:
        self.obs_rms.update(obs)
        return np.clip((obs - self.obs_rms.mean) / np.sqrt(self.obs_rms.var + 1e-8), -10, 10)

    def collect(self, agent, bufs, num_steps: int) -> List[float]:
        """Fills ``bufs`` (observations, actions, log-probabilities, rewards, dones,
        values: ``num_steps × N``) as the sync loop does; returns the finished episodes'
        returns."""
        import torch

        obs_buf, act_buf, logp_buf, rew_buf, done_buf, val_buf = bufs
        count, returns = np.zeros(self.envs.num_envs, dtype=int), []

        def act(ids: np.ndarray) -> None:
            t, ix = count[ids[0]], torch.as_tensor(ids.astype(np.int64))
            x = torch.tensor(self.next_obs[ids], dtype=torch.float32)
            with torch.no_grad():
                action, logp, _, value = agent.act(x)
            obs_buf[t, ix], done_buf[t, ix] = x, torch.tensor(self.next_done[ids])
            act_buf[t, ix], logp_buf[t, ix], val_buf[t, ix] = action, logp, value.flatten()
            self.envs.send(np.clip(action.numpy(), self.low, self.high), ids)
            count[ids] += 1

        groups, self.waiting = self.waiting, []
        for ids in groups:
            act(ids)
        in_flight = len(groups)
        while in_flight:
            obs, reward, term, trunc, info = self.envs.recv()
            in_flight -= 1
            ids = info["env_id"]
            self.episode[ids] += reward
            ended = np.logical_or(term, trunc)
            returns.extend(self.episode[ids][ended].tolist())
            self.episode[ids[ended]] = 0.0
            # NormalizeReward's discounted return, which skips an env's autoreset step.
            active, acc = ~self.autoreset[ids], self.acc[ids]
            acc[active] = acc[active] * self.gamma * (1.0 - term[active]) + reward[active]
            self.acc[ids] = acc
            if active.any():
                self.ret_rms.update(acc[active])
            scaled = np.clip(reward / np.sqrt(self.ret_rms.var + 1e-8), -10, 10)
            scaled = np.where(self.autoreset[ids], 0.0, scaled)
            self.autoreset[ids] = ended
            rew_buf[count[ids[0]] - 1, torch.as_tensor(ids.astype(np.int64))] = torch.tensor(scaled, dtype=torch.float32)
            self.next_obs[ids] = self._normalize(obs)
            self.next_done[ids] = ended
            if count[ids[0]] < num_steps:
                act(ids)
                in_flight += 1
            else:
                self.waiting.append(ids)
        return returns


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--env-id", default="gymfleet/HalfCheetah-v5")
    p.add_argument("--steps", type=int, default=100_000)
    p.add_argument("--envs", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--plot", default="target/cleanrl_ppo_halfcheetah.png")
    p.add_argument("--server", default=None, help="a remote server (or a fleet); default: embedded")
    p.add_argument("--batch-size", type=int, default=None,
                   help="recv this many envs at a time (EnvPool's async loop); default: --envs (sync)")
    p.add_argument("--curve", default=None, help="also write the curve as JSON here")
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

    asynchronous = args.batch_size is not None and args.batch_size < args.envs
    if asynchronous:
        if args.envs % args.batch_size:
            p.error("--batch-size must divide --envs")
        envs = gymfleet.make_vec(args.env_id, args.envs, server=args.server, batch_size=args.batch_size)
    else:
        envs = make_envs(args.env_id, args.envs, gamma, args.server)
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
    if asynchronous:
        envs.reset(seed=args.seed)
        rollout = AsyncRollout(envs, gamma)
    else:
        obs, _ = envs.reset(seed=args.seed)
        next_obs = torch.tensor(obs, dtype=torch.float32)
        next_done = torch.zeros(args.envs)
    # Gymnasium's vector envs reset a finished env on the next step (NEXT_STEP): that
    # step's reward and observation belong to no episode and are masked out of learning.
    autoreset = np.zeros(args.envs, dtype=bool)
    for update in range(updates):
        optimizer.param_groups[0]["lr"] = lr * (1.0 - update / updates)
        returns: List[float] = []
        if asynchronous:
            bufs = (obs_buf, act_buf, logp_buf, rew_buf, done_buf, val_buf)
            returns = rollout.collect(agent, bufs, num_steps)
            step += num_steps * args.envs
            next_obs = torch.tensor(rollout.next_obs, dtype=torch.float32)
            next_done = torch.tensor(rollout.next_done)
        for t in range(0 if asynchronous else num_steps):
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
    if args.curve:
        import json

        pathlib.Path(args.curve).write_text(json.dumps({"args": vars(args), "wall_s": wall, "curve": curve}))


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
