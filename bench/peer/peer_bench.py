#!/usr/bin/env python3
"""gymfleet vs MuJoCo (and EnvPool), measured in one run on one machine.

Per env step, single thread: for each model (pendulum, arm2, arm6, chain20) and each
workload variant, the script alternates gymfleet runs (`cargo run --release -p
gymfleet-env --example peer_step`) and MuJoCo runs (`mujoco_side.py`, the equivalent
MJCF models in bench/peer/models, checked by check_models.py) `--rounds` times and prints
the median of each side and their ratio. MuJoCo runs at gymfleet's defaults: timestep
dt/substeps, Euler, `substeps` mj_step calls per env step, timed as one
`mj_step(m, d, nstep=substeps)` call per env step (the binding's per-call overhead is
then paid once per env step, as gymfleet's is).

Throughput (`--throughput`): gymfleet's remote StepBatch of 256 arm2 envs on a 2-thread
server (the load client, `gymfleet-load`) against EnvPool's Reacher-v5 (sync, 64 envs,
2 threads). The two advance different simulated time per env step (printed beside them).

Setup (not part of CI; PyPI only):
  python3 -m venv /tmp/peer && /tmp/peer/bin/pip install mujoco envpool==1.2.5 numpy
  /tmp/peer/bin/python bench/peer/peer_bench.py            # per-step table
  /tmp/peer/bin/python bench/peer/peer_bench.py --throughput
  /tmp/peer/bin/python bench/peer/peer_bench.py --reacher   # the same model on both sides
  /tmp/peer/bin/python bench/peer/peer_bench.py --locomotion   # HalfCheetah and Ant, same files
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

import mujoco

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import mujoco_side  # noqa: E402

# model -> the instance observed as end effector (it does not change the cost)
MODELS = {"pendulum": "arm", "arm2": "forearm", "arm6": "tool", "chain20": "link20"}
VARIANTS = ["zero", "tilt", "sine", "random"]
TILT_RAD = 0.01


def build():
    for args in (["--example", "peer_step", "-p", "gymfleet-env"],
                 ["-p", "gymfleet-load"]):
        subprocess.run(["cargo", "build", "--release", "-q", *args], cwd=ROOT, check=True)


def gymfleet_us(model, variant, substeps, steps, repeats, amplitudes):
    exe = os.path.join(ROOT, "target", "release", "examples", "peer_step")
    cmd = [exe, "--document", os.path.join(ROOT, "models", model + ".json"),
           "--end-effector", MODELS[model], "--substeps", str(substeps),
           "--steps", str(steps), "--repeats", str(repeats), "--variant", variant,
           "--tilt-deg", repr(TILT_RAD * 180 / 3.141592653589793),
           "--amplitudes", ",".join(repr(float(a)) for a in amplitudes)]
    out = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    return out["us_per_env_step"], out["diverged"]


def mujoco_us(model, variant, substeps, steps, repeats):
    torque = {"zero": "zero", "tilt": "zero", "sine": "sine", "random": "random"}[variant]
    return mujoco_side.mujoco_us_per_env_step(
        mujoco_side.model_path(model), substeps=substeps, steps=steps, repeats=repeats,
        torque=torque, nstep=True, init_tilt=TILT_RAD if variant == "tilt" else 0.0)


def per_step(args):
    print(f"mujoco {mujoco.__version__}; dt 1/240 s, {args.substeps} substeps; "
          f"median of {args.rounds} alternating rounds x {args.repeats} repeats x {args.steps} env steps; "
          f"'min ratio': of each side's fastest round (the least disturbed, on a noisy machine)")
    print(f"{'model':9} {'DOF':>3} {'variant':7} {'gymfleet us':>12} {'mujoco us':>10} {'ratio':>6} "
          f"{'min ratio':>9}")
    summary = {}
    for model in args.models:
        m = mujoco.MjModel.from_xml_path(mujoco_side.model_path(model))
        amplitudes = mujoco_side.torque_amplitudes(m)
        for variant in args.variants:
            ours, theirs, diverged = [], [], 0
            for _ in range(args.rounds):
                us, d = gymfleet_us(model, variant, args.substeps, args.steps, args.repeats, amplitudes)
                ours.append(us)
                diverged += d
                theirs.append(mujoco_us(model, variant, args.substeps, args.steps, args.repeats))
            a, b = statistics.median(ours), statistics.median(theirs)
            fastest = min(ours) / min(theirs)
            summary[(model, variant)] = (m.nv, a, b, fastest)
            note = f"  ({diverged} diverged)" if diverged else ""
            print(f"{model:9} {m.nv:>3} {variant:7} {a:12.2f} {b:10.2f} {a / b:6.2f} {fastest:9.2f}{note}",
                  flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump([dict(model=k[0], variant=k[1], dof=v[0], gymfleet_us=v[1], mujoco_us=v[2],
                            ratio=v[1] / v[2], fastest_round_ratio=v[3])
                       for k, v in summary.items()], f, indent=1)


def throughput(args):
    load = os.path.join(ROOT, "target", "release", "gymfleet-load")
    ours, theirs = [], []
    report = os.path.join(tempfile.mkdtemp(), "load.json")
    for _ in range(args.rounds):
        subprocess.run([load, "--model", "arm2", "--n-envs", "256", "--threads", "2",
                        "--duration", str(args.seconds), "--warmup", "1", "--quiet",
                        "--json", report], check=True, capture_output=True)
        with open(report) as f:
            ours.append(json.load(f)["runs"][0]["env_steps_per_s"])
        theirs.append(mujoco_side.envpool_reacher_steps_per_s(num_envs=64, num_threads=2,
                                                              seconds=args.seconds))
    a, b = statistics.median(ours), statistics.median(theirs)
    print(f"gymfleet remote StepBatch, 256 arm2 envs, 2 threads: {a:10.0f} env-steps/s "
          f"(1/240 s = 4.17 ms simulated per env step, {args.substeps} Euler substeps)")
    print(f"EnvPool Reacher-v5 sync, 64 envs, 2 threads:        {b:10.0f} env-steps/s "
          f"(0.02 s simulated per env step: 2 RK4 steps of 0.01 s)")
    print(f"ratio (env-steps/s): {a / b:.2f}; simulated seconds per second: "
          f"{a / 240:.0f} vs {b * 0.02:.0f} ({a / 240 / (b * 0.02):.2f})")


def same_model_rounds(args, model_args, task, n_envs):
    """Medians over `args.rounds` alternating rounds: gymfleet's remote StepBatch (the load
    client on a 2-thread embedded server, `model_args` naming the model and its step) and
    EnvPool's `task` (sync, 2 threads), both with `n_envs` envs; env-steps/s each."""
    load = os.path.join(ROOT, "target", "release", "gymfleet-load")
    report = os.path.join(tempfile.mkdtemp(), "load.json")
    ours, theirs = [], []
    for _ in range(args.rounds):
        subprocess.run([load, *model_args, "--n-envs", str(n_envs), "--threads", "2",
                        "--duration", str(args.seconds), "--warmup", "1", "--quiet",
                        "--json", report], check=True, capture_output=True)
        with open(report) as f:
            ours.append(json.load(f)["runs"][0]["env_steps_per_s"])
        theirs.append(mujoco_side.envpool_steps_per_s(
            task, num_envs=n_envs, num_threads=2, seconds=args.seconds))
    return statistics.median(ours), statistics.median(theirs)


