#!/usr/bin/env python3
"""In process, one thread: simulated seconds per wall second of gymfleet stepping a
MuJoCo file, against `mujoco.rollout` on the same file and timestep (issue S: the
ceiling a user could reach from C; issue Z1b: files driven by servos and general
actuators, from dm_control and gymnasium-robotics). Not a test.

Both sides step the file's own timestep with random controls, uniform in each actuator's
ctrlrange, held for one env step (the file's frame skip). MuJoCo: `mujoco.rollout.rollout`
of `--batch` trajectories of `--seconds-simulated` each, one `MjData` (one thread), the
file's integrator; its cost includes writing every step's state. gymfleet: the load client
in process on one pool thread (`gymfleet-load --in-process --threads 1 --model FILE --dt
frame_skip*timestep --substeps frame_skip --amplitude 1`): the converted file, semi-implicit
Euler substeps of the file's timestep, an observation per env step, no task. Rounds
alternate the sides; the medians are printed.

    cargo build --release -p gymfleet-load
    pip install mujoco gymnasium
    python bench/peer/rollout_ceiling.py --rounds 3
    pip install --no-deps dm-control gymnasium-robotics     # their files only
    python bench/peer/rollout_ceiling.py --rounds 3 --models adroit_door.xml fetch_push.xml \
        dmc_cheetah.xml dmc_humanoid.xml
"""

from __future__ import annotations

import argparse
import json
import pathlib
import statistics
import subprocess
import tempfile
import time

import gymnasium
import mujoco
import numpy as np
from mujoco import rollout

ROOT = pathlib.Path(__file__).resolve().parents[2]
ASSETS = pathlib.Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
#: file -> Gymnasium's frame skip for it (the v5 envs').
MODELS = {
    "reacher.xml": 2,
    "half_cheetah.xml": 5,
    "hopper.xml": 4,
    "walker2d_v5.xml": 4,
    "ant.xml": 5,
    "humanoid.xml": 5,
    # Issue Z1b, each at its package's control step: Adroit's frame skip 5,
    # gymnasium-robotics' Fetch 20 substeps, dm_control's cheetah 1 and humanoid 5
    # physics steps per control step.
    "adroit_door.xml": 5,
    "fetch_push.xml": 20,
    "dmc_cheetah.xml": 1,
    "dmc_humanoid.xml": 5,
}


def model_path(name: str) -> pathlib.Path:
    """Where a model of `MODELS` is: Gymnasium's files, or dm_control's and
    gymnasium-robotics' (installed with `pip install --no-deps`, files only)."""
    import importlib.util

    def package(name: str) -> pathlib.Path:
        spec = importlib.util.find_spec(name)
        if spec is None or not spec.submodule_search_locations:
            raise SystemExit(f"{name} is not installed: pip install --no-deps {name.replace('_', '-')}")
        return pathlib.Path(list(spec.submodule_search_locations)[0])

    if name.startswith("dmc_"):
        return package("dm_control") / "suite" / name.removeprefix("dmc_")
    robotics = {"adroit_door.xml": "adroit_hand/adroit_door.xml", "fetch_push.xml": "fetch/push.xml"}
    if name in robotics:
        return package("gymnasium_robotics") / "envs" / "assets" / robotics[name]
    return ASSETS / name


def mujoco_rate(xml: pathlib.Path, frame_skip: int, batch: int, seconds: float, seed: int) -> float:
    """Simulated seconds per wall second of `rollout` on one thread."""
    model = mujoco.MjModel.from_xml_path(str(xml))
    data = mujoco.MjData(model)
    nstep = int(round(seconds / model.opt.timestep))
    rng = np.random.default_rng(seed)
    low, high = model.actuator_ctrlrange[:, 0], model.actuator_ctrlrange[:, 1]
    held = rng.uniform(low, high, (batch, nstep // frame_skip + 1, model.nu))
    control = np.repeat(held, frame_skip, axis=1)[:, :nstep]
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state0, spec)
    initial = np.tile(state0, (batch, 1))
    start = time.perf_counter()
    rollout.rollout(model, data, initial, control)
    wall = time.perf_counter() - start
    return batch * nstep * model.opt.timestep / wall


def gymfleet_rate(xml: pathlib.Path, frame_skip: int, batch: int, duration: float) -> float:
    """Simulated seconds per wall second of the load client, in process, one thread."""
    timestep = mujoco.MjModel.from_xml_path(str(xml)).opt.timestep
    dt = frame_skip * timestep
    exe = ROOT / "target" / "release" / "gymfleet-load"
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "load.json"
        subprocess.run(
            [str(exe), "--in-process", "--threads", "1", "--model", str(xml), "--dt", repr(dt),
             "--substeps", str(frame_skip), "--amplitude", "1", "--n-envs", str(batch),
             "--duration", repr(duration), "--warmup", "1", "--json", str(out)],
            check=True, capture_output=True, text=True,
        )
        report = json.loads(out.read_text())
    return env_steps_per_s(report) * dt


def env_steps_per_s(report: dict) -> float:
    """The in-process run's rate in the load client's JSON report."""
    (run,) = [r for r in report["runs"] if r["label"] == "in-process"]
    return float(run["env_steps_per_s"])


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--models", nargs="+", default=list(MODELS), choices=list(MODELS))
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--batch", type=int, default=16, help="trajectories (MuJoCo) and envs (gymfleet)")
    p.add_argument("--seconds-simulated", type=float, default=5.0, help="per MuJoCo trajectory")
    p.add_argument("--duration", type=float, default=3.0, help="gymfleet's timed seconds per round")
    args = p.parse_args()
    for name in args.models:
        xml, skip = model_path(name), MODELS[name]
        ours, theirs = [], []
        for r in range(args.rounds):
            theirs.append(mujoco_rate(xml, skip, args.batch, args.seconds_simulated, r))
            ours.append(gymfleet_rate(xml, skip, args.batch, args.duration))
        a, b = statistics.median(ours), statistics.median(theirs)
        integrator = mujoco.mjtIntegrator(mujoco.MjModel.from_xml_path(str(xml)).opt.integrator).name
        print(f"{name:<17} gymfleet {a:8.0f}  mujoco.rollout {b:8.0f} simulated s per wall s "
              f"(one thread): ratio {a / b:.2f}  (MuJoCo: {integrator})", flush=True)


if __name__ == "__main__":
    main()
