#!/usr/bin/env python3
"""Two builds of `peer_step` on Gymnasium's ten v5 files, each at its suite id's step (the
file's timestep times its frame skip, in frame-skip substeps), random controls in [-1, 1].

For each file: whether both builds step the same bits (`obs_hash` over 2000 env steps),
instructions per env step under callgrind (the difference of 600 and 200 env steps, so the
set-up cancels; `--callgrind`), and wall-clock microseconds per env step of the two builds
alternated for `--rounds` rounds (medians and fastest rounds).

Setup (not part of CI): `pip install gymnasium` (its files only are read), valgrind for
`--callgrind`, and on each commit

  cargo build --release -p gymfleet-env --example peer_step -p gymfleet-import --example convert
  cp target/release/examples/peer_step /tmp/peer_step_<commit>

  python3 bench/peer/suite_builds.py /tmp/peer_step_before /tmp/peer_step_after --callgrind

`--after-args "--contact-limit 100000"` runs the second build with extra flags (the same
binary twice then compares a setting, e.g. the server's default contact-work limit).
`--before-rigid` gives the first build the converted document without its MuJoCo soft
contacts and limits (every material's `soft_contact` and joint's `soft_limit` removed: the
rigid model), so that one binary twice measures what the soft model costs (issue C):

  python3 bench/peer/suite_builds.py P P --before-rigid --models half_cheetah ant --callgrind
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
CONVERT = os.path.join(ROOT, "target", "release", "examples", "convert")

# file -> (end effector, seconds per env step, substeps, actions)
MODELS = {
    "half_cheetah": ("torso", 0.05, 5, 6),
    "hopper": ("torso", 0.008, 4, 3),
    "walker2d": ("torso", 0.008, 4, 6),
    "ant": ("torso", 0.05, 5, 8),
    "humanoid": ("torso", 0.015, 5, 17),
    "reacher": ("fingertip", 0.02, 2, 2),
    "pusher": ("tips_arm", 0.05, 5, 7),
    "swimmer": ("torso", 0.04, 4, 2),
    "inverted_pendulum": ("pole", 0.04, 2, 1),
    "inverted_double_pendulum": ("pole2", 0.05, 5, 1),
}


EXTRA = {}


def command(exe, document, model, steps):
    end_effector, dt, substeps, actions = MODELS[model]
    return [exe] + EXTRA.get(exe, []) + ["--document", document, "--end-effector", end_effector, "--dt", str(dt),
            "--substeps", str(substeps), "--steps", str(steps), "--repeats", "1",
            "--variant", "random", "--amplitudes", ",".join(["1"] * actions)]


def run(exe, document, model, steps):
    out = subprocess.run(command(exe, document, model, steps), check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def instructions(exe, document, model, steps):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        done = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}"]
                              + command(exe, document, model, steps),
                              capture_output=True, text=True)
        return int(re.search(r"Collected : (\d+)", done.stderr).group(1))


def rigid_copy(document):
    """The document beside `document` without MuJoCo's soft contacts and limits."""
    with open(document) as f:
        doc = json.load(f)
    for material in doc.get("materials", {}).values():
        material.pop("soft_contact", None)
    for joint in doc.get("assembly", {}).get("joints", []):
        joint.pop("soft_limit", None)
    rigid = document[:-len(".json")] + ".rigid.json"
    with open(rigid, "w") as f:
        json.dump(doc, f)
    return rigid


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--models", nargs="*", default=list(MODELS), choices=list(MODELS))
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--callgrind", action="store_true")
    ap.add_argument("--after-args", default="", help="extra flags for the second build")
    ap.add_argument("--before-rigid", action="store_true",
                    help="the first build steps the document without its soft contacts and limits")
    args = ap.parse_args()
    if args.after_args or args.before_rigid:
        # The same binary may be given twice: the second is told apart by a path of its own.
        if args.after == args.before:
            args.after = os.path.join(os.path.dirname(args.before), ".", os.path.basename(args.before))
        EXTRA[args.after] = args.after_args.split()
        EXTRA.setdefault(args.after, [])
    import gymnasium
    assets = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")
    with tempfile.TemporaryDirectory() as tmp:
        for model in args.models:
            document = os.path.join(tmp, model + ".json")
            with open(document, "w") as f:
                subprocess.run([CONVERT, os.path.join(assets, model + ".xml")], check=True,
                               stdout=f, stderr=subprocess.DEVNULL)
            documents = {args.before: document, args.after: document}
            if args.before_rigid:
                documents[args.before] = rigid_copy(document)
            hashes = [run(exe, documents[exe], model, 2000)["obs_hash"]
                      for exe in (args.before, args.after)]
            line = f"{model:25} bits {'same' if hashes[0] == hashes[1] else 'DIFFERENT'}"
            if args.callgrind:
                per_step = [(instructions(exe, documents[exe], model, 600)
                             - instructions(exe, documents[exe], model, 200)) / 400
                            for exe in (args.before, args.after)]
                line += (f"; instructions {per_step[0] / 1e3:.1f} k -> {per_step[1] / 1e3:.1f} k "
                         f"({(per_step[1] / per_step[0] - 1) * 100:+.2f} %)")
            times = {args.before: [], args.after: []}
            for _ in range(args.rounds):
                for exe in (args.before, args.after):
                    times[exe].append(run(exe, documents[exe], model, 2000)["us_per_env_step"])
            b, a = times[args.before], times[args.after]
            line += (f"; us per env step, medians {statistics.median(b):.2f} -> "
                     f"{statistics.median(a):.2f} ({statistics.median(a) / statistics.median(b):.3f}), "
                     f"fastest {min(b):.2f} -> {min(a):.2f} ({min(a) / min(b):.3f})")
            print(line, flush=True)


if __name__ == "__main__":
    main()