def reacher(args):
    """Apples to apples: Gymnasium's own reacher.xml on both sides, 0.02 s per env step.

    gymfleet converts the MJCF (the load client's --model) and integrates each env step in
    `substeps` semi-implicit Euler substeps; EnvPool's Reacher-v5 takes 2 RK4 steps of
    0.01 s. Accuracy against MuJoCo over 0.5 s of a torque sequence (reacher_accuracy.py,
    BENCHMARKS.md H1): 1.8 % of the joints' range at 2 substeps, 0.7 % at 5.
    """
    import gymnasium
    xml = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets",
                       "reacher.xml")
    for n_envs in args.reacher_envs:
        for substeps in args.reacher_substeps:
            a, b = same_model_rounds(
                args, ["--model", xml, "--end-effector", "fingertip", "--dt", "0.02",
                       "--substeps", str(substeps), "--amplitude", "1"],
                "Reacher-v5", n_envs)
            print(f"Reacher, {n_envs} envs, 2 threads, 0.02 s per env step: gymfleet remote "
                  f"StepBatch ({substeps} Euler substeps) {a:9.0f} env-steps/s, EnvPool "
                  f"Reacher-v5 sync (2 RK4 steps) {b:9.0f}: ratio {a / b:.2f}; simulated "
                  f"s/s {a * 0.02:.0f} vs {b * 0.02:.0f}")


