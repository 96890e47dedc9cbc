#!/usr/bin/env python3
"""How closely gymfleet's Reacher (Gymnasium's own reacher.xml, converted by the server)
follows MuJoCo's, per substep count: the same torque sequence on both for 0.5 s, and per
joint the largest error over time divided by the range MuJoCo's trajectory spans (the
measure of the import issue and of client/python/tests/test_imports.py).

MuJoCo runs its own model (RK4 at 0.01 s; a motor's ctrl is torque / gear 200), stepping
`dt / 0.01` times per env step; gymfleet steps the converted model at `dt` in `substeps`
semi-implicit Euler substeps.

Setup (PyPI only, not part of CI): a venv with mujoco, gymnasium and the package
(`pip install mujoco gymnasium ./client/python`), then
  python bench/peer/reacher_accuracy.py                     # dt 0.02 and 0.01
"""
import argparse
import pathlib

import gymnasium
import mujoco
import numpy as np

import gymfleet

REACHER = pathlib.Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "reacher.xml"


def torque(t):
    return np.array([0.3 * np.sin(4 * t) + 0.1, 0.2 * np.cos(6 * t)])


def mujoco_trajectory(dt, steps):
    model = mujoco.MjModel.from_xml_path(str(REACHER))
    data = mujoco.MjData(model)
    per_step = round(dt / model.opt.timestep)
    out = []
    for k in range(steps):
        data.ctrl[:] = torque(k * dt) / 200.0
        mujoco.mj_step(model, data, nstep=per_step)
        out.append(data.qpos[:2].copy())
    return np.array(out)


def gymfleet_trajectory(dt, substeps, steps):
    env = gymfleet.make(REACHER, end_effector_ids=["fingertip"], dt=dt, substeps=substeps)
    env.reset(seed=0)
    # Actions are MuJoCo's ctrl on both sides: torque / gear 200.
    ctrl = [(torque(k * dt) / 200.0).astype(np.float32) for k in range(steps)]
    out = [np.radians(env.step(ctrl[k])[0][:2]) for k in range(steps)]
    env.close()
    return np.array(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=0.5)
    args = ap.parse_args()
    for dt, counts in ((0.02, (1, 2, 3, 4, 5, 10)), (0.01, (5, 20))):
        steps = round(args.seconds / dt)
        reference = mujoco_trajectory(dt, steps)
        span = reference.max(axis=0) - reference.min(axis=0)
        for substeps in counts:
            ours = gymfleet_trajectory(dt, substeps, steps)
            error = np.abs(ours - reference).max(axis=0) / span
            print(f"dt {dt} s, {substeps:2d} substeps: error / MuJoCo's range: "
                  f"shoulder {100 * error[0]:.2f} %, elbow {100 * error[1]:.2f} %")


if __name__ == "__main__":
    main()
