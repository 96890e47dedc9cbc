"""Compare two builds of `peer_step` (e.g. before and after a change to vendored Rapier).

    cp target/release/examples/peer_step /tmp/peer_step_before   # on the old commit
    cargo build --release -p gymfleet-env --example peer_step     # on the new one
    python bench/peer/compare_builds.py /tmp/peer_step_before target/release/examples/peer_step

First, whether both step the same trajectories bit for bit: the `obs_hash` of every model
and workload of the peer benchmark (pendulum, arm2, arm6, chain20 x zero, tilt, sine,
random; 3000 env steps, the random ones driven into the stops). Then, with `--time
MODEL:VARIANT ...`, wall-clock microseconds per env step of the two, alternating for
`--rounds` rounds: the ratio of the medians and of the fastest rounds (this VM is noisy).
Exits 1 if any hash differs. Needs MuJoCo (for the torque amplitudes), like peer_bench.py.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

import mujoco

import mujoco_side
from peer_bench import MODELS, ROOT, TILT_RAD, VARIANTS


def run(exe, model, variant, steps, repeats, amplitudes):
    cmd = [exe, "--document", os.path.join(ROOT, "models", model + ".json"),
           "--end-effector", MODELS[model], "--substeps", "5", "--steps", str(steps),
           "--repeats", str(repeats), "--variant", variant,
           "--tilt-deg", repr(TILT_RAD * 180 / 3.141592653589793),
           "--amplitudes", ",".join(repr(float(a)) for a in amplitudes)]
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def amplitudes_of(model):
    return mujoco_side.torque_amplitudes(mujoco.MjModel.from_xml_path(mujoco_side.model_path(model)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--time", nargs="*", default=[], metavar="MODEL:VARIANT")
    ap.add_argument("--rounds", type=int, default=11)
    args = ap.parse_args()

    differ = 0
    for model in MODELS:
        amplitudes = amplitudes_of(model)
        for variant in VARIANTS:
            hashes = [run(exe, model, variant, 3000, 1, amplitudes)["obs_hash"]
                      for exe in (args.before, args.after)]
            same = hashes[0] == hashes[1]
            differ += not same
            print(f"{model:9} {variant:7} {hashes[0]} {hashes[1]} {'same' if same else 'DIFFERENT'}",
                  flush=True)

    for case in args.time:
        model, variant = case.split(":")
        amplitudes = amplitudes_of(model)
        us = {args.before: [], args.after: []}
        for r in range(args.rounds):
            order = (args.before, args.after) if r % 2 == 0 else (args.after, args.before)
            for exe in order:
                us[exe].append(run(exe, model, variant, 3000, 3, amplitudes)["us_per_env_step"])
        a, b = us[args.before], us[args.after]
        print(f"{model:9} {variant:7} before {statistics.median(a):8.2f} us  after "
              f"{statistics.median(b):8.2f} us  after/before {statistics.median(b) / statistics.median(a):.3f}"
              f"  (fastest rounds {min(b) / min(a):.3f})", flush=True)
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
