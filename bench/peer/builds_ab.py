#!/usr/bin/env python3
"""Two builds of the load client against EnvPool on one of Gymnasium's MuJoCo files,
alternated in rounds.

Each round runs the `--before` build, the `--after` build (each a `gymfleet-load` binary:
remote StepBatch on a 2-thread embedded server, the file's frame skip as Euler substeps,
ctrl uniform in [-1, 1]) and EnvPool's v5 task of the same file (sync, 2 threads), and
prints the medians and ratios. Setup as in peer_bench.py (mujoco, envpool==1.2.5,
gymnasium):

  cp target/release/gymfleet-load /tmp/load_before   # built at the old commit
  cargo build --release -p gymfleet-load
  /tmp/peer/bin/python bench/peer/builds_ab.py --model reacher \\
      --before /tmp/load_before --after target/release/gymfleet-load
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mujoco_side  # noqa: E402

# file -> (EnvPool task, end effector, seconds per env step, substeps per env step)
MODELS = {
    "reacher": ("Reacher-v5", "fingertip", 0.02, 2),
    "pusher": ("Pusher-v5", "tips_arm", 0.05, 5),
    "humanoid": ("Humanoid-v5", "torso1", 0.015, 5),
    "ant": ("Ant-v5", "torso", 0.05, 5),
    "half_cheetah": ("HalfCheetah-v5", "torso", 0.05, 5),
}


def load_steps_per_s(binary, xml, model, n_envs, seconds):
    _, end_effector, dt, substeps = MODELS[model]
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "report.json")
        subprocess.run([binary, "--model", xml, "--end-effector", end_effector,
                        "--dt", str(dt), "--substeps", str(substeps), "--amplitude", "1",
                        "--n-envs", str(n_envs), "--threads", "2",
                        "--duration", str(seconds), "--warmup", "1", "--quiet",
                        "--json", report], check=True, capture_output=True)
        with open(report) as f:
            return json.load(f)["runs"][0]["env_steps_per_s"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--model", choices=sorted(MODELS), default="reacher")
    ap.add_argument("--before", required=True)
    ap.add_argument("--after", required=True)
    ap.add_argument("--envs", type=int, nargs="*", default=[64, 256])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=3.0)
    args = ap.parse_args()
    import gymnasium
    task, _, dt, substeps = MODELS[args.model]
    xml = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets",
                       args.model + ".xml")
    for n in args.envs:
        runs = {"before": [], "after": [], "envpool": []}
        for _ in range(args.rounds):
            runs["before"].append(load_steps_per_s(args.before, xml, args.model, n,
                                                   args.seconds))
            runs["after"].append(load_steps_per_s(args.after, xml, args.model, n,
                                                  args.seconds))
            runs["envpool"].append(mujoco_side.envpool_steps_per_s(
                task, num_envs=n, num_threads=2, seconds=args.seconds))
        b, a, e = (statistics.median(runs[k]) for k in ("before", "after", "envpool"))
        print(f"{args.model}, {n} envs, 2 threads, {substeps} Euler substeps of "
              f"{dt / substeps:g} s: gymfleet remote StepBatch before {b:9.0f}, after "
              f"{a:9.0f} ({a / b:.2f}x); EnvPool {task} sync {e:9.0f}: ratio before "
              f"{b / e:.2f}, after {a / e:.2f}")
        print("   rounds:", {k: [round(x) for x in v] for k, v in runs.items()})


if __name__ == "__main__":
    main()