# Gymnasium's locomotion models, the same file on both sides: (file, EnvPool task, env
# step in s = frame_skip x timestep). Actions on both sides are MuJoCo's ctrl, uniform in
# [-1, 1] (the converted motors keep their gear).
LOCOMOTION = {
    "half_cheetah": ("half_cheetah.xml", "HalfCheetah-v5", 0.05),
    "ant": ("ant.xml", "Ant-v5", 0.05),
}


def locomotion(args):
    """Apples to apples on Gymnasium's locomotion models: the same XML on both sides (the
    server converts it), the same env step (frame_skip 5 x 0.01 s). HalfCheetah's file
    integrates with Euler at 0.01 s, so at `substeps` 5 both sides take the same five
    semi-implicit Euler steps of 0.01 s per env step (its resting pose matches MuJoCo's
    within 0.05 deg per joint: crates/import/tests/mjcf.rs); the Ant's file asks for RK4.
    Random uniform actions on both sides; contacts on both.
    """
    import gymnasium
    assets = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")
    for name in args.locomotion_models:
        xml, task, dt = LOCOMOTION[name]
        for n_envs in args.reacher_envs:
            for substeps in args.locomotion_substeps:
                a, b = same_model_rounds(
                    args, ["--model", os.path.join(assets, xml), "--dt", str(dt),
                           "--substeps", str(substeps), "--amplitude", "1"],
                    task, n_envs)
                print(f"{name}, {n_envs} envs, 2 threads, {dt} s per env step: gymfleet "
                      f"remote StepBatch ({substeps} Euler substeps) {a:9.0f} env-steps/s, "
                      f"EnvPool {task} sync {b:9.0f}: ratio {a / b:.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--substeps", type=int, default=5, help="gymfleet's default")
    ap.add_argument("--steps", type=int, default=4000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--models", nargs="*", default=list(MODELS))
    ap.add_argument("--variants", nargs="*", default=VARIANTS)
    ap.add_argument("--throughput", action="store_true")
    ap.add_argument("--reacher", action="store_true",
                    help="the same Reacher model on both sides (throughput)")
    ap.add_argument("--reacher-envs", type=int, nargs="*", default=[64, 256])
    ap.add_argument("--reacher-substeps", type=int, nargs="*", default=[2, 5])
    ap.add_argument("--locomotion", action="store_true",
                    help="Gymnasium's HalfCheetah and Ant, the same file on both sides")
    ap.add_argument("--locomotion-models", nargs="*", default=list(LOCOMOTION))
    ap.add_argument("--locomotion-substeps", type=int, nargs="*", default=[5])
    ap.add_argument("--seconds", type=float, default=5.0)
    ap.add_argument("--json", help="also write the per-step table here")
    ap.add_argument("--no-build", action="store_true")
    args = ap.parse_args()
    if not args.no_build:
        build()
    if args.locomotion:
        locomotion(args)
    elif args.reacher:
        reacher(args)
    elif args.throughput:
        throughput(args)
    else:
        per_step(args)


if __name__ == "__main__":
    main()
