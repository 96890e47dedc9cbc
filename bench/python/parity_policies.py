"""The learning-parity runs' final policies, kept without torch, and played on either side.

``export(model, venv, path)`` writes an SB3 PPO policy's deterministic actor (its MLP's
layers, the action net, the activation) and the ``VecNormalize`` observation statistics to
one ``.npz``; ``Policy.load(path)`` plays it back with numpy alone, as SB3's
``predict(obs, deterministic=True)`` would (normalise and clip the observation, run the actor,
clip the action to the space). ``evaluate(policy, name, side, episodes)`` plays it on
Gymnasium's MuJoCo ``<Name>-v5`` or on ``gymfleet/<Name>-v5``, or on a perturbed MuJoCo:
side ``mujoco*0.8`` is MuJoCo's env with every geom's sliding friction scaled by 0.8 and the
integrator switched (Euler to RK4, RK4 and the implicit ones to Euler), the yardstick a transfer
between two engines is held to (issue C: MuJoCo against a perturbed MuJoCo).

What it answers: a policy trained on MuJoCo that stands or runs on gymfleet as well (and the
other way round) says the dynamics agree where the policy goes; one that falls says where
they part. ``learning_parity.py --cross`` runs it for every exported policy.
"""

from __future__ import annotations

import pathlib
from typing import Any, Dict, List

import numpy as np

ACTIVATIONS = {"ReLU": "relu", "Tanh": "tanh"}


def export(model: Any, venv: Any, path: pathlib.Path) -> None:
    """An SB3 PPO ``model``'s actor and ``venv``'s (a ``VecNormalize``) observation
    statistics, to ``path``."""
    import torch

    layers: Dict[str, np.ndarray] = {}
    activation = None
    k = 0
    for module in model.policy.mlp_extractor.policy_net:
        if isinstance(module, torch.nn.Linear):
            layers[f"w{k}"] = module.weight.detach().cpu().numpy().astype(np.float64)
            layers[f"b{k}"] = module.bias.detach().cpu().numpy().astype(np.float64)
            k += 1
        else:
            activation = ACTIVATIONS[type(module).__name__]
    head = model.policy.action_net
    layers[f"w{k}"] = head.weight.detach().cpu().numpy().astype(np.float64)
    layers[f"b{k}"] = head.bias.detach().cpu().numpy().astype(np.float64)
    rms = venv.obs_rms
    space = model.action_space
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(
        path,
        layers=np.int64(k + 1),
        activation=np.array(activation or "tanh"),
        obs_mean=rms.mean.astype(np.float64),
        obs_var=rms.var.astype(np.float64),
        clip_obs=np.float64(venv.clip_obs),
        epsilon=np.float64(venv.epsilon),
        low=space.low.astype(np.float64),
        high=space.high.astype(np.float64),
        **layers,
    )


class Policy:
    """An exported policy, played with numpy: SB3's deterministic ``predict``."""

    def __init__(self, data: Dict[str, np.ndarray]) -> None:
        n = int(data["layers"])
        self.layers = [(data[f"w{k}"], data[f"b{k}"]) for k in range(n)]
        self.activation = str(data["activation"])
        self.mean, self.var = data["obs_mean"], data["obs_var"]
        self.clip_obs, self.epsilon = float(data["clip_obs"]), float(data["epsilon"])
        self.low, self.high = data["low"], data["high"]

    @classmethod
    def load(cls, path: pathlib.Path) -> "Policy":
        with np.load(path) as data:
            return cls({k: data[k] for k in data.files})

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        x = np.clip((obs - self.mean) / np.sqrt(self.var + self.epsilon), -self.clip_obs, self.clip_obs)
        for k, (w, b) in enumerate(self.layers):
            x = w @ x + b
            if k + 1 < len(self.layers):
                x = np.maximum(x, 0.0) if self.activation == "relu" else np.tanh(x)
        return np.clip(x, self.low, self.high)


#: MuJoCo's integrator enum (mjtIntegrator) and the one a perturbed side switches to.
SWITCHED_INTEGRATOR = {0: 1, 1: 0, 2: 0, 3: 0}


def perturbation(side: str) -> float:
    """The friction scale of a perturbed side (``mujoco*0.8``); 1.0 for a plain one."""
    return float(side.split("*", 1)[1]) if "*" in side else 1.0


def make_env(name: str, side: str) -> Any:
    import gymnasium

    if side.startswith("mujoco"):
        env = gymnasium.make(f"{name}-v5")
        if "*" in side:
            model = env.unwrapped.model
            model.geom_friction[:, 0] *= perturbation(side)
            model.opt.integrator = SWITCHED_INTEGRATOR[int(model.opt.integrator)]
        return env
    import gymfleet  # noqa: F401  (registers the gymfleet/ ids)

    return gymnasium.make(f"gymfleet/{name}-v5")


def evaluate(policy: Policy, name: str, side: str, episodes: int, seed: int = 1000) -> Dict[str, Any]:
    """``episodes`` episodes of ``policy`` on one side, seeds ``seed``, ``seed + 1``, ...:
    each one's return, length and forward progress (the root's x at the end, where the
    info has it)."""
    env = make_env(name, side)
    returns: List[float] = []
    lengths: List[int] = []
    progress: List[float] = []
    try:
        for e in range(episodes):
            obs, info = env.reset(seed=seed + e)
            total, steps, done = 0.0, 0, False
            while not done:
                obs, reward, terminated, truncated, info = env.step(policy(np.asarray(obs, np.float64)))
                total += float(reward)
                steps += 1
                done = terminated or truncated
            returns.append(total)
            lengths.append(steps)
            progress.append(float(info.get("x_position", np.nan)))
    finally:
        env.close()
    return {"returns": returns, "lengths": lengths, "x_end": progress}
