#!/usr/bin/env python3
"""Teach the seed's 2-DOF arm to reach random targets, with Augmented Random Search.

The server computes everything task-related: each env's target is drawn from a box at
every reset (seeded), appended to the observation, and the reward is minus the distance
(mm) from the forearm's tip to it. The policy is linear in a few features of the target
and outputs the two joints' position targets (deg), held for an episode of 30 steps
(0.125 s). ARS (Mania et al., 2018, V1-t) perturbs the policy's weights in random
directions, runs each perturbation on a batch of envs, and steps along the directions that
brought the tip closer.

    pip install ./client/python
    python client/python/examples/ars_reach.py            # about 30 s on 2 cores

It prints the success rate (final distance within 5 mm) on 1024 fresh targets before and
after training. Only the public package is used; nothing here knows the arm's geometry.
"""

from __future__ import annotations

import argparse
import pathlib
import time

import numpy as np

import gymfleet

ARM2 = pathlib.Path(__file__).resolve().parents[3] / "models" / "arm2.json"
#: Targets in the arm's plane (y = 0), world mm; the tip starts at (0, 0, 60).
BOX = {"min": [15.0, 0.0, 30.0], "max": [30.0, 0.0, 45.0]}
SUCCESS_MM = 5.0
TASK = {
    "reach": {
        "end_effector": "forearm",
        # The forearm's tip: its 3 × 3 × 25 mm box's top centre, in its own frame.
        "point": [1.5, 1.5, 25.0],
        "target_box": BOX,
        "success_radius": SUCCESS_MM,
    }
}
STEPS = 30


def features(targets: np.ndarray) -> np.ndarray:
    """1, then the target's x and z scaled to [-1, 1], and their products."""
    lo, hi = np.array(BOX["min"])[[0, 2]], np.array(BOX["max"])[[0, 2]]
    u = 2.0 * (targets[:, [0, 2]] - lo) / (hi - lo) - 1.0
    x, z = u[:, 0], u[:, 1]
    return np.stack([np.ones_like(x), x, z, x * x, z * z, x * z], axis=1)


def episode(envs, weights: np.ndarray, seed) -> np.ndarray:
    """Runs one episode per env with its own weights (n, 2, 6); the final distances (mm)."""
    obs, _ = envs.reset(seed=seed)
    actions = np.einsum("nij,nj->ni", weights, features(obs[:, -3:]))
    for _ in range(STEPS):
        _, rewards, _, _, _ = envs.step(actions)
    return -rewards


def success_rate(envs, theta: np.ndarray, seed: int, rounds: int) -> float:
    hits = []
    for r in range(rounds):
        d = episode(envs, np.broadcast_to(theta, (envs.num_envs, *theta.shape)), seed + r * envs.num_envs)
        hits.append(d <= SUCCESS_MM)
    return float(np.mean(hits))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--iterations", type=int, default=150)
    parser.add_argument("--directions", type=int, default=16)
    parser.add_argument("--top", type=int, default=8)
    parser.add_argument("--targets", type=int, default=8, help="targets per direction and sign")
    parser.add_argument("--step-size", type=float, default=8.0)
    parser.add_argument("--noise", type=float, default=8.0, help="perturbation at first, deg")
    parser.add_argument("--final-noise", type=float, default=1.0, help="perturbation at the end, deg")
    parser.add_argument("--server", default=None, help="host:port; default: embedded")
    args = parser.parse_args()

    half = args.directions * args.targets
    envs = gymfleet.make_vec(
        ARM2, 2 * half, server=args.server, task=TASK, action_type="position",
        autoreset_mode="Disabled", max_steps=10_000,
    )
    rng = np.random.default_rng(0)
    theta = np.zeros((2, 6))
    start = time.perf_counter()
    before = success_rate(envs, theta, seed=1_000_000, rounds=4)
    print(f"before: {before:6.1%} of {4 * envs.num_envs} targets within {SUCCESS_MM} mm")
    for it in range(args.iterations):
        # Anneal: wide steps while far from the targets, fine ones near the end.
        frac = it / max(1, args.iterations - 1)
        noise = args.noise + (args.final_noise - args.noise) * frac
        step_size = args.step_size * noise / args.noise
        deltas = rng.standard_normal((args.directions, 2, 6))
        # Env i < half runs direction i // targets with +noise, env half + i with -noise,
        # on the same target: both halves are seeded `base + i`.
        signs = np.concatenate([np.ones(half), -np.ones(half)])
        per_env = np.tile(np.repeat(deltas, args.targets, axis=0), (2, 1, 1))
        weights = theta + noise * signs[:, None, None] * per_env
        base = it * half
        seeds = [base + (i % half) for i in range(2 * half)]
        returns = -episode(envs, weights, seeds).astype(np.float64)
        r = returns.reshape(2, args.directions, args.targets).mean(axis=2)
        order = np.argsort(-np.maximum(r[0], r[1]))[: args.top]
        sigma = np.concatenate([r[0, order], r[1, order]]).std() + 1e-8
        step = ((r[0, order] - r[1, order])[:, None, None] * deltas[order]).sum(axis=0)
        theta += step_size / (args.top * sigma) * step
        if it % 25 == 24 or it == args.iterations - 1:
            print(f"iteration {it + 1:3d}: mean final distance {-returns.mean():6.2f} mm "
                  f"(perturbed by {noise:.1f} deg)")
    after = success_rate(envs, theta, seed=2_000_000, rounds=4)
    elapsed = time.perf_counter() - start
    steps = (args.iterations * 2 * half + 8 * envs.num_envs) * STEPS
    print(f"after:  {after:6.1%} of {4 * envs.num_envs} targets within {SUCCESS_MM} mm")
    print(f"{args.iterations} iterations, {steps} env steps, {elapsed:.1f} s")
    envs.close()


if __name__ == "__main__":
    main()
