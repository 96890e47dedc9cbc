#!/usr/bin/env python3
"""Balance a cart-pole built from primitives, with Augmented Random Search.

The robot is a document like any other: a grounded rail, a cart on a driven slider
(force actions, N) and a pole on a passive hinge (``"actuated": false``: observed, not
driven). The server's ``upright`` task pays +1 for every step the pole stays within 12° of
vertical and ends the episode with ``fell`` when it does not. Every reset starts the pole
and the cart at random offsets (``reset_noise``, seeded). The policy is linear in the
observation (cart position and velocity, pole angle and angular velocity, scaled); ARS
(Mania et al., 2018) improves it from the returns alone.

    pip install ./client/python
    python client/python/examples/ars_cartpole.py

It prints the mean number of steps the pole stays up (of 500, 2.1 s) before and after.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import gymfleet

CART_POLE = {
    "parts": [
        {"name": "Rail", "primitive": {"type": "cube", "size": {"x": 400, "y": 20, "z": 10}}},
        {"name": "Cart", "primitive": {"type": "cube", "size": {"x": 40, "y": 30, "z": 20}}},
        {"name": "Pole", "primitive": {"type": "cube", "size": {"x": 4, "y": 4, "z": 200}}},
    ],
    "assembly": {
        "instances": [
            {"part": "Rail", "name": "rail", "position": {"x": -200, "y": -10, "z": -10}},
            {"part": "Cart", "name": "cart", "position": {"x": -20, "y": -15, "z": 0}},
            {"part": "Pole", "name": "pole", "position": {"x": -2, "y": -2, "z": 20}},
        ],
        "joints": [
            {"type": "prismatic", "name": "slider", "parent": "rail", "child": "cart",
             "anchor": {"x": 0, "y": 0, "z": 10}, "axis": {"x": 1, "y": 0, "z": 0},
             "min": -150, "max": 150, "max_effort": 0.5},
            {"type": "revolute", "name": "hinge", "parent": "cart", "child": "pole",
             "anchor": {"x": 0, "y": 0, "z": 20}, "axis": {"x": 0, "y": 1, "z": 0},
             "actuated": False},
        ],
    },
}
TASK = {"upright": {"instance": "pole", "max_tilt_deg": 12}}
HORIZON = 500
#: Observation scales: cart mm, pole deg, cart mm/s, pole deg/s.
SCALE = np.array([100.0, 10.0, 100.0, 100.0])


def episode(envs, weights: np.ndarray, seed) -> np.ndarray:
    """Steps survived per env (until the first `fell`), each with its own weights (n, 4)."""
    obs, _ = envs.reset(seed=seed)
    alive = np.ones(envs.num_envs, dtype=bool)
    steps = np.zeros(envs.num_envs)
    for _ in range(HORIZON):
        force = 0.1 * np.einsum("ni,ni->n", weights, obs / SCALE)
        obs, rewards, terminated, _, _ = envs.step(force[:, None])
        alive &= ~terminated
        steps += alive
        if not alive.any():
            break
    return steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--iterations", type=int, default=30)
    parser.add_argument("--directions", type=int, default=16)
    parser.add_argument("--top", type=int, default=8)
    parser.add_argument("--episodes", type=int, default=4, help="per direction and sign")
    parser.add_argument("--step-size", type=float, default=0.5)
    parser.add_argument("--noise", type=float, default=0.5)
    parser.add_argument("--server", default=None, help="host:port; default: embedded")
    args = parser.parse_args()

    half = args.directions * args.episodes
    envs = gymfleet.make_vec(
        CART_POLE, 2 * half, server=args.server, task=TASK, autoreset_mode="Disabled",
        max_steps=HORIZON, reset_noise=2.0,
    )
    assert envs.single_action_space.shape == (1,), "the hinge is passive"
    rng = np.random.default_rng(0)
    theta = np.zeros(4)
    start = time.perf_counter()
    before = episode(envs, np.broadcast_to(theta, (envs.num_envs, 4)), seed=1_000_000)
    print(f"before: the pole stays up {before.mean():6.1f} of {HORIZON} steps on average")
    for it in range(args.iterations):
        deltas = rng.standard_normal((args.directions, 4))
        signs = np.concatenate([np.ones(half), -np.ones(half)])
        per_env = np.tile(np.repeat(deltas, args.episodes, axis=0), (2, 1))
        weights = theta + args.noise * signs[:, None] * per_env
        seeds = [it * half + (i % half) for i in range(2 * half)]
        returns = episode(envs, weights, seeds)
        r = returns.reshape(2, args.directions, args.episodes).mean(axis=2)
        order = np.argsort(-np.maximum(r[0], r[1]))[: args.top]
        sigma = np.concatenate([r[0, order], r[1, order]]).std() + 1e-8
        theta += args.step_size / (args.top * sigma) * (
            (r[0, order] - r[1, order])[:, None] * deltas[order]
        ).sum(axis=0)
        if it % 5 == 4 or it == args.iterations - 1:
            print(f"iteration {it + 1:3d}: {returns.mean():6.1f} steps up (perturbed policies)")
    after = episode(envs, np.broadcast_to(theta, (envs.num_envs, 4)), seed=2_000_000)
    full = float(np.mean(after >= HORIZON))
    print(f"after:  the pole stays up {after.mean():6.1f} of {HORIZON} steps on average; "
          f"{full:.0%} of {envs.num_envs} episodes balance to the end")
    print(f"{args.iterations} iterations, {time.perf_counter() - start:.1f} s")
    envs.close()


if __name__ == "__main__":
    main()
