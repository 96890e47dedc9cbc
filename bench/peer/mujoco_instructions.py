#!/usr/bin/env python3
"""MuJoCo's own cost of a Gymnasium file's env steps, in instructions: `mujoco.rollout` of
`--steps` env steps (the file's frame skip of its own timestep each, random controls uniform in
each actuator's ctrlrange, held for an env step) from the file's initial state, one `MjData`.
Not a test, and it prints nothing: run it under callgrind at two step counts and divide the
difference of the totals by the difference of the counts (Python's start-up and the model's
compilation cancel out). gymfleet's side of the same figure is `peer_step` under callgrind
(bench/journal/2026-12-07-benchmarks-notebook.md, "What dominates").

    for n in 200 600; do
      valgrind --tool=callgrind --callgrind-out-file=cg.mj.$n \\
        python bench/peer/mujoco_instructions.py --model half_cheetah.xml --steps $n
    done
    # (total(600) - total(200)) / 400 = instructions per env step
"""

from __future__ import annotations

import argparse

import mujoco
import numpy as np
from mujoco import rollout

# The files and their frame skips, as the wall-clock comparison has them.
from rollout_ceiling import ASSETS, MODELS as FRAME_SKIP


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--model", default="half_cheetah.xml", choices=list(FRAME_SKIP))
    p.add_argument("--steps", type=int, default=200, help="env steps")
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args()
    model = mujoco.MjModel.from_xml_path(str(ASSETS / args.model))
    data = mujoco.MjData(model)
    skip = FRAME_SKIP[args.model]
    rng = np.random.default_rng(args.seed)
    lo, hi = model.actuator_ctrlrange[:, 0], model.actuator_ctrlrange[:, 1]
    control = np.repeat(rng.uniform(lo, hi, size=(args.steps, model.nu)), skip, axis=0)[None]
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state, spec)
    rollout.rollout(model, data, state[None], control)


if __name__ == "__main__":
    main()
