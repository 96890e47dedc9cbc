#!/usr/bin/env python3
"""What a substep buys (issue S): for each locomotion model of Gymnasium's MuJoCo suite,
how far gymfleet's trajectory is from MuJoCo's under the same control sequence over the
first 0.5 s, at the suite's settings (one substep per MuJoCo timestep, ``frame_skip`` per
env step) and with two and four times the substeps (the same env step, shorter substeps).

Both sides start at MuJoCo's pose with no noise and get the same ctrl sequence (a sine per
actuator); MuJoCo integrates with the file's own integrator. Reported per model and
setting: the largest difference of any hinge or slide joint over the 0.5 s (rad or m; for
the Ant also its base position, m), and the root's x at 0.5 s on both sides.

    python bench/python/substep_fidelity.py            # needs gymfleet, gymnasium, mujoco

Not a test: nothing here asserts a distance.
"""

from __future__ import annotations

import argparse
from typing import Dict, List, Tuple

import gymnasium
import numpy as np

import gymfleet
from gymfleet.suite import SUITE
from gymfleet.suite.model import read_model

MODELS = ["HalfCheetah", "Hopper", "Walker2d", "Ant"]


def controls(n: int, dim: int) -> np.ndarray:
    k = np.arange(n)[:, None]
    return (0.5 * np.sin(0.3 * k + np.arange(dim)[None, :])).astype(np.float32)


def mujoco_side(name: str, ctrl: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Joint positions (steps, joints) and root positions (steps, 3) of MuJoCo."""
    env = gymnasium.make(f"{name}-v5", reset_noise_scale=0.0)
    env.reset(seed=0)
    data = env.unwrapped.data
    free = SUITE[f"gymfleet/{name}-v5"].name == "Ant"
    joints, roots = [], []
    for a in ctrl:
        env.step(a)
        q = data.qpos.copy()
        joints.append(q[7:] if free else q)
        roots.append(q[:3] if free else np.array([q[0], 0.0, q[1]]))
    env.close()
    return np.array(joints), np.array(roots)


def gymfleet_side(name: str, ctrl: np.ndarray, factor: int) -> Tuple[np.ndarray, np.ndarray]:
    spec = SUITE[f"gymfleet/{name}-v5"]
    model = read_model(spec.xml_file)
    dt = model.timestep * spec.frame_skip
    env = gymfleet.make(model.text, units="si", dt=dt, substeps=spec.frame_skip * factor)
    env.reset(seed=0)
    dofs = len(model.joints)
    free = model.free is not None
    joints, roots = [], []
    for a in ctrl:
        obs, *_ = env.step(a)
        joints.append(obs[:dofs].astype(np.float64))
        roots.append(obs[2 * dofs : 2 * dofs + 3] if free else np.array([obs[0], 0.0, obs[1]]))
    env.close()
    return np.array(joints), np.array(roots)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", nargs="*", default=MODELS)
    ap.add_argument("--seconds", type=float, default=0.5)
    ap.add_argument("--factors", type=int, nargs="*", default=[1, 2, 4])
    args = ap.parse_args()
    for name in args.models:
        spec = SUITE[f"gymfleet/{name}-v5"]
        model = read_model(spec.xml_file)
        dt = model.timestep * spec.frame_skip
        steps = int(round(args.seconds / dt))
        probe = gymnasium.make(f"{name}-v5")
        ctrl = controls(steps, probe.action_space.shape[0])
        probe.close()
        ref_joints, ref_roots = mujoco_side(name, ctrl)
        rows: List[Dict[str, float]] = []
        for factor in args.factors:
            joints, roots = gymfleet_side(name, ctrl, factor)
            joint_gap = float(np.max(np.abs(joints - ref_joints)))
            root_gap = float(np.max(np.linalg.norm(roots - ref_roots, axis=1)))
            rows.append({"factor": factor, "joint": joint_gap, "root": root_gap, "x": float(roots[-1, 0])})
        line = f"{name}-v5 ({steps} steps of {dt:g} s, MuJoCo x at the end {ref_roots[-1, 0]:+.3f} m):"
        for r in rows:
            line += (f" {spec.frame_skip * r['factor']:>2} substeps: joints {r['joint']:.3f}, root "
                     f"{r['root']:.3f} m, x {r['x']:+.3f} m;")
        print(line.rstrip(";"), flush=True)


if __name__ == "__main__":
    main()
